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
