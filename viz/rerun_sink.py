"""rerun sink: one recording per run on a `frame` timeline.

Entities (per-node data is batched into a few entities, never one entity per node):
  /scene/mesh             Mesh3D, exploded (3 vertices per face) to colour faces by status
  /scene/contours/failed  LineStrips3D, one closed strip per node whose contour test failed
  /scene/contours/kernel  Points3D, their kernel points o
  /scene/contours/ray     Arrows3D, their rays r (projected on the plane of the test)
  /scene/cones            Arrows3D, cone axes of the nodes that were not culled
  /scene/bvh              Boxes3D, BVH nodes at the chosen depth
  /stats/...              Scalars: tests, verdicts by reason, collisions, ms per stage (contour
                          tests included), front entries added/removed (front methods)
  /log                    TextLog: per frame, first one sentence per collision (warning level: what
                          collides, and why the smallest node holding it was not culled; the
                          first MAX_COLLISION_LINES), then one per failing node (contour failures
                          first), MAX_LOG_LINES lines in all, then the count of the rest
  /scene/collisions       Points3D (DCD): one per colliding pair, between the two triangles'
                          centroids, labelled with their ids ("12 x 60")
  /scene/contacts/vf, /ee Points3D / LineStrips3D: CCD contacts of the step (drawn at its end),
                          labelled with their ids and earliest time, rounded down ("v6 f62 t>=0.765")
  /front/mesh             Mesh3D (front methods): each face coloured by how many BVTT front
                          entries reach it (SelfCollider.front_load), in a second 3D tab
  /stats/compare/<method>/...  Scalars (record's compare=): per compared method, run untraced on
                          its own collider: contour-test ms, contour tests, elementary tests,
                          query ms ("nc+front" is logged as nc_front)
For CCD recordings frame k shows the step from frame k to frame k + 1.
"""

from __future__ import annotations

import contextlib
import os

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from conecull.datasets import checks
from conecull.viz import layers as L
from conecull.viz.compare import compared_colliders, timed_query
from conecull.viz.explain import collision_sentences, time_floor
from conecull.viz.checks import (check_arithmetic, check_compare, check_depth, check_flag, check_frame_range,
                                 check_method)

MAX_LOG_LINES = 300  # per frame; the count of the rest is logged
MAX_COLLISION_LINES = 100  # of these, the collisions explained (explain.collision_sentences) at most


def compare_path(method: str) -> str:
    """Where record(compare=...) logs a method's series ('+' is not an entity path character)."""
    return f"/stats/compare/{method.replace('+', '_')}"


def blueprint(front: bool = False, compare: tuple = ()) -> rrb.Blueprint:
    views = rrb.Spatial3DView(origin="/scene", name="mesh and culling")
    if front:
        views = rrb.Tabs(views, rrb.Spatial3DView(origin="/front", name="BVTT front on the mesh"))
    # Counts (thousands) and milliseconds (fractions) in separate plots: on one axis the times
    # lie flat on zero.
    plots = [rrb.TimeSeriesView(origin="/stats", contents=["$origin/**", "- /stats/compare/**", "- /stats/ms/**"],
                                name="counts"),
             rrb.TimeSeriesView(origin="/stats/ms", name="ms per stage")]
    if compare:  # the compared methods in their own plots: one for the contour-test time, one for all
        plots += [rrb.TimeSeriesView(origin="/stats/compare", name="contour-test ms per method",
                                     contents=[f"+ {compare_path(m)}/contour_ms" for m in compare]),
                  rrb.TimeSeriesView(origin="/stats/compare", name="methods compared")]
    texts = [rrb.TextLogView(origin="/log", name="why not culled"),
             rrb.TextDocumentView(origin="/legend", name="face colours")]
    if front:
        texts.append(rrb.TextDocumentView(origin="/front/legend", name="front colours"))
    return rrb.Blueprint(
        rrb.Horizontal(
            views,
            rrb.Vertical(rrb.Tabs(*plots), rrb.Tabs(*texts)),
            column_shares=[3, 2],
        ),
        collapse_panels=True,
    )


# Contour verdicts only the baselines give: not plotted (always 0) for the other methods.
BASELINE_REASONS = {"no_kernel_on_search_line": "sct", "edges_may_overlap": "cbc"}


class RerunRecorder:
    """Writes one .rrd; `log_frame` once per frame, then `close`."""

    def __init__(self, path: str, faces: np.ndarray, *, recording_id: str | None = None, bvh_depth: int = 4,
                 app_id: str = "conecull", front: bool = False, compare: tuple = ()):
        self.path = path
        self.rec = rr.RecordingStream(app_id, recording_id=recording_id)
        self.rec.set_log_time_enabled(False)  # deterministic recordings: frame timeline only
        self._writing(lambda: self.rec.save(path))
        self.rec.send_blueprint(blueprint(front, compare))
        self.faces = np.asarray(faces)
        self.bvh_depth = bvh_depth
        legend = "\n".join(f"- **{n}**: rgb{tuple(int(c) for c in L.STATUS_COLORS[i])}" for i, n in enumerate(L.STATUS_NAMES))
        self.rec.log("/legend", rr.TextDocument("Face colours\n" + legend, media_type=rr.MediaType.MARKDOWN), static=True)

    def log_frame(self, frame: int, col, V: np.ndarray, res) -> L.FrameLayers:
        """One DCD frame, or one CCD step (res a CcdResult; V its end pose)."""
        rec = self.rec
        lay = L.compute(col, self.faces, V, res)
        rec.set_time("frame", sequence=frame)
        # Mesh3D has no per-face colours: explode the faces and repeat each colour 3 times.
        rec.log("/scene/mesh", rr.Mesh3D(vertex_positions=V[self.faces].reshape(-1, 3),
                                         vertex_colors=np.repeat(lay.face_colors, 3, axis=0)))
        colors = [L.REASON_COLORS[int(c)] for c in lay.contour_reasons]
        rec.log("/scene/contours/failed", rr.LineStrips3D(lay.contour_strips, colors=colors,
                                                          labels=[L.reason_name(c) for c in lay.contour_reasons]))
        rec.log("/scene/contours/kernel", rr.Points3D(lay.kernels, colors=colors, radii=-3.0))
        rec.log("/scene/contours/ray", rr.Arrows3D(origins=lay.kernels, vectors=lay.rays, colors=colors))
        cone_colors = np.where(lay.cone_bounded[:, None], [[80, 175, 95]], [[235, 195, 60]]).astype(np.uint8)
        rec.log("/scene/cones", rr.Arrows3D(origins=lay.cone_origins, vectors=lay.cone_vectors, colors=cone_colors))
        bvh = col.bvh_arrays()
        sel = np.flatnonzero(bvh["depth"] == self.bvh_depth)
        lo, hi = bvh["box"][sel, 0], bvh["box"][sel, 1]
        rec.log("/scene/bvh", rr.Boxes3D(centers=0.5 * (lo + hi), half_sizes=0.5 * (hi - lo), colors=[[120, 120, 200]],
                                          fill_mode=rr.components.FillMode.MajorWireframe))

        if hasattr(res, "vf"):  # CCD: the contacts of the step
            n_vf = len(res.vf)
            toi = res.toi if res.toi is not None else np.full(n_vf + len(res.ee), np.nan)
            rec.log("/scene/contacts/vf", rr.Points3D(V[res.vf[:, 0]], colors=[[215, 40, 40]], radii=-5.0,
                                                     labels=[f"v{v} f{f} t>={time_floor(t, 3)}" for (v, f), t in
                                                             zip(res.vf.tolist(), toi[:n_vf])]))
            E = col.mesh.edges
            strips = [np.vstack([V[E[a]], V[E[b]][::-1]]) for a, b in res.ee]  # both edges of a pair
            rec.log("/scene/contacts/ee", rr.LineStrips3D(strips, colors=[[215, 40, 40]], radii=-2.0,
                                                         labels=[f"e{a} e{b} t>={time_floor(t, 3)}" for (a, b), t in
                                                                 zip(res.ee.tolist(), toi[n_vf:])]))
        else:  # DCD: which triangles intersect, by id
            c = V[self.faces].mean(axis=1)
            rec.log("/scene/collisions", rr.Points3D(0.5 * (c[res.pairs[:, 0]] + c[res.pairs[:, 1]]).reshape(-1, 3),
                                                     colors=[[215, 40, 40]], radii=-4.0,
                                                     labels=[f"{i} x {j}" for i, j in res.pairs.tolist()]))
        s = res.stats
        rec.log("/stats/tests/cone", rr.Scalars(s["cone_tests"]))
        rec.log("/stats/tests/contour", rr.Scalars(s["contour_tests"]))
        rec.log("/stats/tests/elementary", rr.Scalars(s["elementary_tests"]))
        rec.log("/stats/verdict/culled", rr.Scalars(s["contour_passed"]))
        rec.log("/stats/verdict/cone_too_wide", rr.Scalars(s["cone_tests"] - s["cone_passed"]))
        for name, count in s["contour_failed_by_reason"].items():
            if BASELINE_REASONS.get(name, s.get("method")) == s.get("method"):
                rec.log(f"/stats/verdict/contour_{name}", rr.Scalars(count))
        rec.log("/stats/verdict/ineligible", rr.Scalars(s["contour_ineligible"]))
        rec.log("/stats/collisions", rr.Scalars(s["colliding_pairs"]))
        if hasattr(res, "vf"):
            rec.log("/stats/ccd/vf_contacts", rr.Scalars(s["vf_contacts"]))
            rec.log("/stats/ccd/ee_contacts", rr.Scalars(s["ee_contacts"]))
            rec.log("/stats/ccd/npf_culled", rr.Scalars(s["npf_culled"]))
        for stage in ("refit", "traversal", "elementary", "contour"):
            if f"seconds_{stage}" in s:
                rec.log(f"/stats/ms/{stage}", rr.Scalars(1e3 * s[f"seconds_{stage}"]))
        if s.get("method", "").endswith("+front"):  # BVTT front growth (Alg. 4), frame by frame
            rec.log("/stats/front/entries", rr.Scalars(s["front_entries"]))
            rec.log("/stats/front/added", rr.Scalars(s["front_added"]))
            rec.log("/stats/front/removed", rr.Scalars(s["front_removed"]))
            rec.log("/stats/front/rested", rr.Scalars(s["front_rested"]))  # nodes whose front churned
            load = col.front_load("ccd" if hasattr(res, "vf") else "dcd")
            rec.log("/front/mesh", rr.Mesh3D(vertex_positions=V[self.faces].reshape(-1, 3),
                                             vertex_colors=np.repeat(L.front_colors(load), 3, axis=0)))
            rec.log("/front/legend", rr.TextDocument(
                f"Front entries reaching each face (log scale, grey: none); max {int(load.max()) if len(load) else 0}, "
                f"{s['front_entries']} entries in all", media_type=rr.MediaType.MARKDOWN))

        n_hits = len(res.vf) + len(res.ee) if hasattr(res, "vf") else len(res.pairs)
        hits = collision_sentences(col, res, MAX_COLLISION_LINES)
        for line in hits:
            rec.log("/log", rr.TextLog(line, level=rr.TextLogLevel.WARN))
        if n_hits > len(hits):
            rec.log("/log", rr.TextLog(f"... and {n_hits - len(hits)} more collisions", level=rr.TextLogLevel.WARN))
        room = MAX_LOG_LINES - len(hits)
        for line in lay.sentences[:room]:
            rec.log("/log", rr.TextLog(line, level=rr.TextLogLevel.INFO))
        if len(lay.sentences) > room:
            rec.log("/log", rr.TextLog(f"... and {len(lay.sentences) - room} more failing nodes", level=rr.TextLogLevel.INFO))
        return lay

    def log_compare(self, frame: int, method: str, stats: dict, query_ms: float):
        """One compared method's counters and times at `frame` (an untraced query)."""
        self.rec.set_time("frame", sequence=frame)
        base = compare_path(method)
        self.rec.log(f"{base}/contour_ms", rr.Scalars(1e3 * stats["seconds_contour"]))
        self.rec.log(f"{base}/contour_tests", rr.Scalars(stats["contour_tests"]))
        self.rec.log(f"{base}/elementary_tests", rr.Scalars(stats["elementary_tests"]))
        self.rec.log(f"{base}/query_ms", rr.Scalars(query_ms))

    def close(self):
        try:
            self._writing(self.rec.flush)
        finally:
            self.rec.disconnect()

    def _writing(self, write):
        """rerun reports a failed write (a full disk: --out /dev/full) as a RuntimeError, which the
        CLI would show as a traceback: an OSError naming the file instead."""
        try:
            write()
        except RuntimeError as e:
            raise OSError(f"cannot write the recording '{self.path}' ({e})") from None


def record(path: str, faces, frames, *, method: str = "nc", frame_range=None, recording_id: str | None = None,
           bvh_depth: int = 4, progress=None, ccd: bool = False, arithmetic: str = "exact", compare=None) -> list:
    """Record a sequence; returns the per-frame stats. The BVH is built from frames[0].
    frames: (T, n, 3) positions (array-like); frame_range: indices in [0, T) (default all).
    With ccd=True, frame k shows the CCD step from frame k to k + 1 (the last frame has no step).
    compare: methods (e.g. ["nc", "sct", "cbc"]) also run on every frame, untraced, each on its
    own collider fed the same frames, their contour-test time and counters logged under
    /stats/compare (tracing slows the recorded query, so time the recorded method by listing it
    too); with exact arithmetic their collisions are checked equal to the recorded method's.
    Every argument is checked before any work, each error naming it."""
    import conecull

    ccd = check_flag(ccd, "ccd")
    method = check_method(method, ccd)
    compare = check_compare(compare, ccd)
    arithmetic = check_arithmetic(arithmetic)  # even without ccd: a typo is a typo
    bvh_depth = check_depth(bvh_depth)
    if progress is not None and not callable(progress):
        raise ValueError(f"progress: expected None or a function (done, total), got {progress!r}")
    if recording_id is not None and not isinstance(recording_id, str):
        raise ValueError(f"recording_id: expected None or a string, got {recording_id!r}")
    frames = checks.frames("frames", frames)
    frame_range = check_frame_range(frame_range, len(frames))
    try:
        mesh = conecull.Mesh(faces, n_vertices=frames.shape[1])
    except ValueError as e:
        if not str(e).startswith("n_vertices:"):  # n_vertices is ours, from the frames
            raise
        raise ValueError(f"frames: {frames.shape[1]} vertices per frame, but faces use vertex "
                         f"{int(np.max(faces))}") from None
    if ccd:
        frame_range = [k for k in frame_range if k + 1 < len(frames)]
        if not frame_range:
            raise ValueError(f"frame_range: CCD records the step from each frame k to k + 1, and no frame selected "
                             f"has a next one (the input has frames 0..{len(frames) - 1})")
    checks.writable_file("path", path)  # rerun would say so only after the first query
    col = conecull.SelfCollider(mesh, method=method)
    _query(col.dcd, "frame 0", frames[0])  # node ids depend only on the first pose: stable across commands
    deepest = int(col.bvh_arrays()["depth"].max())
    if bvh_depth > deepest:  # no box would be drawn
        raise ValueError(f"bvh_depth: {bvh_depth} is deeper than this mesh's BVH, whose nodes are at depths 0..{deepest}")
    others = compared_colliders(mesh, compare, frames[0])  # the same BVH as the recorded collider's
    rec = RerunRecorder(path, mesh.faces, recording_id=recording_id, bvh_depth=bvh_depth,
                        front=method.endswith("+front"), compare=compare)
    out = []
    try:
        for i, k in enumerate(frame_range):
            if ccd:
                res = _query(col.ccd, f"step {k} -> {k + 1}", frames[k], frames[k + 1], arithmetic=arithmetic,
                             trace=True, toi=True)
                rec.log_frame(k, col, frames[k + 1], res)
            else:
                res = _query(col.dcd, f"frame {k}", frames[k], trace=True)
                rec.log_frame(k, col, frames[k], res)
            for m, other in others.items():
                r, ms = timed_query(other, frames[k], frames[k + 1] if ccd else None, arithmetic)
                if not ccd or arithmetic == "exact":  # float / conservative answers depend on the candidates
                    same = (np.array_equal(r.vf, res.vf) and np.array_equal(r.ee, res.ee)) if ccd else \
                        np.array_equal(r.pairs, res.pairs)
                    if not same:
                        raise RuntimeError(f"compare: method {m!r} found other collisions than {method!r} at frame "
                                           f"{k}; every method must agree: please report this as a bug")
                rec.log_compare(k, m, r.stats, ms)
            out.append(res.stats)
            if progress:
                progress(i + 1, len(frame_range))
        rec.close()  # the last writes: a full disk shows here
    except BaseException:
        with contextlib.suppress(OSError):
            rec.close()
        # A recording cut short would pass for the whole run; only a regular file is removed (never
        # a device such as /dev/full, which --out may name).
        if os.path.isfile(path):
            with contextlib.suppress(OSError):
                os.remove(path)
        raise
    return out


def _query(run, where: str, *args, **kwargs):
    """A query; the core's complaint about the positions (V, V0, V1) also says which frame."""
    try:
        return run(*args, **kwargs)
    except ValueError as e:
        raise ValueError(f"frames: {where}: {e}") from None
