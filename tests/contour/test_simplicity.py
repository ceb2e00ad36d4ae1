"""The simplicity fallback of "nc" (DCD, contour_test_simple.hpp): after Alg. 1 fails, a node is
still culled if its contour projected along l is a simple polygon. Checked against an exact
twin (fractions: every pair of edges, closed segments in the exact projection), against the
cbc test's all-pairs version of the same predicates (the sweep may skip only pairs that cannot
meet), and in the traversal against the brute-force oracle."""

from fractions import Fraction as Fr

import numpy as np
import pytest

import conecull
import exact_twin as ex
from conecull._core import ccd as CC
from conecull._core import contour as CT
from oracle import brute_force_pairs


def _proj(p, l):
    """p projected on the plane perpendicular to l, exactly."""
    p, l = ex.fr3(p), ex.fr3(l)
    k = ex.dot(p, l) / ex.dot(l, l)
    return tuple(p[i] - k * l[i] for i in range(3))


def _on_segment(x, a, b, l):
    """x on the closed projected segment [a, b] (exact)."""
    if ex.side_sign(a, b, x, l) != 0:
        return False
    xa, xb = ex.sub(_proj(x, l), _proj(a, l)), ex.sub(_proj(x, l), _proj(b, l))
    return ex.dot(xa, xb) <= 0


def exact_simple(pts, l) -> bool:
    """The loop projected along l is a simple polygon: non-adjacent edges do not meet (closed
    segments), adjacent ones meet only at their shared vertex. Exact (fractions)."""
    n = len(pts)
    for i in range(n):
        a, b, c = pts[i], pts[(i + 1) % n], pts[(i + 2) % n]
        if ex.side_sign(a, b, c, l) == 0:  # collinear neighbours: they overlap iff they turn back
            ba, bc = ex.sub(_proj(a, l), _proj(b, l)), ex.sub(_proj(c, l), _proj(b, l))
            if ex.dot(ba, bc) > 0 or _proj(a, l) == _proj(b, l) or _proj(c, l) == _proj(b, l):
                return False
    for i in range(n):
        for j in range(i + 2, n):
            if i == 0 and j == n - 1:
                continue  # adjacent through the closing edge
            a, b, c, d = pts[i], pts[(i + 1) % n], pts[j], pts[(j + 1) % n]
            s1, s2 = ex.side_sign(a, b, c, l), ex.side_sign(a, b, d, l)
            s3, s4 = ex.side_sign(c, d, a, l), ex.side_sign(c, d, b, l)
            if s1 * s2 < 0 and s3 * s4 < 0:
                return False
            if (_on_segment(c, a, b, l) or _on_segment(d, a, b, l) or _on_segment(a, c, d, l)
                    or _on_segment(b, c, d, l)):
                return False
    return True


def _loops():
    """Random loops: wobbly circles (simple), with spikes pushed across (often not), bent into a C
    (simple, not star-shaped), on a coarse grid (touching and collinear edges), tilted out of the
    plane of projection, with random axes l."""
    rng = np.random.default_rng(7)
    out = []
    for k in range(160):
        n = int(rng.integers(3, 40))
        t = np.sort(rng.uniform(0, 2 * np.pi, n))
        r = 1 + 0.3 * rng.uniform(-1, 1, n)
        kind = k % 4
        if kind == 1:  # some vertices pushed far across the loop
            r[rng.integers(0, n, 2)] *= -1.5
        if kind == 2:  # a C: the angles squeezed into 300 degrees, a thin inner arc
            t = np.linspace(0, 5.2, n // 2 + 2)
            t = np.concatenate([t, t[::-1]])
            r = np.concatenate([np.full(len(t) // 2, 1.0), np.full(len(t) // 2, 0.7)])
        P = np.stack([r * np.cos(t), r * np.sin(t), 0.05 * rng.uniform(-1, 1, len(t))], axis=1)
        if kind == 3:
            P = np.round(P * 2) / 2  # grid: repeated points, collinear runs, touching edges
        l = np.array([0.0, 0.0, 1.0]) + 0.3 * rng.uniform(-1, 1, 3)
        out.append((P, l))
    return out


@pytest.mark.parametrize("case", range(160))
def test_simplicity_test_matches_exact_twin_and_cbc(case):
    P, l = _loops()[case]
    ids = np.arange(len(P), dtype=np.int32)
    res = CT.simplicity_test(ids, P, l)
    pts = [tuple(p) for p in P]
    truth = exact_simple(pts, tuple(l))
    if res["passed"]:
        assert truth, "passed a loop whose projection is not simple"
    else:
        assert res["reason"] == 7 and 0 <= res["edge"] < len(P) and 0 <= res["other_edge"] < len(P)
    # The sweep skips only pairs that cannot meet: the same answer as all pairs with the same predicates.
    assert res["passed"] == CT.cbc_contour_test(ids, P, l)["passed"]
    if truth and case % 4 != 3:  # off the grid no point lies exactly on another edge's line
        assert res["passed"], "a simple loop in general position failed"


def test_the_loops_cover_both_answers():
    verdicts = [CT.simplicity_test(np.arange(len(P), dtype=np.int32), P, l)["passed"] for P, l in _loops()]
    assert 40 <= sum(verdicts) <= 120, sum(verdicts)


def test_c_shape_is_simple_but_not_star_shaped():
    """An E-shaped loop: Alg. 1 fails (its kernel is empty), the simplicity test passes; pushing
    one vertex across an edge makes it fail, naming a crossing pair."""
    pts = np.array([[0, 0, 0], [3, 0, 0], [3, 1, 0], [1, 1, 0], [1, 2, 0], [3, 2, 0], [3, 3, 0], [0, 3, 0]], float)
    ids = np.arange(len(pts), dtype=np.int32)
    l = np.array([0.0, 0.0, 1.0])
    assert CT.contour_test(ids, pts, l)["reason"] == 2
    assert CT.simplicity_test(ids, pts, l)["passed"]
    pts[4] = [4, 0.5, 0]  # edge (3, 4) now crosses edge (1, 2)
    res = CT.simplicity_test(ids, pts, l)
    assert not res["passed"] and {res["edge"], res["other_edge"]} == {1, 3}
    assert not exact_simple([tuple(p) for p in pts], tuple(l))


@pytest.mark.parametrize("scene,frames", [("crumple", (0, 10, 20, 25, 29))])
def test_nc_with_the_fallback_equals_the_oracle(scene, frames):
    """In the traversal: nodes culled by the fallback (contour_passed_simple > 0), and the
    colliding pairs exactly the brute force's."""
    from conecull.datasets.inputs import load_sequence

    F, X = load_sequence(scene)
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=X.shape[1]), method="nc")
    col.dcd(X[0])
    by_fallback = 0
    for k in frames:
        res = col.dcd(X[k])
        by_fallback += res.stats["contour_passed_simple"]
        assert res.stats["contour_passed_simple"] <= res.stats["contour_passed"]
        assert {tuple(p) for p in res.pairs.tolist()} == brute_force_pairs(F, X[k]), (scene, k)
    assert by_fallback > 0


def test_a_vertex_touching_an_edge_fails():
    """A loop that touches itself at one point (vertex (2, 0) on edge (0, 0)-(4, 0)) is not simple,
    and neither is one pinched at a point (two vertices at (2, 1))."""
    pts = np.array([[0, 0, 0], [4, 0, 0], [4, 3, 0], [2, 0, 0], [1, 3, 0], [0, 3, 0]], float)
    ids = np.arange(len(pts), dtype=np.int32)
    l = np.array([0.0, 0.0, 1.0])
    assert not exact_simple([tuple(p) for p in pts], tuple(l))
    res = CT.simplicity_test(ids, pts, l)
    assert not res["passed"] and {res["edge"], res["other_edge"]} == {0, 2}
    pinched = np.array([[0, 0, 0], [2, 1, 0], [4, 0, 0], [4, 2, 0], [2, 1, 0], [0, 2, 0]], float)
    assert not exact_simple([tuple(p) for p in pinched], tuple(l))
    assert not CT.simplicity_test(ids, pinched, l)["passed"]
    assert not CT.simplicity_test_ccd(ids, pinched, pinched + 0.25, l)["passed"]


def _moving(case):
    """A loop of _loops() and a second pose: moved, turned a little about l and wobbled."""
    P0, l = _loops()[case]
    rng = np.random.default_rng(100 + case)
    c, s = np.cos(0.2), np.sin(0.2)
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    P1 = P0 @ R.T + rng.uniform(-0.5, 0.5, 3) + 0.03 * rng.uniform(-1, 1, P0.shape)
    if case % 4 == 3:
        P1 = np.round(P1 * 2) / 2
    return P0, P1, l


@pytest.mark.parametrize("case", range(0, 160, 2))
def test_simplicity_test_ccd_matches_exact_twin_and_cbc(case):
    """Over a step: passed only if the projected loop is simple at t = 0, 1/3, 1/2 and 1 (exact
    points at rational t), and passed wherever cbc's all-pairs continuous test passes. (Not iff:
    cbc's continuous predicates are conservative, and a pair the sweep skips, its extents apart
    over the whole step, may be one they cannot prove apart.)"""
    P0, P1, l = _moving(case)
    ids = np.arange(len(P0), dtype=np.int32)
    res = CT.simplicity_test_ccd(ids, P0, P1, l)
    by_cbc = CT.cbc_contour_test_ccd(ids, P0, P1, l)["passed"]
    if by_cbc:
        assert res["passed"]
    if res["passed"]:
        # Passed beyond cbc (extents apart over the step, turns proven in the (g, h) coordinates):
        # checked at 7 times.
        times = (Fr(0), Fr(1, 3), Fr(1, 2), Fr(1)) if by_cbc else tuple(Fr(k, 6) for k in range(7))
        for t in times:
            pts = [ex.lerp(p0, p1, t) for p0, p1 in zip(P0, P1)]
            assert exact_simple(pts, tuple(l)), f"passed, but not simple at t = {t}"


def test_the_moving_loops_cover_both_answers():
    verdicts = [CT.simplicity_test_ccd(np.arange(len(P0), dtype=np.int32), P0, P1, l)["passed"]
                for P0, P1, l in map(_moving, range(0, 160, 2))]
    assert 15 <= sum(verdicts) <= 75, sum(verdicts)  # 73 of 80: the loops pushed across fail


def test_nc_ccd_with_the_fallback_equals_the_brute_force():
    """CCD in the traversal: steps of crumple where the fallback culls nodes, with exactly the
    brute force's contacts (exact arithmetic)."""
    from ccd_brute_force import brute_force_ccd
    from conecull.datasets.inputs import load_sequence

    F, X = load_sequence("crumple")
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=X.shape[1]), method="nc")
    col.dcd(X[0])
    by_fallback = 0
    for k in (5, 28):
        res = col.ccd(X[k], X[k + 1])
        by_fallback += res.stats["contour_passed_simple"]
        vf, ee = brute_force_ccd(F, X[k], X[k + 1], "exact")
        assert {tuple(p) for p in res.vf.tolist()} == vf and {tuple(p) for p in res.ee.tolist()} == ee, k
    assert by_fallback > 0


def test_nc_runs_first_the_test_that_proved_the_node_last():
    """FirstTest: "nc" remembers per node which test proved it and runs that one first in the next
    query. The same frame twice on a fresh collider: the same pairs, culled nodes and nodes proved
    by the simplicity test; the second time those skip Alg. 1's attempt with the mean (no kernel
    point in their events), and the edge counts drop by exactly that attempt's edges, node by
    node (the single-loop binding with and without simplicity_first). The explanations say which
    way each was proved."""
    from conecull.datasets.inputs import load_sequence
    from conecull.viz.explain import explain_node

    F, X = load_sequence("crumple")
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=X.shape[1]), method="nc")
    first = col.dcd(X[20], trace=True)  # builds the BVH: every node tries Alg. 1 first
    again = col.dcd(X[20], trace=True)
    assert np.array_equal(first.pairs, again.pairs)
    for key in ("contour_tests", "contour_passed", "contour_passed_simple", "contour_failed"):
        assert first.stats[key] == again.stats[key], key
    c1, c2 = first.trace.contour, again.trace.contour
    assert np.array_equal(c1["node"], c2["node"]) and np.array_equal(c1["simple"], c2["simple"])
    simple = c1["simple"]
    assert simple.sum() > 0 and (~simple & (c1["reason"] == 0)).sum() > 0
    assert np.isfinite(c1["kernel"]).all()  # Alg. 1 ran first everywhere
    assert np.isnan(c2["kernel"][simple]).all() and np.isnan(c2["ray"][simple]).all()
    assert np.isfinite(c2["kernel"][~simple]).all()
    ct, axes = col.contour_arrays(), col.cone_arrays()["axis"]
    saved = 0
    for node in c1["node"][simple]:
        loop = ct["vertices"][ct["offsets"][node]:ct["offsets"][node + 1]].astype(np.int32)
        star_first = CT.nc_contour_test(loop, X[20], axes[node])
        sweep_first = CT.nc_contour_test(loop, X[20], axes[node], simplicity_first=True)
        assert star_first["passed"] and star_first["simple"] and sweep_first["passed"] and sweep_first["simple"]
        assert sweep_first["edges_visited"] == CT.simplicity_test(loop, X[20], axes[node])["edges_visited"]
        saved += star_first["edges_visited"] - sweep_first["edges_visited"]
    assert saved > 0 and first.stats["contour_edges"] - again.stats["contour_edges"] == saved
    node = int(c1["node"][np.flatnonzero(simple)[0]])
    text1, text2 = explain_node(col, first, node), explain_node(col, again, node)
    assert "not star-shaped from its kernel point, but it projects to a simple polygon" in text1
    assert "the simplicity test, run first" in text2 and "kernel point" not in text2
    assert "verdict: culled, passed: the contour projects to a simple polygon" in text2
    # ... and a node proved by Alg. 1 keeps it first.
    star = int(c1["node"][np.flatnonzero(~simple & (c1["reason"] == 0))[0]])
    assert "star-shaped polygon around its kernel point" in explain_node(col, again, star)


def test_trace_and_explain_name_the_fallback():
    """The trace marks the nodes the fallback culled (contour event field `simple`, reason 0), as
    many as the stats count, and `explain` says why such a node was culled."""
    from conecull.datasets.inputs import load_sequence
    from conecull.viz.explain import explain_node

    F, X = load_sequence("crumple")
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=X.shape[1]), method="nc")
    col.dcd(X[0])
    res = col.dcd(X[20], trace=True)
    c = res.trace.contour
    assert c["simple"].dtype == bool and c["simple"].sum() == res.stats["contour_passed_simple"] > 0
    assert (c["reason"][c["simple"]] == 0).all()
    node = int(c["node"][np.flatnonzero(c["simple"])[0]])
    assert "verdict: culled, passed: the contour is not star-shaped from its kernel point, but it projects to a " \
           "simple polygon" in explain_node(col, res, node)
    star = int(c["node"][np.flatnonzero((c["reason"] == 0) & ~c["simple"])[0]])
    assert "star-shaped polygon around its kernel point" in explain_node(col, res, star)


def test_the_sweep_gives_up_on_crowded_contours():
    """A star of 300 long spikes: every edge spans most of the sweep's axis, so nearly every pair
    of its 600 edges overlaps there. The sweep stops after 64 pairs per edge and answers "not
    proven" (never a guess), though the loop is simple: cbc's all-pairs test passes it, and so does
    Alg. 1, which is what culls such a star in the traversal (the fallback only runs after it)."""
    t = np.linspace(0, 2 * np.pi, 600, endpoint=False)
    r = np.where(np.arange(600) % 2 == 0, 10.0, 1.0)
    P = np.stack([r * np.cos(t), r * np.sin(t), np.zeros(600)], axis=1)
    ids = np.arange(600, dtype=np.int32)
    l = np.array([0.0, 0.0, 1.0])
    res = CT.simplicity_test(ids, P, l)
    assert not res["passed"] and res["reason"] == 7
    assert res["edges_visited"] <= 2 * 600 + 2 * 64 * 600
    assert CT.cbc_contour_test(ids, P, l)["passed"] and CT.contour_test(ids, P, l)["passed"]


def _lopsided_star():
    """600 edges: 150 spikes of radius 10 on one half-turn, the other vertices on the unit circle.
    Star-shaped around the origin (its kernel has an interior there), but the mean, pulled to
    (0, 1.43), is outside the kernel; and the spikes crowd the sweep, which gives up."""
    t = np.linspace(0, 2 * np.pi, 600, endpoint=False)
    r = np.where((np.arange(600) % 2 == 0) & (t < np.pi), 10.0, 1.0)
    return np.stack([r * np.cos(t), r * np.sin(t), np.zeros(600)], axis=1)


def _mean(P):
    return np.array(ex.float_mean([tuple(p) for p in P]))  # the core's mean, bit for bit


def _mean_only(ids, P, l):
    """Alg. 1 at the mean alone (contour_test with o fixed to the mean: no kernel search)."""
    return CT.contour_test(ids, P, l, o=_mean(P))


def test_nc_order_mean_then_simplicity_then_kernel_search():
    """The test "nc" runs in its traversal (with_simplicity_fallback): Alg. 1 with the mean; where it
    fails, the simplicity test; the kernel-point search only where that gave up (DCD). Its edge
    counts add up attempt by attempt, so they show which ran."""
    l = np.array([0.0, 0.0, 1.0])
    # E-shape: the mean fails, the simplicity test passes; no kernel search.
    E = np.array([[0, 0, 0], [3, 0, 0], [3, 1, 0], [1, 1, 0], [1, 2, 0], [3, 2, 0], [3, 3, 0], [0, 3, 0]], float)
    ids = np.arange(len(E), dtype=np.int32)
    res = CT.nc_contour_test(ids, E, l)
    assert res["passed"] and res["simple"]
    assert res["edges_visited"] == _mean_only(ids, E, l)["edges_visited"] + CT.simplicity_test(ids, E, l)["edges_visited"]
    # Lopsided star: the mean fails, the sweep gives up, the kernel search passes it.
    P = _lopsided_star()
    ids = np.arange(len(P), dtype=np.int32)
    first, sweep, full = _mean_only(ids, P, l), CT.simplicity_test(ids, P, l), CT.contour_test(ids, P, l)
    assert not first["passed"] and not sweep["passed"] and full["passed"]
    res = CT.nc_contour_test(ids, P, l)
    assert res["passed"] and not res["simple"]
    assert res["edges_visited"] == sweep["edges_visited"] + full["edges_visited"]
    # Not simple (an edge crosses another): the pair test proves it in one pose, no kernel search.
    E[4] = [4, 0.5, 0]
    ids = np.arange(len(E), dtype=np.int32)
    res = CT.nc_contour_test(ids, E, l)
    assert not res["passed"] and not res["simple"]
    assert res["edges_visited"] == _mean_only(ids, E, l)["edges_visited"] + CT.simplicity_test(ids, E, l)["edges_visited"]
    # Over a step the pair predicates are conservative, so the search runs after any failure.
    res = CT.nc_contour_test_ccd(ids, E, E + 0.01, l)
    assert not res["passed"]
    mean_ccd = CC.contour_test_ccd(ids, E, E + 0.01, l, o=_mean(E), o1=_mean(E + 0.01))
    swept = CT.simplicity_test_ccd(ids, E, E + 0.01, l)
    assert not mean_ccd["passed"] and not swept["passed"]
    assert res["edges_visited"] > swept["edges_visited"] + mean_ccd["edges_visited"]
    P1 = P + 0.001
    res = CT.nc_contour_test_ccd(np.arange(600, dtype=np.int32), P, P1, l)
    assert res["passed"] and not res["simple"]


def test_nc_order_with_the_simplicity_test_first():
    """simplicity_first (a node the simplicity test proved when last tested): the simplicity
    test; where it fails, Alg. 1 with the mean, then the kernel-point search where the simplicity
    test gave up. A failure reports Alg. 1's verdict, as with Alg. 1 first."""
    l = np.array([0.0, 0.0, 1.0])
    E = np.array([[0, 0, 0], [3, 0, 0], [3, 1, 0], [1, 1, 0], [1, 2, 0], [3, 2, 0], [3, 3, 0], [0, 3, 0]], float)
    ids = np.arange(len(E), dtype=np.int32)
    res = CT.nc_contour_test(ids, E, l, simplicity_first=True)
    assert res["passed"] and res["simple"] and np.isnan(res["kernel"]).all() and np.isnan(res["ray"]).all()
    assert res["edges_visited"] == CT.simplicity_test(ids, E, l)["edges_visited"]
    # Lopsided star: the sweep gives up, the mean fails, the kernel search passes it.
    P = _lopsided_star()
    pids = np.arange(len(P), dtype=np.int32)
    sweep, full = CT.simplicity_test(pids, P, l), CT.contour_test(pids, P, l)
    res = CT.nc_contour_test(pids, P, l, simplicity_first=True)
    assert res["passed"] and not res["simple"]
    assert res["edges_visited"] == sweep["edges_visited"] + full["edges_visited"]
    # Not simple: the pair test proves it; Alg. 1 runs for the verdict, no kernel search.
    E[4] = [4, 0.5, 0]
    res = CT.nc_contour_test(ids, E, l, simplicity_first=True)
    star = CT.nc_contour_test(ids, E, l)
    mean = _mean_only(ids, E, l)
    assert not res["passed"] and not res["simple"]
    for key in ("reason", "edge", "crossings"):
        assert res[key] == star[key] == mean[key], key
    assert np.array_equal(res["kernel"], mean["kernel"]) and np.array_equal(res["ray"], mean["ray"])
    assert res["edges_visited"] == star["edges_visited"]
    # Over a step: the sweep, then Alg. 3 and the search after any failure.
    res = CT.nc_contour_test_ccd(ids, E, E + 0.01, l, simplicity_first=True)
    assert not res["passed"] and res["edges_visited"] == CT.nc_contour_test_ccd(ids, E, E + 0.01, l)["edges_visited"]
    ok = CT.nc_contour_test_ccd(ids[:4], E[:4], E[:4] + 0.01, l, simplicity_first=True)
    assert ok["passed"] and ok["simple"] and np.isnan(ok["kernel_end"]).all()
    res = CT.nc_contour_test_ccd(pids, P, P + 0.001, l, simplicity_first=True)
    assert res["passed"] and not res["simple"]


def test_sweep_and_nc_agree_with_all_pairs_on_adversarial_loops():
    """2000 loops (random, pushed across, on a coarse grid, scaled by 1e-20..1e20 and offset, with a
    repeated point, with long collinear runs; axes of any length): the swept test answers as cbc's
    all-pairs test with the same predicates (it skips only pairs proven apart, and settles turns
    only where the (g, h) bound proves them), nc's traversal test passes exactly where the
    simplicity test or Alg. 1 with its kernel search does, and over a step the sweep passes
    wherever cbc does."""
    rng = np.random.default_rng(123)
    passed = 0
    for k in range(2000):
        n = int(rng.integers(3, 60))
        kind = k % 6
        t = np.sort(rng.uniform(0, 2 * np.pi, n))
        r = 1 + 0.3 * rng.uniform(-1, 1, n)
        if kind == 1:
            r[rng.integers(0, n, 2)] *= -1.5
        P = np.stack([r * np.cos(t), r * np.sin(t), 0.05 * rng.uniform(-1, 1, n)], 1)
        if kind == 2:
            P = np.round(P * 3) / 3
        if kind == 3:
            P = P * 10.0 ** rng.uniform(-20, 20) + 10.0 ** rng.uniform(-5, 5) * rng.uniform(-1, 1, 3)
        if kind == 4:
            P[rng.integers(0, n)] = P[rng.integers(0, n)]
        if kind == 5:
            P[:, 0] = np.round(P[:, 0])
            P[:, 1] = np.round(P[:, 1] * 2) / 2
        l = np.array([0, 0, 1.0]) + 0.3 * rng.uniform(-1, 1, 3)
        if k % 7 == 0:
            l = l * 10.0 ** rng.uniform(-3, 3)
        ids = np.arange(n, dtype=np.int32)
        swept = CT.simplicity_test(ids, P, l)["passed"]
        assert swept == CT.cbc_contour_test(ids, P, l)["passed"], k
        assert CT.nc_contour_test(ids, P, l)["passed"] == (swept or CT.contour_test(ids, P, l)["passed"]), k
        Q = P + 0.05 * rng.uniform(-1, 1, P.shape)
        if CT.cbc_contour_test_ccd(ids, P, Q, l)["passed"]:
            assert CT.simplicity_test_ccd(ids, P, Q, l)["passed"], k
        passed += swept
    assert 400 <= passed <= 1600, passed  # both answers, often


def _folded_triangles(count, seed):
    """Loops (a, b, c) exactly collinear in space, c on the segment [b, a]: a = b + 3w, c = b + w with
    b, w dyadic (exact sums). The loop folds back on itself at b and at a. The ratio 3 : 1 is not
    kept by rounding, so the rounded (g, h) turns are noise: only the bound keeps them unproven."""
    rng = np.random.default_rng(seed)
    for _ in range(count):
        b = np.round(rng.uniform(-1, 1, 3) * 2**20) / 2**20
        w = np.round(rng.uniform(-1, 1, 3) * 2**20) / 2**20
        yield np.array([b + 3 * w, b, b + w]), rng.uniform(-1, 1, 3)


def test_turns_within_rounding_are_never_proven():
    """Folded loops fail, in one pose and over a step (b and w moving linearly keep them collinear
    at every t); a build with turn_apart's bound set to 0 passes 2178 of these 3000 (measured)."""
    ids = np.arange(3, dtype=np.int32)
    for P, l in _folded_triangles(3000, 5):
        assert not CT.simplicity_test(ids, P, l)["passed"]
        assert not CT.nc_contour_test(ids, P, l)["passed"]
    for (P0, l), (P1, _) in zip(_folded_triangles(300, 6), _folded_triangles(300, 7)):
        assert not CT.simplicity_test_ccd(ids, P0, P1, l)["passed"]


_EPS = 1.1102230246251565e-16  # kEps


def _swept_pairs(poses, l):
    """The pairs of non-adjacent edges the sweep must examine: those whose rounded extents along g
    and along h are not apart by more than its gap. The core's floats replicated operation by
    operation (its Z_g, Z_h per vertex and pose, the hull of an edge's ends over the poses, D1 and
    the gap; IEEE doubles, no FMA, as the core is built), then the rule applied to every pair: a
    model of which pairs the runs' walk reaches, without the runs."""
    l = tuple(float(x) for x in l)
    u, w, _, _ = ex._frame(l)
    c = tuple(float(x) for x in poses[0][0])
    n, d1, phi = len(poses[0]), 0.0, ex.SWEEP_PHI
    Z = []  # per vertex: (g, h) per pose
    for i in range(n):
        z = []
        for P in poses:
            x, y, n1 = ex._fproject(tuple(float(x) for x in P[i]), c, u, w)
            d1 = max(d1, n1)
            z.append((x + phi * y, y - phi * x))
        Z.append(z)
    gap = 64.0 * _EPS * d1 * ex._frame_scale(l, u, w)
    ext = []
    for i in range(n):
        zs = Z[i] + Z[(i + 1) % n]
        ext.append((min(p[0] for p in zs), max(p[0] for p in zs), min(p[1] for p in zs), max(p[1] for p in zs)))
    count = 0
    for i in range(n):
        for j in range(i + 2, n):
            if i == 0 and j == n - 1:
                continue
            a, b = ext[i], ext[j]
            if not (b[0] - a[1] > gap or a[0] - b[1] > gap or b[2] - a[3] > gap or a[2] - b[3] > gap):
                count += 1
    return count


def _far_spike_loop():
    """A 40-gon of radius 0.1 with one vertex 1e14 away (pointing outward, so the loop stays
    simple). D1, and so the sweep's gap, is about 1e14 x 2^-53 x 64 ~ 1: the whole 40-gon lies within
    the gap, and every step along g of its runs too."""
    t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    P = np.stack([0.1 * np.cos(t), 0.1 * np.sin(t), np.zeros(40)], axis=1)
    far = [[1e14 * np.cos(0.23), 1e14 * np.sin(0.23), 0.0]]
    return np.concatenate([P[:2], far, P[2:]]), np.array([0.0, 0.0, 1.0])


def test_the_runs_walk_examines_exactly_the_pairs_not_apart():
    """The sweep cuts the loop into runs monotone along g and walks pairs of runs whose boxes meet;
    within a run it examines no pair. On every passing loop of _loops() (one pose) and of _moving()
    (a step), the pairs it examined with the predicates (edges_visited: 2 per turn, 2 per pair) are
    exactly those the plain rule leaves: extents not apart along g or h (_swept_pairs). A walk that
    missed a pair, or a run whose order was trusted within rounding, would count fewer."""
    checked = 0
    for case in range(160):
        P, l = _loops()[case]
        ids = np.arange(len(P), dtype=np.int32)
        res = CT.simplicity_test(ids, P, l)
        if res["passed"]:
            assert res["edges_visited"] == 2 * len(P) + 2 * _swept_pairs([P], l), case
            checked += 1
        if case % 2 == 0:
            P0, P1, l = _moving(case)
            res = CT.simplicity_test_ccd(ids, P0, P1, l)
            if res["passed"]:
                assert res["edges_visited"] == 2 * len(P0) + 2 * _swept_pairs([P0, P1], l), case
                checked += 1
    assert checked >= 60, checked
    # Rounding as large as a run's steps (_far_spike_loop): no run order is trusted, every pair of
    # the 40-gon is examined, as cbc's all-pairs test does (a build that trusts the runs examines
    # 1146 / 2 - 41 pairs instead of 779: measured).
    P, l = _far_spike_loop()
    ids = np.arange(len(P), dtype=np.int32)
    res, by_cbc = CT.simplicity_test(ids, P, l), CT.cbc_contour_test(ids, P, l)
    assert res["passed"] and by_cbc["passed"]
    assert res["edges_visited"] == by_cbc["edges_visited"] == 2 * len(P) + 2 * _swept_pairs([P], l)


def _pass_model(P, ids, l):
    """The one-pose pass replicated in Python floats (IEEE doubles, as the core is built: no FMA):
    Z_g, Z_h per vertex of the loop (two wrapped), the largest |p - c|_1, the turn margin at each
    vertex (turn_margin<1>: max(-dot, |cross|) of the vectors to the two neighbours) and their
    least, + 0.0 as the core returns it (a zero is +0)."""
    l = tuple(float(x) for x in l)
    u, w, _, _ = ex._frame(l)
    c = tuple(float(x) for x in P[ids[0]])
    zg, zh, norms = [], [], []
    for i in ids:
        x, y, n1 = ex._fproject(tuple(float(v) for v in P[i]), c, u, w)
        norms.append(n1)
        zg.append(x + ex.SWEEP_PHI * y)
        zh.append(y - ex.SWEEP_PHI * x)
    n = len(ids)
    turns = []
    for b in range(n):
        a, cc = (b - 1) % n, (b + 1) % n
        ag, ah, cg, ch = zg[a] - zg[b], zh[a] - zh[b], zg[cc] - zg[b], zh[cc] - zh[b]
        dot, cr = ag * cg + ah * ch, ag * ch - ah * cg
        turns.append(max(-dot, cr, -cr))
    return zg + zg[:2], zh + zh[:2], max(norms), min(turns) + 0.0, norms, turns


def _bits(x):
    return np.asarray(x, dtype=np.float64).view(np.uint64).tolist()


def _pass_cases():
    """(P, ids, l): _loops()'s first 40 shapes and random loops of 3 to 19 vertices over 40 orders of
    magnitude; then, for every n from 3 to 12 and every vertex k, a random loop whose least turn is
    at k alone and one whose farthest vertex from vertex 0 is k alone (so that a turn or a vertex
    the pass skips, or a lane its reductions drop, changes the answer). Ids scattered over a
    larger array (the gathers)."""
    rng = np.random.default_rng(11)
    shapes = list(_loops()[:40])
    for n in range(3, 20):
        shapes.append((rng.standard_normal((n, 3)) * np.exp(rng.uniform(-20, 20, (n, 1))), rng.standard_normal(3)))
    for n in range(3, 13):
        for k in range(n):
            for want in ("turn", "far"):
                if want == "far" and k == 0:
                    continue  # vertex 0 is c: |p - c|_1 = 0
                while True:
                    P, l = rng.standard_normal((n, 3)), rng.standard_normal(3)
                    *_, norms, turns = _pass_model(P, np.arange(n), l)
                    v = np.array(turns if want == "turn" else norms)
                    best = v.min() if want == "turn" else v.max()
                    if np.flatnonzero(v == best).tolist() == [k]:
                        shapes.append((P, l))
                        break
    for P, l in shapes:
        n = len(P)
        big = rng.standard_normal((3 * n + 5, 3))
        ids = rng.permutation(len(big))[:n].astype(np.int32)
        big[ids] = P
        yield big, ids, l


def _check_pass(portable):
    count = 0
    for big, ids, l in _pass_cases():
        zg, zh, d1, margin, *_ = _pass_model(big, ids, l)
        got = CT.simplicity_pass(ids, big, l, portable=portable)
        assert _bits(got[0]) == _bits(zg) and _bits(got[1]) == _bits(zh), (len(ids), portable)
        assert _bits(got[2]) == _bits(d1) and _bits(got[3]) == _bits(margin), (len(ids), portable)
        count += 1
    assert count == 57 + 2 * sum(range(3, 13)) - 10


def test_the_one_pose_pass_portable_path_equals_the_float_model():
    """simplicity_pass's portable path gives the float model's numbers bit for bit (_pass_cases):
    its arrays, D1 and least turn margin. The binding fills its buffers with NaN first, so an entry
    the pass never writes shows."""
    _check_pass(portable=True)


@pytest.mark.skipif(not CT.simplicity_pass_vectorised(), reason="this CPU has no AVX2: the portable path runs")
def test_the_one_pose_pass_avx2_path_equals_the_float_model():
    """The AVX2 path (four vertices at a time, gathers, lane reductions and a scalar tail) gives the
    same bits as the model and the portable path on every case, including a zero margin, returned
    as +0 by both (a turn straight back gives +0, a zero-length edge -0; the lanes meet them in
    another order than the loop)."""
    _check_pass(portable=False)
    # Both zeros in one loop: vertex 3 equals vertex 1 (a turn straight back at 2: +0) and vertex 6
    # equals vertex 5 (a zero-length edge: -0).
    t = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    P = np.stack([np.cos(t), np.sin(t), np.zeros(8)], axis=1)
    P[3], P[6] = P[1], P[5]
    ids, l = np.arange(8, dtype=np.int32), np.array([0.0, 0.0, 1.0])
    for portable in (False, True):
        assert _bits(CT.simplicity_pass(ids, P, l, portable=portable)[3]) == _bits(0.0)
