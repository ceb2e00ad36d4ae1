"""Plain-language verdict of one BVH node in one traced query (`conecull explain`)."""

from __future__ import annotations

import numpy as np

from conecull.trace import CONE_TOO_WIDE, REASONS, explain
from conecull.viz.checks import check_node


def parents(bvh: dict) -> np.ndarray:
    p = np.full(len(bvh["depth"]), -1, np.int64)
    inner = np.flatnonzero(bvh["right"] >= 0)
    p[bvh["left"][inner]] = inner
    p[bvh["right"][inner]] = inner
    return p


def path_to_root(bvh: dict, node: int) -> list[int]:
    par = parents(bvh)
    out = [node]
    while par[out[-1]] >= 0:
        out.append(int(par[out[-1]]))
    return out


def check_result(col, res) -> None:
    """res must be a traced query of col itself: node ids mean nothing in another collider's BVH.
    A result names its collider (res.collider, a weak reference). For a result built by hand
    (collider None), what the trace shows is compared instead: the method, the BVH's depth (the
    trace has one level entry per depth) and that every node, face, vertex, edge and contour edge
    it names exists in col."""
    import conecull

    if not isinstance(col, conecull.SelfCollider):
        raise ValueError(f"col: expected a conecull.SelfCollider, got {type(col).__name__}")
    if not isinstance(res, (conecull.DcdResult, conecull.CcdResult)):
        raise ValueError(f"res: expected the result of a query of col (col.dcd(V, trace=True)), "
                         f"got {type(res).__name__}")
    if not len(col.bvh_arrays()["depth"]):
        raise ValueError("col: has no BVH yet (it is built by the first query): run col.dcd(V) first")
    if res.trace is None:
        raise ValueError("res: the query was not traced; run it with trace=True (col.dcd(V, trace=True))")
    if res.collider is not None and res.collider() is not col:
        raise ValueError("res: comes from another collider; pass the result of a query of col itself")
    method = res.stats.get("method")
    if method != col.method:
        raise ValueError(f"res: comes from a query with method {method!r}, but col uses {col.method!r}; "
                         "pass the result of col's own query")
    bvh, tr, mesh = col.bvh_arrays(), res.trace, col.mesh
    depth = int(bvh["depth"].max()) + 1 if len(bvh["depth"]) else 0
    ct = col.contour_arrays()
    loop_len = np.diff(ct["offsets"])
    problems = []
    if len(tr.level["pairs"]) != depth:
        problems.append(f"its trace covers a BVH of depth {len(tr.level['pairs']) - 1}, col's has depth {depth - 1}")
    n_nodes = len(bvh["depth"])
    for kind in ("cone", "contour"):
        nodes = getattr(tr, kind)["node"]
        if len(nodes) and nodes.max() >= n_nodes:
            problems.append(f"its trace names node {int(nodes.max())}, col's BVH has nodes 0..{n_nodes - 1}")
    c = tr.contour
    if not problems and len(c["node"]) and (c["edge"] >= loop_len[c["node"]]).any():
        problems.append("its trace names contour edges col's contours do not have")
    for kind, limits, what in (("elementary", (mesh.n_faces, mesh.n_faces), "triangle"),
                               ("vf", (mesh.n_vertices, mesh.n_faces), "vertex or face"),
                               ("ee", (len(mesh.edges),) * 2, "edge")):
        pairs = getattr(tr, kind)["pair"] if hasattr(tr, kind) else np.zeros((0, 2))
        if len(pairs) and (pairs.max(axis=0) >= limits).any():
            problems.append(f"its trace names a {what} col's mesh does not have")
    if problems:
        raise ValueError(f"res: comes from another collider ({problems[0]}); pass the result of a query of col itself")


def explain_node(col, res, node: int, *, node_name: str = "node") -> str:
    """A few lines: where the node is, what was tested there, and the verdict in words.
    res: a traced query (trace=True) of col itself; node: a node id of col's BVH (node_name is
    what errors call it: the CLI passes "--node")."""
    check_result(col, res)
    bvh = col.bvh_arrays()
    node = check_node(node, len(bvh["depth"]), node_name)
    tr = res.trace
    nt = int(bvh["end"][node] - bvh["begin"][node])
    path = path_to_root(bvh, node)
    lines = [f"node {node}: depth {int(bvh['depth'][node])}, {nt} triangle{'s' if nt != 1 else ''}, "
             f"{'leaf' if bvh['right'][node] < 0 else 'internal'}; path to root: {' -> '.join(map(str, path))}"]
    cone_i = np.flatnonzero(tr.cone["node"] == node)
    contour_i = np.flatnonzero(tr.contour["node"] == node)
    if len(cone_i):
        i = cone_i[0]
        ang = float(np.degrees(tr.cone["apex_angle"][i]))
        ax = np.round(tr.cone["axis"][i], 4).tolist()
        lines.append(f"normal cone: axis {ax}, apex angle {ang:.2f} degrees")
        if not tr.cone["bounded"][i]:
            lines.append("verdict: not culled, cone_too_wide: " + CONE_TOO_WIDE[1].format(angle=ang) + ".")
            return "\n".join(lines)
    if len(contour_i):
        i = contour_i[0]
        code = int(tr.contour["reason"][i])
        simple = bool(tr.contour["simple"][i])
        star_tried = bool(np.isfinite(tr.contour["kernel"][i]).all())
        if code < 16 and star_tried:
            lines.append(f"contour test: kernel point {np.round(tr.contour['kernel'][i], 6).tolist()}, "
                         f"ray {np.round(tr.contour['ray'][i], 4).tolist()}, crossings {int(tr.contour['crossings'][i])}")
        elif code < 16:
            lines.append("contour test: the simplicity test, run first: it proved this node when last tested")
        verdict = "culled" if code == 0 else "not culled"
        lines.append(f"verdict: {verdict}, {REASONS[code][0]}: "
                     + explain(code, tr.contour["edge"][i], tr.contour["crossings"][i], simple, star_tried) + ".")
        return "\n".join(lines)
    # Not judged itself: say why.
    culled = set(tr.culled_nodes().tolist())
    above = [a for a in path[1:] if a in culled]
    if above:
        lines.append(f"verdict: not examined: its ancestor {above[0]} was culled, which covers this node.")
    elif nt < 2:
        lines.append("verdict: not examined: a single triangle cannot collide with itself (Alg. 2 line 1).")
    elif res.stats.get("method") in ("aabb", "aabb+front"):
        lines.append(f"verdict: not examined: method '{res.stats['method']}' uses no normal cones.")
    else:
        lines.append("verdict: not examined by normal cones in this query.")
    return "\n".join(lines)
