"""How small could any normal-cone test make the front (Fig. 11) on a pose? A bound, for the
front table (`bench front`).

Alg. 2 / 4 cull a node N only if ApexAngle(C_N) < pi (line 5), that is only if every triangle
normal below N lies in one open hemisphere; ours certifies that with a bounded cone, and adds the
contour test. So no cone test can cull a node whose normals are not in an open hemisphere, and
the front of Alg. 4 keeps at least the sub-segments Front_X of those nodes that the traversal
reaches. `front_bound` walks the BVH from the root as Alg. 4 would with an ideal test: every
node whose normals lie in an open hemisphere is culled, contour or not; the others keep the
sub-segment that `aabb+front` keeps for them (the same BVTT cut of Collide(L, R)).

Whether unit normals n_i lie in an open hemisphere is a linear program: maximise t subject to
n_i . v >= t and |v_k| <= 1; they do iff t > 0. It is solved in floating point (scipy's
`linprog`, HiGHS) for a report, not certified like the culling predicates (see LP_T_MIN); a node
whose cone ours bounded needs no solve (certified), and the mean normal is tried as a witness
first.
"""

from __future__ import annotations

import numpy as np

from conecull._api import DEFAULT_LEAF_SIZE


def scipy_linprog():
    """scipy.optimize.linprog, or None (scipy comes with the `bench` extra, through ipctk)."""
    try:
        from scipy.optimize import linprog
    except ImportError:
        return None
    return linprog


# At or below this optimum t the normals count as not in an open hemisphere. The solver works to
# tolerances of about 1e-7, so only a node whose normals come within that of spanning a closed
# hemisphere (some nearly exactly opposite) may be judged either way; any other verdict stands.
LP_T_MIN = 1e-9


def in_open_hemisphere(normals: np.ndarray, linprog=None, *, witness: bool = True) -> bool:
    """True if some v has n . v > 0 for every row n of `normals` (unit vectors, (k, 3)).
    witness=False skips the mean-normal shortcut, so the linear program decides (tests)."""
    n = np.asarray(normals, dtype=np.float64)
    if len(n) == 0:
        return True
    if witness and (n @ n.sum(axis=0) > 0).all():  # the mean normal is a witness: no solve
        return True
    linprog = linprog or scipy_linprog()
    if linprog is None:
        raise ImportError("front_bound needs scipy (pip install 'conecull[bench]')")
    # Variables (v_x, v_y, v_z, t): minimise -t subject to t - n . v <= 0, -1 <= v_k <= 1, t <= 1.
    res = linprog(np.array([0.0, 0.0, 0.0, -1.0]), A_ub=np.c_[-n, np.ones(len(n))], b_ub=np.zeros(len(n)),
                  bounds=[(-1.0, 1.0)] * 3 + [(None, 1.0)], method="highs")
    return bool(res.status == 0 and -res.fun > LP_T_MIN)


def front_bound(F, V_build, V, linprog=None, *, leaf_size: int = DEFAULT_LEAF_SIZE) -> dict:
    """On pose V, the BVH built at V_build: per culling rule, the front entries kept (the
    sub-segments of `aabb+front` for the internal nodes that the traversal reaches and does not
    cull), and the share of all of `aabb+front`'s entries that is. "ours": a node is culled where
    `nc` culled it (bounded cone and contour test passed); "bound": where its normals lie in an
    open hemisphere (any cone test's best). bound <= ours always: ours culls only such nodes.
    leaf_size: the colliders' (triangles per BVH leaf), which sets the BVTT and so the fronts."""
    import conecull

    F = np.asarray(F)
    V = np.asarray(V, dtype=np.float64)
    mesh = conecull.Mesh(F, n_vertices=len(V))
    aabb = conecull.SelfCollider(mesh, method="aabb+front", leaf_size=leaf_size, threads=1)
    nc = conecull.SelfCollider(mesh, method="nc", leaf_size=leaf_size, threads=1)
    for col in (aabb, nc):
        col.dcd(V_build)  # the BVH comes from the first pose queried
    # The jump from V_build to V can make sub-segments churn, and a churned one rests: it keeps
    # no entries for a query or more, and is rebuilt by the query after. Query V until a query
    # rested nowhere and none is left to rest, so every node's Front_X is counted.
    for _ in range(64):
        rested = aabb.dcd(V).stats["front_rested"]
        if rested == 0 and not aabb.front_arrays("dcd")["resting"].any():
            break
    else:
        raise RuntimeError("front_bound: aabb+front kept resting nodes after 64 queries of the same pose")
    traced = nc.dcd(V, trace=True)
    b = nc.bvh_arrays()
    left, right, begin, end, order = b["left"], b["right"], b["begin"], b["end"], b["order"]
    front = aabb.front_arrays("dcd")
    kept = np.bincount(front["owner"], minlength=len(left))
    total = int(kept.sum())
    # nc's verdicts: culled where the cone was bounded and the contour test passed (reason 0).
    culled_by_ours = np.zeros(len(left), dtype=bool)
    contour = traced.trace.contour
    culled_by_ours[np.asarray(contour["node"])[np.asarray(contour["reason"]) == 0]] = True
    bounded = nc.cone_arrays()["cos_bound"] > 0  # certified: normals in an open hemisphere
    T = V[F]
    normals = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    length = np.linalg.norm(normals, axis=1)
    unit = normals / np.where(length > 0, length, 1.0)[:, None]  # a zero-area triangle: 0, no constraint

    def walk(culled) -> tuple[int, int]:
        entries, nodes, stack = 0, 0, [0] if len(left) else []
        while stack:
            x = stack.pop()
            if right[x] < 0 or culled(x):  # a leaf, or culled: no sub-segment below
                continue
            entries += int(kept[x])
            nodes += 1
            stack += [int(left[x]), int(right[x])]
        return entries, nodes

    def hemisphere(x) -> bool:
        if bounded[x]:
            return True
        n = unit[order[begin[x]:end[x]]]
        return in_open_hemisphere(n[np.any(n != 0, axis=1)], linprog)

    ours, ours_nodes = walk(lambda x: culled_by_ours[x])
    bound, bound_nodes = walk(hemisphere)
    return {"aabb_front": total, "ours": ours, "ours_nodes": ours_nodes, "bound": bound, "bound_nodes": bound_nodes,
            "ours_ratio": ours / total if total else 0.0, "bound_ratio": bound / total if total else 0.0}
