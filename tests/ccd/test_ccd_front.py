"""CCD with the BVTT front methods: over a sequence of steps (fronts kept from step to step), steps
in random order and unrelated steps, and DCD and CCD queries alternating on one collider, every
method returns exactly the brute force's VF and EE contacts (exact arithmetic), and the front
methods test exactly the primitive pairs of their method without a front."""

import functools

import numpy as np
import pytest

import conecull
from conecull.datasets.generated import fold, grid_sheet
from oracle import brute_force_pairs
from ccd_brute_force import brute_force_ccd

FRONT = {"aabb+front": "aabb", "nc+front": "nc"}


@functools.lru_cache(maxsize=None)
def poses():
    """A rippled 9 x 9 sheet folding from 0.85 pi to 1.3 pi (contacts on most steps)."""
    F, V = grid_sheet(9, 9)
    V = V.copy()
    V[:, 2] = 0.01 * np.sin(9.0 * V[:, 0]) * np.sin(7.0 * V[:, 1])
    return F, [fold(V, a, radius=0.05) for a in np.linspace(0.85 * np.pi, 1.3 * np.pi, 12)]


@functools.lru_cache(maxsize=None)
def expected_ccd(i, j):
    F, P = poses()
    return brute_force_ccd(F, P[i], P[j], "exact")


@functools.lru_cache(maxsize=None)
def expected_dcd(i):
    F, P = poses()
    return frozenset(brute_force_pairs(F, P[i]))


def rows(a):
    return {tuple(r) for r in a.tolist()}


def check_step(cols, i, j, where):
    F, P = poses()
    vf_ref, ee_ref = expected_ccd(i, j)
    res = {m: c.ccd(P[i], P[j], arithmetic="exact", trace=True) for m, c in cols.items()}
    for m, r in res.items():
        assert rows(r.vf) == vf_ref, f"{where} {m}: VF differ"
        assert rows(r.ee) == ee_ref, f"{where} {m}: EE differ"
    for m, base in FRONT.items():
        a, b = res[m], res[base]
        for key in ("vf_candidates", "ee_candidates", "vf_tests", "ee_tests"):
            assert a.stats[key] == b.stats[key], f"{where} {m}: {key} {a.stats[key]} != {b.stats[key]}"
        assert rows(a.trace.vf["pair"]) == rows(b.trace.vf["pair"]) and rows(a.trace.ee["pair"]) == rows(b.trace.ee["pair"])
    return res


def colliders():
    F, _ = poses()
    mesh = conecull.Mesh(F)
    return {m: conecull.SelfCollider(mesh, method=m) for m in conecull.CCD_METHODS}


def test_steps_in_sequence():
    cols = colliders()
    n = len(poses()[1])
    hits = 0
    for k in range(n - 1):
        res = check_step(cols, k, k + 1, f"step {k}")
        hits += bool(len(res["nc"].vf) + len(res["nc"].ee))
        if k:
            for m in FRONT:
                assert res[m].stats["front_entries"] > 0
    assert hits >= (n - 1) // 2


def test_large_motion_between_steps():
    """Steps in random order, and steps spanning the whole fold: the front of the last query is
    far from the new one."""
    cols = colliders()
    n = len(poses()[1])
    rng = np.random.default_rng(7)
    steps = [(int(k), int(k) + 1) for k in rng.permutation(n - 1)]
    steps[3:3] = [(0, n - 1), (n - 1, 0), (2, 9)]
    for i, j in steps:
        check_step(cols, i, j, f"step {i}->{j}")


def test_dcd_and_ccd_alternate_on_one_collider():
    """DCD and CCD queries interleaved: each kind keeps its own front, so repeating a DCD query
    after a CCD one finds its front unchanged; all results exact."""
    cols = colliders()
    F, P = poses()
    n = len(P)
    for k in range(n - 1):
        for m, c in cols.items():
            got = rows(c.dcd(P[k]).pairs)
            assert got == expected_dcd(k), f"dcd {k} {m}"
        check_step(cols, k, k + 1, f"step {k}")
        for m in FRONT:
            s = cols[m].dcd(P[k]).stats
            assert rows(cols[m].dcd(P[k]).pairs) == expected_dcd(k)
            assert s["front_added"] == 0 and s["front_removed"] == 0, (k, m, s["front_added"], s["front_removed"])


@pytest.mark.parametrize("method", list(FRONT))
def test_ccd_front_stats(method):
    F, P = poses()
    col = conecull.SelfCollider(conecull.Mesh(F), method=method)
    contacts = 0
    for k in range(len(P) - 1):
        res = col.ccd(P[k], P[k + 1], arithmetic="float")
        s = res.stats
        # A step with a contact keeps a front (its root is not culled); the first steps, whose
        # normals stay within a hemisphere, may be culled whole by nc+front.
        if len(res.vf) + len(res.ee):
            contacts += 1
            assert s["front_entries"] > 0
        n_nodes = len(col.bvh_arrays()["right"])
        assert s["front_bytes"] == 8 * s["front_entries"] + 24 * s["front_segments"] + 4 * n_nodes
        if k == 0:
            assert s["front_added"] == s["front_entries"] and s["front_removed"] == 0
        else:
            assert s["front_entries"] == prev + s["front_added"] - s["front_removed"], k
        prev = s["front_entries"]
    assert contacts >= (len(P) - 1) // 2


@pytest.mark.parametrize("threads", [1, 2])
def test_untraced_steps_equal_brute_force(threads):
    """check_step traces its queries (one thread, the traced traversal); queries run untraced,
    on one and two threads: over the steps in sequence, a step repeated (the front unchanged),
    a step without motion (V1 = V0: it stops) and a jump across the whole fold, every CCD
    method's contacts equal the brute force's, and the fronts are resumed (fewer box tests
    than without a front on most steps of the sequence)."""
    F, P = poses()
    mesh = conecull.Mesh(F)
    cols = {m: conecull.SelfCollider(mesh, method=m, threads=threads) for m in conecull.CCD_METHODS}
    n = len(P)
    steps = [(k, k + 1) for k in range(n - 1)] + [(n - 2, n - 1), (n - 1, n - 1), (n - 1, n - 1), (0, n - 1), (n - 2, n - 1)]
    saved = {m: 0 for m in FRONT}
    for q, (i, j) in enumerate(steps):
        vf_ref, ee_ref = expected_ccd(i, j)
        res = {m: c.ccd(P[i], P[j], arithmetic="exact") for m, c in cols.items()}
        for m, r in res.items():
            assert rows(r.vf) == vf_ref and rows(r.ee) == ee_ref, f"threads={threads} step {i}->{j} {m}"
        for m, base in FRONT.items():
            s, b = res[m].stats, res[base].stats
            assert (s["vf_tests"], s["ee_tests"]) == (b["vf_tests"], b["ee_tests"]), (q, m)
            if 0 < q < n - 1:
                saved[m] += s["bv_tests"] < b["bv_tests"]
            if q in (n - 1, n + 1):  # the same step as the query before: the front stays as it was
                assert s["front_added"] == 0 and s["front_removed"] == 0, (q, m, s)
    assert all(v >= (n - 2) // 2 for v in saved.values()), saved
