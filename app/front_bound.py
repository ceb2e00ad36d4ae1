"""How small could any normal-cone test make the front (Fig. 11) on a pose? A bound, for the
front table (`bench front`).

Alg. 2 / 4 cull a node N only if ApexAngle(C_N) < pi (line 5), that is only if every triangle
normal below N lies in one open hemisphere; ours certifies that with a bounded cone, and adds the
contour test. So no cone test can cull a node whose normals are not in an open hemisphere, and
the front of Alg. 4 keeps at least the sub-segments Front_X of those nodes that the traversal
reaches. `front_bound` walks the BVH from the root as Alg. 4 would with an ideal test: every
node whose normals lie in an open hemisphere is culled, contour or not; the others keep the
sub-segment that `aabb+front` keeps for them (the same BVTT cut of Collide(L, R)).

Whether the normals lie in an open hemisphere is conecull.normal_spread's question, answered
with a witness checked exactly (until 2026-11-28 a floating-point linear program, scipy's
`linprog`). A node whose cone ours bounded needs no search (certified). A node the search leaves
undecided counts as culled, so the bound stays a lower bound.
"""

from __future__ import annotations

import numpy as np

from conecull._api import DEFAULT_LEAF_SIZE
from conecull.normal_spread import Normals, normal_spread


def front_bound(F, V_build, V, *, leaf_size: int = DEFAULT_LEAF_SIZE) -> dict:
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
    normals = Normals(F, V)

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
        return bool(bounded[x]) or normal_spread(normals, order[begin[x]:end[x]]).kind != "beyond"

    ours, ours_nodes = walk(lambda x: culled_by_ours[x])
    bound, bound_nodes = walk(hemisphere)
    return {"aabb_front": total, "ours": ours, "ours_nodes": ours_nodes, "bound": bound, "bound_nodes": bound_nodes,
            "ours_ratio": ours / total if total else 0.0, "bound_ratio": bound / total if total else 0.0}
