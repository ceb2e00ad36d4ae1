"""Reading .rrd recordings back in tests."""

from rerun.chunk import RrdReader


def rows_by_frame(path, entity, column):
    """{frame: value of `column` in that frame's row} for one entity."""
    store = RrdReader(path).stream().collect()
    out = {}
    for chunk in store.stream():
        rb = chunk.to_record_batch()
        if rb.schema.metadata and rb.schema.metadata.get(b"rerun:entity_path", b"").decode() != entity:
            continue
        names = rb.schema.names
        if column not in names or "frame" not in names:
            continue
        frames = rb.column(names.index("frame")).to_pylist()
        vals = rb.column(names.index(column)).to_pylist()
        for f, v in zip(frames, vals):
            out[f] = v
    return out


def log_rows(path):
    """{frame: [(level, text), ...]} of /log, in logging order (row ids, TUIDs, sort in it; the
    rows of one frame may span chunks)."""
    rows = []
    for chunk in RrdReader(path).stream().collect().stream():
        rb = chunk.to_record_batch()
        if (rb.schema.metadata or {}).get(b"rerun:entity_path", b"").decode() != "/log":
            continue
        names = rb.schema.names
        rows += zip(rb.column(names.index("rerun.controls.RowId")).to_pylist(), rb.column(names.index("frame")).to_pylist(),
                    rb.column(names.index("TextLog:level")).to_pylist(), rb.column(names.index("TextLog:text")).to_pylist())
    out = {}
    for _, f, level, text in sorted(rows, key=lambda r: r[0]):
        out.setdefault(f, []).append((level[0] if isinstance(level, list) else level,
                                      text[0] if isinstance(text, list) else text))
    return out


def rows_by_frame_static(path, entity, column):
    """The static rows of `column` for `entity` (logged once, without a frame)."""
    out = []
    for chunk in RrdReader(path).stream().collect().stream():
        rb = chunk.to_record_batch()
        if (rb.schema.metadata or {}).get(b"rerun:entity_path", b"").decode() != entity:
            continue
        if column in rb.schema.names and "frame" not in rb.schema.names:
            for v in rb.column(rb.schema.names.index(column)).to_pylist():
                out.append(v[0] if isinstance(v, list) and len(v) == 1 and isinstance(v[0], str) else v)
    return out
