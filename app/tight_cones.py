"""What would tighter normal cones save? An upper bound on one query, by replay.

Many nodes fail the cone test although their normals fit in an open hemisphere (normal_spread:
"within"): the cone merged from their children's (Sec. 3.6) is looser than the normals. Were
their cones tight, the contour test would run on them. This replays Alg. 2 in Python on a traced
`nc` query, culling what `nc` culled plus every "within" node whose contour test (Alg. 1, then
the simplicity fallback, as `nc`) passes about the exact witness axis, and counts box tests and
elementary tests both ways. The replay of `nc`'s own rule must reproduce the core's counters
(checked: an error otherwise), so the difference is what tight cones could save at best, before
the cost of finding them every query.

    python -m conecull.app.tight_cones [STEP ...]    # the shared real steps (default: all four)
"""

from __future__ import annotations

import sys

import numpy as np

import conecull
from conecull import _core
from conecull.normal_spread import Normals, node_spreads


def replay_counts(bvh: dict, culled: set) -> tuple[int, int]:
    """(box tests, elementary tests) of Alg. 2 over the BVH, culling the nodes in `culled`: as the
    core counts them (Collide descends the larger node; two leaves test every pair of theirs)."""
    lo, hi, right, begin, end = bvh["box"][:, 0], bvh["box"][:, 1], bvh["right"], bvh["begin"], bvh["end"]
    size = end - begin
    bv = tests = 0
    stack = [("self", 0, 0)]
    while stack:
        kind, a, b = stack.pop()
        if kind == "self":
            if size[a] < 2 or a in culled:
                continue
            if right[a] < 0:
                tests += int(size[a]) * (int(size[a]) - 1) // 2
                continue
            stack += [("pair", a + 1, int(right[a])), ("self", int(right[a]), 0), ("self", a + 1, 0)]
            continue
        bv += 1
        if not ((lo[a] <= hi[b]).all() and (lo[b] <= hi[a]).all()):
            continue
        la, lb = right[a] < 0, right[b] < 0
        if la and lb:
            tests += int(size[a]) * int(size[b])
        elif lb or (not la and size[a] >= size[b]):
            stack += [("pair", int(right[a]), b), ("pair", a + 1, b)]
        else:
            stack += [("pair", a, int(right[b])), ("pair", a, b + 1)]
    return bv, tests


def tight_cone_gain(F, V_build, V) -> dict:
    """On pose V (the BVH built at V_build, leaf 2): nc's box and elementary tests, replayed and
    from the core, and the replay's counts with the "within" nodes whose contour passes culled."""
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=len(V)), method="nc", threads=1)
    col.dcd(V_build)
    res = col.dcd(V, trace=True)
    tr, bvh, ct = res.trace, col.bvh_arrays(), col.contour_arrays()
    culled = set(tr.contour["node"][tr.contour["reason"] == 0].tolist())
    failed = tr.cone["node"][~tr.cone["bounded"]]
    spreads = node_spreads(Normals(F, V), bvh, failed)
    more = set()
    for n, s in spreads.items():
        loop = ct["vertices"][ct["offsets"][n] : ct["offsets"][n + 1]].astype(np.int32)
        if s.kind != "within" or len(loop) < 3:
            continue
        axis = s.axis / np.linalg.norm(s.axis)
        if (_core.contour.contour_test(loop, V, axis)["reason"] == 0
                or _core.contour.simplicity_test(loop, V, axis)["reason"] == 0):
            more.add(n)
    bv, tests = replay_counts(bvh, culled)
    if (bv, tests) != (res.stats["bv_tests"], res.stats["elementary_tests"]):
        raise RuntimeError(f"tight_cones: the replay counts {bv} box tests and {tests} elementary tests, the core "
                           f"{res.stats['bv_tests']} and {res.stats['elementary_tests']}: the replay is not Alg. 2's")
    tight_bv, tight_tests = replay_counts(bvh, culled | more)
    within = sorted(n for n, s in spreads.items() if s.kind == "within")
    return {"failed_cones": len(spreads), "within": len(within), "would_pass": len(more),
            "within_median_triangles": float(np.median([bvh["end"][n] - bvh["begin"][n] for n in within]))
            if within else 0.0,
            "bv_tests": bv, "elementary_tests": tests, "tight_bv_tests": tight_bv, "tight_elementary_tests": tight_tests}


def main(argv=None) -> int:
    from conecull.datasets.shared import load_scalable_step, scalable_ccd_steps, shared_data_dir

    names = list(sys.argv[1:] if argv is None else argv)
    data = shared_data_dir()
    if data is None:
        print("tight_cones: error: no shared steps (../shared/data/scalable-ccd is absent)", file=sys.stderr)
        return 2
    listed = scalable_ccd_steps(data)
    known = [scene for scene, _ in listed]
    unknown = [n for n in names if n not in known]
    if unknown:
        print(f"tight_cones: error: STEP: unknown step {unknown[0]!r}; known: {', '.join(known)}", file=sys.stderr)
        return 2
    steps = [(scene, *load_scalable_step(data, scene, step)) for scene, step in listed if not names or scene in names]
    print("| step | failed cones | within a hemisphere | would pass | box tests: nc -> tight | "
          "elementary tests: nc -> tight |")
    print("|---|---|---|---|---|---|")
    for name, F, V0, V1, _, _ in steps:
        g = tight_cone_gain(F, V0, V1)
        print(f"| {name} | {g['failed_cones']} | {g['within']} (median {g['within_median_triangles']:g} triangles) | "
              f"{g['would_pass']} | {g['bv_tests']} -> {g['tight_bv_tests']} "
              f"({g['tight_bv_tests'] / max(g['bv_tests'], 1) - 1:+.1%}) | {g['elementary_tests']} -> "
              f"{g['tight_elementary_tests']} ({g['tight_elementary_tests'] / max(g['elementary_tests'], 1) - 1:+.1%}) |")
    print("(DCD at each step's end pose, the BVH built at its start, nc, leaf 2; 'would pass': the contour test "
          "passes about the exact witness axis)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
