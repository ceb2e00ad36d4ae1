"""rerun sink: one recording per run on a `frame` timeline.

Entities (per-node data is batched into a few entities, never one entity per node):
  /about                  TextDocument: what was recorded (method, DCD or CCD, arithmetic, input,
                          frames) and how to read the timeline
  /legend                 TextDocument: the face colours in words, and the other layers
  /scene/mesh             Mesh3D, exploded (3 vertices per face) to colour faces by status
  /scene/culled           LineStrips3D, the boundary contour of each culled node (methods with cones)
  /scene/failed_nodes     Boxes3D, the nodes not culled, labelled "node N: reason" as the log
  /scene/contours/failed  LineStrips3D, one closed strip per node whose contour test failed
  /scene/contours/kernel  Points3D, their kernel points o (not for cbc, nor where sct found none)
  /scene/contours/ray     Arrows3D, their rays r (projected on the plane of the test)
  /scene/cones            Arrows3D, the axis of each bounded cone (culled, contour failed, ineligible)
  /scene/bvh              Boxes3D, BVH nodes at the chosen depth
  /stats/...              Scalars, named in words (SERIES_NAMES): tests (box tests for every
                          method), verdicts by reason (methods with cones), collisions or CCD
                          contacts, ms per stage (contour tests included), front entries
                          added/removed (front methods); one plot per kind
  /story                  TextDocument: the same lines as /log, one page per frame (the log view
                          cuts long lines; a page wraps them)
  /log                    TextLog: per frame, first one sentence per collision (warning level: what
                          collides, and why the smallest node holding it was not culled; the
                          first MAX_COLLISION_LINES), then where a front method's front came
                          from, what the culled nodes prove, and one sentence per failing node
                          (contour failures first), MAX_LOG_LINES lines in all, then the count of
                          the rest
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
from conecull.trace import REASONS
from conecull.viz import layers as L
from conecull.viz.compare import compared_colliders, timed_query
from conecull.viz.explain import NO_CONES, collision_sentences, time_floor
from conecull.viz.checks import (check_arithmetic, check_compare, check_depth, check_flag, check_frame_range,
                                 check_method)

MAX_LOG_LINES = 300  # per frame; the count of the rest is logged
MAX_COLLISION_LINES = 100  # of these, the collisions explained (explain.collision_sentences) at most


def compare_path(method: str) -> str:
    """Where record(compare=...) logs a method's series ('+' is not an entity path character)."""
    return f"/stats/compare/{method.replace('+', '_')}"


def blueprint(front: bool = False, compare: tuple = (), cones: bool = True) -> rrb.Blueprint:
    # The cone axes start hidden (an eye toggle in the viewer): at every culled node, long arrows
    # crowd out the mesh.
    views = rrb.Spatial3DView(origin="/scene", name="mesh and culling",
                              overrides={"/scene/cones": rrb.EntityBehavior(visible=False)})
    if front:
        views = rrb.Tabs(views, rrb.Spatial3DView(origin="/front", name="BVTT front on the mesh"))
    # One plot per kind of count: tests run in thousands, verdicts in tens, and on one axis the
    # small ones lie flat on zero (as milliseconds would).
    plots = [rrb.TimeSeriesView(origin="/stats/tests", name="tests")]
    if cones:
        plots.append(rrb.TimeSeriesView(origin="/stats/verdict", name="verdicts"))
    plots.append(rrb.TimeSeriesView(origin="/stats", contents=["+ /stats/collisions", "+ /stats/ccd/**"],
                                    name="collisions"))
    if front:
        plots.append(rrb.TimeSeriesView(origin="/stats/front", name="front"))
    plots.append(rrb.TimeSeriesView(origin="/stats/ms", name="ms per stage"))
    if compare:  # the compared methods in their own plots: one for the contour-test time, one for all
        plots += [rrb.TimeSeriesView(origin="/stats/compare", name="contour-test ms per method",
                                     contents=[f"+ {compare_path(m)}/contour_ms" for m in compare]),
                  rrb.TimeSeriesView(origin="/stats/compare", name="methods compared")]
    texts = [rrb.TextLogView(origin="/log", name="why not culled"),
             rrb.TextDocumentView(origin="/story", name="why not culled (whole lines)"),
             rrb.TextDocumentView(origin="/legend", name="face colours"),
             rrb.TextDocumentView(origin="/about", name="about this recording")]
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


# Contour verdicts only the baselines give: not plotted (always 0) for the other methods. sct's star
# test after its line search gives Alg. 1's reasons too; cbc's edge-pair test gives only its own.
BASELINE_REASONS = {"no_kernel_on_search_line": "sct", "edges_may_overlap": "cbc"}


def plotted_reason(name: str, method: str) -> bool:
    """Whether the contour verdict `name` can occur for `method`, so is plotted."""
    if method == "cbc":
        return name == "edges_may_overlap"
    return BASELINE_REASONS.get(name, method) == method


# Every plotted series' name in words (the plot legends show these, not the entity paths).
SERIES_NAMES = {
    "/stats/tests/box": "box tests (BVTT node pairs)", "/stats/tests/cone": "cone tests",
    "/stats/tests/contour": "contour tests", "/stats/tests/elementary": "elementary tests",
    "/stats/tests/vf": "vertex-face tests", "/stats/tests/ee": "edge-edge tests",
    "/stats/verdict/culled": "culled (contour passed)", "/stats/verdict/cone_too_wide": "cone too wide",
    "/stats/verdict/ineligible": "not eligible for the contour test (non-manifold, not one patch, holes...)",
    "/stats/collisions": "colliding triangle pairs", "/stats/ccd/vf_contacts": "vertex-face contacts",
    "/stats/ccd/ee_contacts": "edge-edge contacts",
    "/stats/ccd/npf_culled": "pairs culled by the non-penetration filter",
    "/stats/front/entries": "front entries", "/stats/front/added": "entries added since the last query",
    "/stats/front/removed": "entries removed since the last query", "/stats/front/rested": "nodes whose front rests",
    "/stats/ms/refit": "refit ms", "/stats/ms/traversal": "traversal ms", "/stats/ms/elementary": "elementary ms",
    "/stats/ms/contour": "contour tests ms (inside the traversal)",
}


# The plotted verdicts in the colours the mesh and boxes use for them.
SERIES_COLORS = {"/stats/verdict/culled": tuple(int(c) for c in L.STATUS_COLORS[L.CULLED]),
                 "/stats/verdict/cone_too_wide": tuple(int(c) for c in L.STATUS_COLORS[L.CONE_FAILED]),
                 "/stats/collisions": tuple(int(c) for c in L.STATUS_COLORS[L.COLLIDING]),
                 **{f"/stats/verdict/contour_{name}": L.REASON_COLORS[code] for code, (name, _) in REASONS.items()}}
MARKER = (20, 20, 20)  # collision points and contact strips: dark, on the red of the colliding faces


def status_legend_markdown(depth: int | None) -> str:
    """The face colours, in words and rgb, and what the 3D view's other layers mean."""
    deepest = "" if depth is None else f", {depth}"
    words = {L.CULLED: f"green: inside a culled node (deep green for a node near the root, paler down to the BVH's "
                       f"deepest level{deepest}): no two of its triangles can collide",
             L.UNTESTED: "grey: not examined by normal cones (aabb methods have none; a mesh of one triangle has "
                         "nothing to test)",
             L.CONE_FAILED: "yellow: the deepest node judged, a leaf or one holding it, could not bound its normal "
                            "cone below 180 degrees (a lone triangle is never tested: nothing to collide with)",
             L.CONTOUR_FAILED: "orange: the deepest node judged failed its contour test (or has no single simple "
                               "contour)",
             L.COLLIDING: "red: colliding"}
    rows = [f"- **{L.STATUS_NAMES[i]}**, {words[i]}; rgb{tuple(int(c) for c in L.STATUS_COLORS[i])}"
            for i in range(len(L.STATUS_NAMES))]
    return "\n".join([
        "### Face colours", "Each face shows the verdict of the deepest BVH node that judged it. The traversal "
        "descends below a failing node until a node is culled, so most faces end up green; where culling "
        "worked only deep in the BVH the green is pale.", *rows, "",
        "### Other layers",
        "- **scene/culled**: the boundary contour of each culled node (dark green): the culled patches.",
        "- **scene/failed_nodes**: the box of each node that was not culled, labelled `node N: reason` as in the "
        f"log: yellow when its cone was too wide and its normals span a hemisphere or more (no cone could pass), "
        f"pale yellow rgb{L.CONE_BOUND_COLOR} when its normals fit in an open hemisphere (only the cone merged from "
        "its children's was too wide; conecull.normal_spread, checked exactly), else the colour of its contour "
        "test's reason.",
        "- **scene/contours/failed**: the boundary contour of each node whose contour test failed, in its reason's "
        "colour, with its kernel point and ray (none for cbc's edge-pair test, nor where sct found no kernel point).",
        "- **scene/cones** (hidden at first: its eye in the blueprint panel shows it): the axis of each node's "
        "cone that was bounded, the direction its contour test projects along: dark green where the node was "
        "culled, else its reason's colour (a cone too wide has no axis).",
        "- **scene/collisions** (DCD): one dark point per colliding pair, labelled (on hover) with the two triangles; "
        "**scene/contacts** (CCD): vertex-face points and edge-edge strips, labelled with a certified lower bound on "
        "the time of contact.",
        "- **scene/bvh**: the BVH boxes at one depth.",
        "", "Contour reasons and their colours: " + ", ".join(
            f"{name} rgb{tuple(c)}" for name, c in L.reason_legend()) + "."])


class RerunRecorder:
    """Writes one .rrd; `log_frame` once per frame, then `close`."""

    def __init__(self, path: str, faces: np.ndarray, *, recording_id: str | None = None, bvh_depth: int = 4,
                 app_id: str = "conecull", front: bool = False, compare: tuple = (), method: str = "nc",
                 about: str = "", deepest: int | None = None, stream: rr.RecordingStream | None = None,
                 layout: bool = True):
        """stream: log to this (connected) stream instead of a new one saved to path; layout: send
        the default blueprint (the screenshots send their own)."""
        self.path = path
        self.rec = stream if stream is not None else rr.RecordingStream(app_id, recording_id=recording_id)
        self.rec.set_log_time_enabled(False)  # deterministic recordings: frame timeline only
        if stream is None:
            self._writing(lambda: self.rec.save(path))
        self.method = method
        self.cones = method not in NO_CONES
        if layout:
            self.rec.send_blueprint(blueprint(front, compare, self.cones))
        self.faces = np.asarray(faces)
        self.bvh_depth = bvh_depth
        self.rec.log("/legend", rr.TextDocument(status_legend_markdown(deepest), media_type=rr.MediaType.MARKDOWN),
                     static=True)
        if about:
            self.rec.log("/about", rr.TextDocument(about, media_type=rr.MediaType.MARKDOWN), static=True)
        self._named = set()

    def _scalar(self, path: str, value, name: str | None = None):
        """One point of a plotted series, its name in words (name, else SERIES_NAMES) set once."""
        if path not in self._named:
            self._named.add(path)
            name = name or SERIES_NAMES.get(path, path.rsplit("/", 1)[-1].replace("_", " "))
            color = SERIES_COLORS.get(path)
            self.rec.log(path, rr.SeriesLines(names=name, colors=[color] if color else None), static=True)
        self.rec.log(path, rr.Scalars(value))

    def log_frame(self, frame: int, col, V: np.ndarray, res, previous: int | None = None) -> L.FrameLayers:
        """One DCD frame, or one CCD step (res a CcdResult; V its end pose). previous: the frame of
        the collider's query before this one (a front method's front comes from it)."""
        rec = self.rec
        ccd = hasattr(res, "vf")
        lay = L.compute(col, self.faces, V, res)
        rec.set_time("frame", sequence=frame)
        # Mesh3D has no per-face colours: explode the faces and repeat each colour 3 times.
        rec.log("/scene/mesh", rr.Mesh3D(vertex_positions=V[self.faces].reshape(-1, 3),
                                         vertex_colors=np.repeat(lay.face_colors, 3, axis=0)))
        if self.cones:  # aabb methods have no cones nor contours: no empty layers for them
            rec.log("/scene/culled", rr.LineStrips3D(lay.culled_strips, colors=[L.CULLED_CONTOUR_COLOR], radii=-1.0,
                                                     labels=[f"node {n}: culled" for n in lay.culled_nodes.tolist()],
                                                     show_labels=False))
            rec.log("/scene/failed_nodes", rr.Boxes3D(mins=lay.box_lo, sizes=lay.box_hi - lay.box_lo,
                                                      colors=lay.node_colors, labels=lay.node_labels, show_labels=False,
                                                      fill_mode=rr.components.FillMode.MajorWireframe))
            colors = [L.REASON_COLORS[int(c)] for c in lay.contour_reasons]
            labels = [L.node_label(n, c) for n, c in zip(lay.contour_nodes.tolist(), lay.contour_reasons.tolist())]
            rec.log("/scene/contours/failed", rr.LineStrips3D(lay.contour_strips, colors=colors, labels=labels))
            if self.method != "cbc":  # its edge-pair test has no kernel point nor ray
                has = np.isfinite(lay.kernels).all(axis=1)
                kcol = np.array(colors, np.uint8).reshape(-1, 3)[has]
                rec.log("/scene/contours/kernel", rr.Points3D(lay.kernels[has], colors=kcol, radii=-3.0))
                rec.log("/scene/contours/ray", rr.Arrows3D(origins=lay.kernels[has], vectors=lay.rays[has], colors=kcol))
            # The axes of the cones that were bounded (a cone too wide has none: the trace's is zero).
            rec.log("/scene/cones", rr.Arrows3D(origins=lay.axis_origins, vectors=lay.axis_vectors,
                                                colors=lay.axis_colors,
                                                labels=[f"node {n}: cone axis" for n in lay.axis_nodes.tolist()],
                                                show_labels=False))
        bvh = col.bvh_arrays()
        sel = np.flatnonzero(bvh["depth"] == self.bvh_depth)
        lo, hi = bvh["box"][sel, 0], bvh["box"][sel, 1]
        rec.log("/scene/bvh", rr.Boxes3D(centers=0.5 * (lo + hi), half_sizes=0.5 * (hi - lo), colors=[[120, 120, 200]],
                                          fill_mode=rr.components.FillMode.MajorWireframe))

        if ccd:  # the contacts of the step
            n_vf = len(res.vf)
            toi = res.toi if res.toi is not None else np.full(n_vf + len(res.ee), np.nan)
            rec.log("/scene/contacts/vf", rr.Points3D(V[res.vf[:, 0]], colors=[MARKER], radii=-5.0, show_labels=False,
                                                     labels=[f"v{v} f{f} t>={time_floor(t, 3)}" for (v, f), t in
                                                             zip(res.vf.tolist(), toi[:n_vf])]))
            E = col.mesh.edges
            strips = [np.vstack([V[E[a]], V[E[b]][::-1]]) for a, b in res.ee]  # both edges of a pair
            rec.log("/scene/contacts/ee", rr.LineStrips3D(strips, colors=[MARKER], radii=-2.0, show_labels=False,
                                                         labels=[f"e{a} e{b} t>={time_floor(t, 3)}" for (a, b), t in
                                                                 zip(res.ee.tolist(), toi[n_vf:])]))
        else:  # DCD: which triangles intersect, by id
            c = V[self.faces].mean(axis=1)
            rec.log("/scene/collisions", rr.Points3D(0.5 * (c[res.pairs[:, 0]] + c[res.pairs[:, 1]]).reshape(-1, 3),
                                                     colors=[MARKER], radii=-4.0, show_labels=False,
                                                     labels=[f"{i} x {j}" for i, j in res.pairs.tolist()]))
        s = res.stats
        self._scalar("/stats/tests/box", s["bv_tests"])
        if self.cones:
            self._scalar("/stats/tests/cone", s["cone_tests"])
            self._scalar("/stats/tests/contour", s["contour_tests"])
            self._scalar("/stats/verdict/culled", s["contour_passed"])
            self._scalar("/stats/verdict/cone_too_wide", s["cone_tests"] - s["cone_passed"])
            for name, count in s["contour_failed_by_reason"].items():
                if plotted_reason(name, self.method):
                    self._scalar(f"/stats/verdict/contour_{name}", count)
            self._scalar("/stats/verdict/ineligible", s["contour_ineligible"])
        if ccd:
            self._scalar("/stats/tests/vf", s["vf_tests"])
            self._scalar("/stats/tests/ee", s["ee_tests"])
            self._scalar("/stats/ccd/vf_contacts", s["vf_contacts"])
            self._scalar("/stats/ccd/ee_contacts", s["ee_contacts"])
            self._scalar("/stats/ccd/npf_culled", s["npf_culled"])
        else:
            self._scalar("/stats/tests/elementary", s["elementary_tests"])
            self._scalar("/stats/collisions", s["colliding_pairs"])
        for stage in ("build", "refit", "traversal", "elementary", "contour"):
            if f"seconds_{stage}" in s:
                self._scalar(f"/stats/ms/{stage}", 1e3 * s[f"seconds_{stage}"])
        front = s.get("method", "").endswith("+front")
        if front:  # BVTT front growth (Alg. 4), frame by frame
            self._scalar("/stats/front/entries", s["front_entries"])
            self._scalar("/stats/front/added", s["front_added"])
            self._scalar("/stats/front/removed", s["front_removed"])
            self._scalar("/stats/front/rested", s["front_rested"])  # nodes whose front churned
            load = col.front_load("ccd" if ccd else "dcd")
            rec.log("/front/mesh", rr.Mesh3D(vertex_positions=V[self.faces].reshape(-1, 3),
                                             vertex_colors=np.repeat(L.front_colors(load), 3, axis=0)))
            rec.log("/front/legend", rr.TextDocument(
                f"Front entries reaching each face (log scale, grey: none); max {int(load.max()) if len(load) else 0}, "
                f"{s['front_entries']} entries in all. Key: " + ", ".join(
                    f"{n} rgb{c}" for n, c in L.front_legend(load)) + ".", media_type=rr.MediaType.MARKDOWN))

        n_hits = len(res.vf) + len(res.ee) if ccd else len(res.pairs)
        hits = collision_sentences(col, res, MAX_COLLISION_LINES)
        story = []  # the log's lines, also as one page per frame: the log view cuts long lines

        def say(line, level=rr.TextLogLevel.INFO):
            rec.log("/log", rr.TextLog(line, level=level))
            story.append(line)

        for line in hits:
            say(line, rr.TextLogLevel.WARN)
        if n_hits > len(hits):
            say(f"... and {n_hits - len(hits)} more collisions", rr.TextLogLevel.WARN)
        if front:
            what = "step" if ccd else "frame"
            since = (f"the previous query ({what} {previous})" if previous is not None and previous != frame else
                     f"the previous query, of this same {what}'s pose" if previous == frame else
                     "no earlier query of this kind: built from the top")
            say(f"front: {s['front_entries']} entries, +{s['front_added']} / -{s['front_removed']} since {since} "
                "(Alg. 4 keeps the front between queries)")
        if not self.cones:
            say(f"method {self.method}: no normal cones, so no node is culled: every pair of overlapping boxes is "
                "descended to its triangles")
        elif lay.culled_summary:
            say(lay.culled_summary)
        elif not lay.sentences and col.mesh.n_faces == 1:
            say("the mesh is a single triangle: nothing to collide with, so nothing was tested")
        if lay.cone_summary:
            say(lay.cone_summary)
        room = MAX_LOG_LINES - len(hits)
        for line in lay.sentences[:room]:
            say(line)
        if len(lay.sentences) > room:
            say(f"... and {len(lay.sentences) - room} more failing nodes")
        what = f"step {frame} → {frame + 1}" if ccd else f"frame {frame}"
        rec.log("/story", rr.TextDocument(f"### Why culled or not, {what}\n\n" + "\n".join(f"- {x}" for x in story),
                                          media_type=rr.MediaType.MARKDOWN))
        return lay

    def log_compare(self, frame: int, method: str, stats: dict, query_ms: float):
        """One compared method's counters and times at `frame` (an untraced query)."""
        self.rec.set_time("frame", sequence=frame)
        base = compare_path(method)
        self._scalar(f"{base}/contour_ms", 1e3 * stats["seconds_contour"], f"{method}: contour-test ms")
        self._scalar(f"{base}/contour_tests", stats["contour_tests"], f"{method}: contour tests")
        self._scalar(f"{base}/elementary_tests", stats["elementary_tests"], f"{method}: elementary tests")
        self._scalar(f"{base}/query_ms", query_ms, f"{method}: query ms")

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
           bvh_depth: int | None = None, progress=None, ccd: bool = False, arithmetic: str = "exact", compare=None,
           source: str | None = None) -> list:
    """Record a sequence; returns the per-frame stats. The BVH is built from frames[0].
    frames: (T, n, 3) positions (array-like); frame_range: indices in [0, T) (default all).
    With ccd=True, frame k shows the CCD step from frame k to k + 1 (the last frame has no step).
    compare: methods (e.g. ["nc", "sct", "cbc"]) also run on every frame, untraced, each on its
    own collider fed the same frames, their contour-test time and counters logged under
    /stats/compare (tracing slows the recorded query, so time the recorded method by listing it
    too); with exact arithmetic their collisions are checked equal to the recorded method's.
    bvh_depth: the depth whose boxes are drawn (default: 4, or the BVH's deepest level if less).
    source: what the frames are (an input's name), for the recording's /about page.
    Every argument is checked before any work, each error naming it."""
    import conecull

    ccd = check_flag(ccd, "ccd")
    method = check_method(method, ccd)
    compare = check_compare(compare, ccd)
    arithmetic = check_arithmetic(arithmetic)  # even without ccd: a typo is a typo
    if arithmetic != "exact" and not ccd:
        raise ValueError(f"arithmetic: {arithmetic!r} is a CCD mode; a DCD recording (ccd=False) has no arithmetic")
    bvh_depth = None if bvh_depth is None else check_depth(bvh_depth)
    if source is not None and not isinstance(source, str):
        raise ValueError(f"source: expected None or a string, got {source!r}")
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
        if len(frames) < 2:
            raise ValueError("frames: CCD records the step from each frame k to k + 1, and the input has one frame")
        frame_range = [k for k in frame_range if k + 1 < len(frames)]
        if not frame_range:
            raise ValueError(f"frame_range: CCD records the step from each frame k to k + 1, and no frame selected "
                             f"has a next one (the input has frames 0..{len(frames) - 1})")
    checks.writable_file("path", path)  # rerun would say so only after the first query
    col = conecull.SelfCollider(mesh, method=method)
    _query(col.dcd, "frame 0", frames[0])  # node ids depend only on the first pose: stable across commands
    deepest = int(col.bvh_arrays()["depth"].max())
    if bvh_depth is None:
        bvh_depth = min(DEFAULT_BVH_DEPTH, deepest)
    elif bvh_depth > deepest:  # no box would be drawn
        raise ValueError(f"bvh_depth: {bvh_depth} is deeper than this mesh's BVH, whose nodes are at depths 0..{deepest}")
    others = compared_colliders(mesh, compare, frames[0])  # the same BVH as the recorded collider's
    about = about_markdown(method, ccd, arithmetic, source, len(frames), frame_range, len(mesh.faces), bvh_depth,
                           deepest, compare)
    rec = RerunRecorder(path, mesh.faces, recording_id=recording_id, bvh_depth=bvh_depth,
                        front=method.endswith("+front"), compare=compare, method=method, about=about,
                        deepest=deepest)
    out = []
    previous = 0  # the query of frame 0 above built the BVH (and a front method's first front)
    try:
        for i, k in enumerate(frame_range):
            if ccd:
                res = _query(col.ccd, f"step {k} -> {k + 1}", frames[k], frames[k + 1], arithmetic=arithmetic,
                             trace=True, toi=True)
                rec.log_frame(k, col, frames[k + 1], res, previous=previous if i else None)
            else:
                res = _query(col.dcd, f"frame {k}", frames[k], trace=True)
                rec.log_frame(k, col, frames[k], res, previous=previous)
            previous = k
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


DEFAULT_BVH_DEPTH = 4


def about_markdown(method: str, ccd: bool, arithmetic: str, source: str | None, n_frames: int, frame_range: list,
                   n_faces: int, bvh_depth: int, deepest: int, compare) -> str:
    """The recording's /about page: what produced it, and how to read its timeline."""
    ks = list(frame_range)
    span = f"{ks[0]}" if len(ks) == 1 else (f"{ks[0]}..{ks[-1]}" if ks == list(range(ks[0], ks[-1] + 1)) else
                                            ", ".join(map(str, ks)))
    kind = (f"**CCD** ({arithmetic} arithmetic): timeline `frame` k shows the continuous step from frame k to "
            f"frame k + 1, drawn at its end pose (frame k + 1); steps recorded: {span}" if ccd else
            f"**DCD**: timeline `frame` k shows the pose of frame k; frames recorded: {span}")
    front = ""
    if method.endswith("+front"):
        first = ("the first recorded step's front is built from the top (no CCD query before it)" if ccd else
                 "the first recorded frame's to the query of frame 0 that built the BVH")
        front = ("\n- The front (Alg. 4) is kept between queries: a frame's front counters (added, removed) are "
                 f"relative to the query before it; {first}. The log says which, frame by frame.")
    return "\n".join([
        "### About this recording",
        f"- Method **{method}**; {kind}.",
        f"- Input: {source or 'frames given to conecull.viz.rerun_sink.record'}: {n_faces} "
        f"triangle{'' if n_faces == 1 else 's'}, "
        f"{n_frames} frames (counted from 0).",
        f"- The BVH, and so every node id, comes from frame 0, as in `conecull explain` and `conecull view`; "
        f"its depths are 0..{deepest}, and *scene/bvh* draws depth {bvh_depth}.",
        *([f"- Also compared, each on its own collider: {', '.join(compare)}."] if compare else []),
        ]) + front


def _query(run, where: str, *args, **kwargs):
    """A query; the core's complaint about the positions (V, V0, V1) also says which frame."""
    try:
        return run(*args, **kwargs)
    except ValueError as e:
        raise ValueError(f"frames: {where}: {e}") from None
