"""What the viewers draw for one traced frame, computed once for both sinks (rerun, viser).

Face status, by precedence (later wins): not examined by normal cones < inside a node whose
cone failed < inside a node whose contour test failed or could not run < inside a culled node
< colliding. Deeper nodes overwrite shallower ones, so each face shows the verdict of the
deepest node that judged it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from conecull.trace import CONE_TOO_WIDE, REASONS, explain, reason_name

UNTESTED, CONE_FAILED, CONTOUR_FAILED, CULLED, COLLIDING = range(5)
STATUS_NAMES = ("not examined", "cone too wide", "contour failed", "culled", "colliding")
STATUS_COLORS = np.array([[190, 190, 190], [235, 195, 60], [240, 130, 40], [80, 175, 95], [215, 40, 40]], np.uint8)

# One colour per contour reason (trace.REASONS: Alg. 1 failures 1-5, the sct and cbc baselines' 6
# and 7, ineligible 16+); tests check that every reason has one.
REASON_COLORS = {
    0: (80, 175, 95), 1: (150, 80, 200), 2: (240, 130, 40), 3: (60, 140, 230), 4: (220, 60, 160), 5: (120, 120, 120),
    6: (40, 170, 200), 7: (190, 150, 30),
    17: (90, 90, 90), 18: (160, 60, 60), 19: (100, 160, 160), 20: (200, 200, 80), 21: (140, 100, 60), 22: (60, 100, 60),
}


@dataclass
class FrameLayers:
    face_status: np.ndarray       # (m,) uint8 of the constants above
    face_colors: np.ndarray       # (m, 3) uint8
    contour_nodes: np.ndarray     # nodes whose Alg. 1 ran and failed (they have a loop)
    contour_strips: list          # closed loops as (k + 1, 3) arrays, one per contour node
    contour_reasons: np.ndarray
    kernels: np.ndarray           # (c, 3) at the pose drawn (CCD: the end pose, so o at t = 1)
    rays: np.ndarray              # (c, 3) vectors, scaled to the node size
    cone_nodes: np.ndarray        # nodes whose cone or contour test failed
    cone_origins: np.ndarray
    cone_vectors: np.ndarray
    cone_bounded: np.ndarray
    sentences: list               # one plain sentence per failing node: contour failures, then cones


def node_sentence(node: int, depth: int, n_tris: int, kind: str, code: int = 0, edge: int = -1,
                  crossings: int = 0) -> str:
    head = f"node {node} (depth {depth}, {n_tris} triangles) was not culled "
    if kind == "cone":
        return head + f"({CONE_TOO_WIDE[0]}): " + CONE_TOO_WIDE[1] + "."
    return head + f"({reason_name(code)}): " + explain(code, edge, crossings) + "."


def colliding_faces(col, res) -> np.ndarray:
    """Faces to paint as colliding: both faces of each DCD pair; for CCD, the face of each VF
    contact and the faces around its vertex, and the faces of both edges of each EE contact."""
    if not hasattr(res, "vf"):
        return res.pairs.ravel()
    mesh = col.mesh
    voff, vids = mesh.vertex_faces
    eoff, eids = mesh.edge_faces
    out = [res.vf[:, 1]]
    out += [vids[voff[v] : voff[v + 1]] for v in res.vf[:, 0]]
    out += [eids[eoff[e] : eoff[e + 1]] for e in res.ee.ravel()]
    return np.unique(np.concatenate(out)) if out else np.zeros(0, np.int64)


def compute(col, faces: np.ndarray, V: np.ndarray, res) -> FrameLayers:
    tr = res.trace
    bvh = col.bvh_arrays()
    ct = col.contour_arrays()
    m = len(faces)
    depth, begin, end, order, box = bvh["depth"], bvh["begin"], bvh["end"], bvh["order"], bvh["box"]
    status = np.zeros(m, np.uint8)
    # (depth, status) per judged node; paint shallow first.
    events = []
    for node, ok in zip(tr.cone["node"], tr.cone["bounded"]):
        if not ok:
            events.append((depth[node], CONE_FAILED, node))
    for node, code in zip(tr.contour["node"], tr.contour["reason"]):
        events.append((depth[node], CULLED if code == 0 else CONTOUR_FAILED, node))
    for _, st, node in sorted(events):
        status[order[begin[node] : end[node]]] = st
    hit = colliding_faces(col, res)
    if len(hit):
        status[hit] = COLLIDING

    fail = (tr.contour["reason"] > 0) & (tr.contour["reason"] < 16)
    cnodes = tr.contour["node"][fail]
    strips = []
    for node in cnodes:
        loop = ct["vertices"][ct["offsets"][node] : ct["offsets"][node + 1]]
        strips.append(V[np.append(loop, loop[0])])
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
    cone_nodes = np.concatenate([bad_cone, cnodes, tr.contour["node"][tr.contour["reason"] >= 16]]).astype(np.int64)
    centers = 0.5 * (box[cone_nodes, 0] + box[cone_nodes, 1])
    vecs = np.array([axes_of[int(n)] * 0.5 * size[n] for n in cone_nodes]).reshape(-1, 3)
    bounded = np.isin(cone_nodes, tr.cone["node"][tr.cone["bounded"]])

    # Failed contours first (the rarer and more telling verdict: a log cut short keeps them).
    sentences = []
    for node, code, e, c in zip(tr.contour["node"], tr.contour["reason"], tr.contour["edge"], tr.contour["crossings"]):
        if code != 0:
            sentences.append(node_sentence(int(node), int(depth[node]), int(end[node] - begin[node]), "contour",
                                           int(code), int(e), int(c)))
    for node in bad_cone:
        sentences.append(node_sentence(int(node), int(depth[node]), int(end[node] - begin[node]), "cone"))
    kernels = tr.contour["kernel_end"][fail]
    if res.stats.get("method") == "cbc":  # its edge-pair test has no kernel point nor ray (the trace's are fillers)
        kernels, proj = np.full_like(kernels, np.nan), np.full_like(proj, np.nan)
    return FrameLayers(
        face_status=status, face_colors=STATUS_COLORS[status], contour_nodes=cnodes, contour_strips=strips,
        contour_reasons=tr.contour["reason"][fail], kernels=kernels, rays=proj,
        cone_nodes=cone_nodes, cone_origins=centers.reshape(-1, 3), cone_vectors=vecs, cone_bounded=bounded,
        sentences=sentences,
    )


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
    return [(name, tuple(int(c) for c in STATUS_COLORS[i])) for i, name in enumerate(STATUS_NAMES)]


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


__all__ = ["compute", "front_colors", "front_legend", "status_legend", "FrameLayers", "STATUS_NAMES", "STATUS_COLORS",
           "REASON_COLORS", "reason_name", "node_sentence"]
