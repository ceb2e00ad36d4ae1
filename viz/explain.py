"""Plain-language verdict of one BVH node in one traced query (`conecull explain`)."""

from __future__ import annotations

import numpy as np

from conecull.trace import CONE_TOO_WIDE, REASONS, explain


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


def explain_node(col, res, node: int) -> str:
    """A few lines: where the node is, what was tested there, and the verdict in words."""
    bvh = col.bvh_arrays()
    n_nodes = len(bvh["depth"])
    if not 0 <= node < n_nodes:
        raise ValueError(f"--node: {node} is out of range: the BVH has nodes 0..{n_nodes - 1}")
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
        if code < 16:
            lines.append(f"contour test: kernel point {np.round(tr.contour['kernel'][i], 6).tolist()}, "
                         f"ray {np.round(tr.contour['ray'][i], 4).tolist()}, crossings {int(tr.contour['crossings'][i])}")
        verdict = "culled" if code == 0 else "not culled"
        lines.append(f"verdict: {verdict}, {REASONS[code][0]}: "
                     + explain(code, tr.contour["edge"][i], tr.contour["crossings"][i]) + ".")
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
