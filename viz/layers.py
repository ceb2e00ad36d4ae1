"""What the viewers draw for one traced frame, computed once for both sinks (rerun, viser).

Face status, by precedence (later wins): not examined by normal cones < inside a node whose
cone failed < inside a node whose contour test failed or could not run < inside a culled node
< colliding. Deeper nodes overwrite shallower ones, so each face shows the verdict of the
deepest node that judged it. The traversal descends below a failing node until a node is culled,
so most faces end in a culled node: their green is shaded by that node's depth (deep green for a
node near the root, paler for a small one deep in the BVH), and the culled nodes' boundary
contours (the contour their test passed) outline the culled patches. Faces stay yellow or orange
only where nothing below the failing node was judged: a failing leaf, or a lone triangle under a
failing node (a single triangle is never tested: it has nothing to collide with); the failing
nodes above are drawn as boxes (rerun; in the viewer, behind a checkbox).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from conecull.normal_spread import Normals, Spread, node_spreads
from conecull.trace import CONE_TOO_WIDE, REASONS, explain, reason_name

UNTESTED, CONE_FAILED, CONTOUR_FAILED, CULLED, COLLIDING = range(5)
STATUS_NAMES = ("not examined", "cone too wide", "contour failed", "culled", "colliding")
STATUS_COLORS = np.array([[190, 190, 190], [235, 195, 60], [240, 130, 40], [80, 175, 95], [215, 40, 40]], np.uint8)
# A failed cone whose normals fit in an open hemisphere (normal_spread: "within"): the bound failed,
# not the patch; a paler yellow than a cone whose normals really span a hemisphere.
CONE_BOUND_COLOR = (250, 225, 140)
SPREAD_WORDS = {"beyond": "normals span a hemisphere", "within": "normals within a hemisphere",
                "undecided": "spread undecided", "unsearched": "spread not searched"}
# Hemisphere searches per frame (normal_spread.node_spreads), deepest nodes first: about 0.15-0.3 s
# on falling's 4500 failed cones (169K triangles) where searching all took 0.8-1.2 s per frame,
# which every frame change in the viewer paid.
MAX_SPREAD_SEARCHES = 500
CULLED_PALE = 0.5  # how far toward white the green of a culled face goes at the BVH's deepest level
CULLED_CONTOUR_COLOR = (30, 110, 50)  # the culled nodes' outlines: a darker green than any culled face
KERNEL_NOT_FOUND = next(c for c, (name, _) in REASONS.items() if name == "no_kernel_on_search_line")  # sct's
CONE_TOO_WIDE_CODE = -1  # in FrameLayers.node_codes: the node's cone test failed (no contour test ran)

# One colour per contour reason (trace.REASONS: Alg. 1 failures 1-5, the sct and cbc baselines' 6
# and 7, ineligible 16+); tests check that every reason has one.
REASON_COLORS = {
    0: CULLED_CONTOUR_COLOR, 1: (150, 80, 200), 2: (240, 130, 40), 3: (60, 140, 230), 4: (220, 60, 160),
    5: (120, 120, 120), 6: (40, 170, 200), 7: (0, 120, 120),
    # the ineligible ones: none green (culled) nor yellow (cone too wide)
    17: (90, 90, 90), 18: (160, 60, 60), 19: (100, 160, 160), 20: (170, 170, 225), 21: (140, 100, 60), 22: (100, 60, 140),
}


@dataclass
class FrameLayers:
    face_status: np.ndarray       # (m,) uint8 of the constants above
    face_colors: np.ndarray       # (m, 3) uint8; culled faces shaded by their culled node's depth
    face_node: np.ndarray         # (m,) the node whose verdict a face shows (-1: none)
    culled_nodes: np.ndarray      # nodes whose contour test passed (Alg. 2 line 6: culled)
    culled_strips: list           # their boundary contours, closed (k + 1, 3) loops: the culled patches
    contour_nodes: np.ndarray     # nodes whose Alg. 1 ran and failed (they have a loop)
    contour_strips: list          # closed loops as (k + 1, 3) arrays, one per contour node
    contour_reasons: np.ndarray
    kernels: np.ndarray           # (c, 3) at the pose drawn (CCD: the end pose, so o at t = 1)
    rays: np.ndarray              # (c, 3) vectors, scaled to the node size
    cone_nodes: np.ndarray        # nodes not culled: cone too wide, contour failed, or ineligible
    node_colors: np.ndarray       # (c, 3) uint8: yellow for a cone too wide (pale: normals within a
                                  # hemisphere), else REASON_COLORS
    node_labels: list             # per cone node: "node 17: not_star_shaped", as the log names it
    axis_nodes: np.ndarray        # nodes whose cone was bounded: culled, contour failed, or ineligible
    axis_origins: np.ndarray      # their box centres
    axis_vectors: np.ndarray      # their cone axes (the contour test's projection direction), scaled to the node
    axis_colors: np.ndarray       # dark green where culled, else the contour reason's colour
    box_lo: np.ndarray            # (c, 3) per cone node its box's lower corner,
    box_hi: np.ndarray            # (c, 3) and its upper one
    sentences: list               # one plain sentence per failing node: contour failures, then cones
    culled_summary: str           # one sentence on the culled nodes ("" if none)
    cone_summary: str             # one sentence on the failed cones' spreads ("" if none failed)


def node_label(node: int, code: int, spread: Spread | None = None) -> str:
    """'node 17: not_star_shaped': a node and its verdict (CONE_TOO_WIDE_CODE or a contour reason),
    as the recording's boxes and strips are labelled; a failed cone's label says its spread."""
    if code != CONE_TOO_WIDE_CODE:
        return f"node {node}: {reason_name(code)}"
    return f"node {node}: {CONE_TOO_WIDE[0]}" + (f", {SPREAD_WORDS[spread.kind]}" if spread is not None else "")


def node_sentence(node: int, depth: int, n_tris: int, kind: str, code: int = 0, edge: int = -1,
                  crossings: int = 0, spread: Spread | None = None, ccd: bool = False) -> str:
    head = f"node {node} (depth {depth}, {n_tris} triangles) was not culled "
    if kind == "cone":
        return head + f"({CONE_TOO_WIDE[0]}): " + CONE_TOO_WIDE[1] + (
            f"; {spread.sentence(ccd)}." if spread is not None else ".")
    return head + f"({reason_name(code)}): " + explain(code, edge, crossings) + "."


def cone_sentence(spreads: dict, ccd: bool = False) -> str:
    """The failed cones of a query by their normals' spread, in one sentence ("" if none failed)."""
    if not spreads:
        return ""
    kinds = [s.kind for s in spreads.values()]
    n, within, undecided, unsearched = len(kinds), kinds.count("within"), kinds.count("undecided"), kinds.count("unsearched")
    nodes = "node" if n == 1 else "nodes"
    normals = "the control vectors of their normals over the step" if ccd else "their normals"
    text = (f"{n} {nodes} failed the normal cone test (Alg. 2 line 5): {n - within - undecided - unsearched} have "
            f"{normals} spanning a hemisphere or more, so no cone {'over them ' if ccd else ''}could pass; "
            f"{within} have {normals} within an open hemisphere, so the failure is the cone bound's (merged from "
            "the children's cones, Sec. 3.6, and widened for rounding), not the patch's (each answer checked "
            "exactly)")
    text += f"; {undecided} undecided (no witness held exactly)" if undecided else ""
    return text + (f"; {unsearched} not searched (past {MAX_SPREAD_SEARCHES} searches a frame, deepest nodes "
                   "first; `conecull explain --cones` searches all)" if unsearched else "")


def colliding_triangles(col, res) -> np.ndarray:
    """(k, 2) pairs of triangles that collide in a query of col: DCD, its pairs; CCD, for each
    contact the triangles on either side (a vertex's contact with a face: each triangle around
    the vertex with the face; an edge's with an edge: the triangles around each)."""
    if not hasattr(res, "vf"):
        return res.pairs
    voff, vids = col.mesh.vertex_faces
    eoff, eids = col.mesh.edge_faces
    pairs = [(t, f) for v, f in res.vf.tolist() for t in vids[voff[v] : voff[v + 1]]]
    pairs += [(u, t) for a, b in res.ee.tolist() for u in eids[eoff[a] : eoff[a + 1]] for t in eids[eoff[b] : eoff[b + 1]]]
    return np.array(pairs, dtype=np.int64).reshape(-1, 2)


def colliding_faces(col, res) -> np.ndarray:
    """Faces to paint as colliding: those of colliding_triangles (DCD: both faces of each pair;
    CCD: the face of each VF contact and the faces around its vertex, the faces of both edges of
    each EE contact)."""
    return np.unique(colliding_triangles(col, res))


def compute(col, faces: np.ndarray, V: np.ndarray, res) -> FrameLayers:
    tr = res.trace
    bvh = col.bvh_arrays()
    ct = col.contour_arrays()
    m = len(faces)
    depth, begin, end, order, box = bvh["depth"], bvh["begin"], bvh["end"], bvh["order"], bvh["box"]
    status = np.zeros(m, np.uint8)
    # (depth, status) per judged node; paint shallow first.
    face_node = np.full(m, -1, np.int64)
    events = []
    for node, ok in zip(tr.cone["node"], tr.cone["bounded"]):
        if not ok:
            events.append((depth[node], CONE_FAILED, node))
    for node, code in zip(tr.contour["node"], tr.contour["reason"]):
        events.append((depth[node], CULLED if code == 0 else CONTOUR_FAILED, node))
    for _, st, node in sorted(events):
        f = order[begin[node] : end[node]]
        status[f], face_node[f] = st, node
    colors = STATUS_COLORS[status]
    culled = np.flatnonzero(status == CULLED)
    if len(culled):  # shallow culled node: full green; the deepest level: CULLED_PALE toward white
        t = CULLED_PALE * depth[face_node[culled]] / max(int(depth.max()), 1)
        colors[culled] = np.round(STATUS_COLORS[CULLED] + t[:, None] * (255.0 - STATUS_COLORS[CULLED])).astype(np.uint8)
    hit = colliding_faces(col, res)
    if len(hit):
        status[hit] = COLLIDING
        colors[hit] = STATUS_COLORS[COLLIDING]

    def loop_of(node):
        loop = ct["vertices"][ct["offsets"][node] : ct["offsets"][node + 1]]
        return V[np.append(loop, loop[0])]

    culled_nodes = tr.contour["node"][tr.contour["reason"] == 0].astype(np.int64)
    culled_nodes = culled_nodes[ct["offsets"][culled_nodes + 1] > ct["offsets"][culled_nodes]]  # a passed test had one
    culled_strips = [loop_of(n) for n in culled_nodes]

    fail = (tr.contour["reason"] > 0) & (tr.contour["reason"] < 16)
    cnodes = tr.contour["node"][fail]
    strips = [loop_of(node) for node in cnodes]
    size = np.linalg.norm(box[:, 1] - box[:, 0], axis=1)
    rays = tr.contour["ray"][fail]
    axes_of = dict(zip(tr.cone["node"].tolist(), tr.cone["axis"]))
    # Show the ray in the plane the test works in: its projection perpendicular to the axis.
    proj = []
    for node, r in zip(cnodes, rays):
        l = axes_of[int(node)]
        p = r - np.dot(r, l) * l
        n = np.linalg.norm(p)
        proj.append(p / n * 0.6 * size[node] if n > 0 else p)
    proj = np.array(proj).reshape(-1, 3)

    bad_cone = tr.cone["node"][~tr.cone["bounded"]]
    ineligible = tr.contour["reason"] >= 16
    cone_nodes = np.concatenate([bad_cone, cnodes, tr.contour["node"][ineligible]]).astype(np.int64)
    node_codes = np.concatenate([np.full(len(bad_cone), CONE_TOO_WIDE_CODE), tr.contour["reason"][fail],
                                 tr.contour["reason"][ineligible]]).astype(np.int64)
    ccd = hasattr(res, "vf")
    spreads = node_spreads(Normals(faces, *tr.positions), bvh, bad_cone, MAX_SPREAD_SEARCHES) if len(bad_cone) else {}
    node_colors = np.array([REASON_COLORS[int(c)] if c != CONE_TOO_WIDE_CODE else CONE_BOUND_COLOR
                            if spreads[n].kind == "within" else STATUS_COLORS[CONE_FAILED]
                            for n, c in zip(cone_nodes.tolist(), node_codes.tolist())], np.uint8).reshape(-1, 3)
    node_labels = [node_label(n, c, spreads.get(n)) for n, c in zip(cone_nodes.tolist(), node_codes.tolist())]
    tested = np.isin(tr.contour["node"], tr.cone["node"][tr.cone["bounded"]])
    axis_nodes = tr.contour["node"][tested].astype(np.int64)
    axis_codes = tr.contour["reason"][tested]
    axis_colors = np.array([REASON_COLORS[int(c)] for c in axis_codes], np.uint8).reshape(-1, 3)

    # Failed contours first (the rarer and more telling verdict: a log cut short keeps them).
    sentences = []
    for node, code, e, c in zip(tr.contour["node"], tr.contour["reason"], tr.contour["edge"], tr.contour["crossings"]):
        if code != 0:
            sentences.append(node_sentence(int(node), int(depth[node]), int(end[node] - begin[node]), "contour",
                                           int(code), int(e), int(c)))
    for node in bad_cone:
        sentences.append(node_sentence(int(node), int(depth[node]), int(end[node] - begin[node]), "cone",
                                       spread=spreads[int(node)], ccd=ccd))
    kernels = tr.contour["kernel_end"][fail].copy()
    # No kernel point was tried (the trace's kernel and ray are fillers): cbc's edge-pair test has
    # none, and sct's line search may find none. NaN rows: the sinks draw only finite ones.
    no_kernel = np.full(len(kernels), res.stats.get("method") == "cbc")
    no_kernel |= tr.contour["reason"][fail] == KERNEL_NOT_FOUND
    kernels[no_kernel] = np.nan
    proj[no_kernel] = np.nan
    return FrameLayers(
        face_status=status, face_colors=colors, face_node=face_node, culled_nodes=culled_nodes,
        culled_strips=culled_strips, contour_nodes=cnodes, contour_strips=strips,
        contour_reasons=tr.contour["reason"][fail], kernels=kernels, rays=proj,
        cone_nodes=cone_nodes,
        node_colors=node_colors, node_labels=node_labels, axis_nodes=axis_nodes,
        axis_origins=(0.5 * (box[axis_nodes, 0] + box[axis_nodes, 1])).reshape(-1, 3),
        axis_vectors=np.array([axes_of[int(n)] * 0.5 * size[n] for n in axis_nodes]).reshape(-1, 3),
        axis_colors=axis_colors,
        box_lo=box[cone_nodes, 0].reshape(-1, 3), box_hi=box[cone_nodes, 1].reshape(-1, 3),
        sentences=sentences,
        culled_summary=culled_sentence(culled_nodes, depth, end - begin, m, ccd),
        cone_summary=cone_sentence(spreads, ccd),
    )


def culled_sentence(nodes: np.ndarray, depth: np.ndarray, n_tris: np.ndarray, m: int, ccd: bool, shown: int = 3) -> str:
    """What the culled nodes (Alg. 2 line 6) prove, in one sentence, the largest named."""
    if not len(nodes):
        return ""
    what = "touch during the step" if ccd else "intersect"
    if (nodes == 0).any():
        return (f"the root (all {m} triangles) was culled: its normal cone is bounded below 180 degrees and its "
                f"contour passed the test, so no two of its triangles can {what}; nothing else was tested.")
    big = nodes[np.lexsort((nodes, -n_tris[nodes]))][:shown]
    named = ", ".join(f"node {n} (depth {depth[n]}, {n_tris[n]} triangles)" for n in big.tolist())
    return (f"{len(nodes)} nodes culled, {int(n_tris[nodes].sum())} of the {m} triangles: no two triangles of one "
            f"culled node can {what} (pairs across nodes are left to box tests); the largest: {named}.")


# Front load heatmap stops (no front -> light grey, then blue to yellow as the load grows).
_FRONT_STOPS = np.array([[215, 215, 215], [70, 50, 130], [40, 120, 175], [60, 180, 115], [250, 220, 40]], float)


def front_colors(load: np.ndarray) -> np.ndarray:
    """(m, 3) uint8 per face for `SelfCollider.front_load`: grey where no front entry reaches,
    else a ramp on log(1 + load) scaled to the frame's maximum (fronts span decades)."""
    load = np.asarray(load, np.float64)
    top = np.log1p(load.max()) if len(load) and load.max() > 0 else 1.0
    t = np.where(load > 0, 0.25 + 0.75 * np.log1p(load) / top, 0.0)
    x = t * (len(_FRONT_STOPS) - 1)
    i = np.minimum(x.astype(int), len(_FRONT_STOPS) - 2)
    f = (x - i)[:, None]
    return np.round((1 - f) * _FRONT_STOPS[i] + f * _FRONT_STOPS[i + 1]).astype(np.uint8)


def status_legend() -> list[tuple[str, tuple]]:
    """The key of the verdict colouring (face_colors): (name, colour) per face status."""
    names = list(STATUS_NAMES)
    names[CULLED] += " (paler: a smaller node, deeper in the BVH)"
    names[CONE_FAILED] += " (nothing below it judged)"
    names[CONTOUR_FAILED] += " (nothing below it judged)"
    return [(name, tuple(int(c) for c in STATUS_COLORS[i])) for i, name in enumerate(names)]


def front_legend(load: np.ndarray) -> list[tuple[str, tuple]]:
    """The key of front_colors(load): no entry, one entry, a load between and the frame's maximum
    (the ramp is logarithmic and scaled to that maximum, so the key is per frame)."""
    top = int(np.max(load)) if len(load) else 0
    keys = [0] + sorted({1, int(round(np.sqrt(top))), top} - {0}) if top > 0 else [0]
    words = {0: "no front entry", 1: "1 front entry"}
    names = [words.get(k, f"{k} entries") + (" (the most now)" if k == top and k > 0 else "") for k in keys]
    return [(n, tuple(int(c) for c in rgb)) for n, rgb in zip(names, front_colors(np.array(keys)))]


def reason_legend() -> list[tuple[str, tuple]]:
    return [(REASONS[c][0], REASON_COLORS[c]) for c in sorted(REASON_COLORS) if c in REASONS]


__all__ = ["compute", "colliding_triangles", "front_colors", "front_legend", "status_legend", "FrameLayers", "STATUS_NAMES", "STATUS_COLORS",
           "REASON_COLORS", "reason_name", "node_label", "node_sentence"]
