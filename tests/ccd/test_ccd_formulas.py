"""Sec. 3.6 formulas checked against exact arithmetic: the Bernstein coefficients of CSide1
(and the printed k2's sign error), CSideSign1/2, Alg. 3, and CCD normal cones for every t."""

from fractions import Fraction as Fr

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

import exact_twin as ex
from conecull._core import ccd as C
from contour.test_contour import _sideways_spike, projected_simple

coord = st.floats(-2.0, 2.0, allow_nan=False).map(lambda x: 0.0 if abs(x) < 2.0**-100 else x)
pt = st.tuples(coord, coord, coord)
TS = [Fr(0), Fr(1, 7), Fr(1, 3), Fr(1, 2), Fr(5, 7), Fr(1)]


def bern2(k, t):
    return k[0] * (1 - t) ** 2 + 2 * k[1] * t * (1 - t) + k[2] * t ** 2


@settings(max_examples=300, deadline=None)
@given(pt, pt, pt, pt, pt, pt, st.one_of(st.none(), pt))
def test_cside1_bernstein_coefficients(o, b0, c0, b1, c1, l, o1):
    """Fixed kernel point (o1 None, as printed) and moving (o -> o1, as the core runs it)."""
    k = ex.cside1_coefficients(o, b0, c0, b1, c1, l, o1)
    for t in TS:
        assert bern2(k, t) == ex.cside1_value(o, b0, c0, b1, c1, l, t, o1)


def test_printed_k2_has_a_sign_error():
    """The printed k2 uses v_c x (b0 - a) where (b0 - a) x v_c is right: it is not CSide1 at t = 1
    unless (b0 - a) x v_c . l happens to vanish."""
    rng = np.random.default_rng(0)
    wrong = 0
    for _ in range(200):
        o, b0, c0, b1, c1, l = rng.standard_normal((6, 3))
        f1 = ex.cside1_value(o, b0, c0, b1, c1, l, Fr(1))
        assert ex.cside1_coefficients(o, b0, c0, b1, c1, l)[2] == f1
        wrong += ex.cside1_printed_k2(o, b0, c0, b1, c1, l) != f1
    assert wrong == 200


def rows(*p):
    return [np.array([q], float) for q in p]


@st.composite
def near_degenerate_motion(draw):
    """Moving edges with exact degeneracies: lattice points, edges through o, no motion."""
    lat = st.integers(-2, 2).map(float)
    lp = st.tuples(lat, lat, lat)
    o, b0, c0 = draw(lp), draw(lp), draw(lp)
    b1 = draw(st.one_of(st.just(b0), lp))
    c1 = draw(st.one_of(st.just(c0), lp))
    l = draw(st.sampled_from([(0.0, 0.0, 1.0), (0.0, 1.0, 0.0), (0.6, 0.0, 0.8)]))
    return o, b0, c0, b1, c1, l


@settings(max_examples=800, deadline=None)
@given(st.one_of(st.tuples(pt, pt, pt, pt, pt, pt), near_degenerate_motion()),
       st.one_of(st.none(), pt, st.tuples(*[st.integers(-2, 2).map(float)] * 3)))
def test_csidesign1_matches_exact(args, o1):
    """Kernel point fixed (o1 None) or moving from o to o1 (lattice ends: exact degeneracies)."""
    o, b0, c0, b1, c1, l = args
    got = C.csidesign1(*rows(o, b0, c0, b1, c1, l)) if o1 is None else C.csidesign1(*rows(o, b0, c0, b1, c1, l),
                                                                                    o1=np.array([o1], float))
    assert got[0] == ex.csidesign1(o, b0, c0, b1, c1, l, o1)


@st.composite
def moving_loops(draw):
    n = draw(st.integers(3, 9))
    l = np.array([0.0, 0.0, 1.0]) if draw(st.booleans()) else np.array([0.36, 0.0, 0.48]) / 0.6
    ang = np.sort(np.array([draw(st.floats(0, 2 * np.pi)) for _ in range(n)]))
    rad = np.array([draw(st.floats(0.3, 1.0)) for _ in range(n)])
    z = np.array([draw(st.floats(-0.5, 0.5)) for _ in range(n)])
    u = np.cross(l, [0.3, 0.7, 0.1])
    u /= np.linalg.norm(u)
    w = np.cross(l, u)
    P0 = rad[:, None] * (np.cos(ang)[:, None] * u + np.sin(ang)[:, None] * w) + z[:, None] * l
    amp = draw(st.sampled_from([0.0, 0.05, 0.3, 1.5]))
    D = np.array([[draw(st.floats(-1, 1)) for _ in range(3)] for _ in range(n)]) * amp
    if draw(st.booleans()):  # a twist that can turn the loop inside out
        D = D + draw(st.floats(-2, 2)) * np.cross(l, P0)
    P1 = P0 + D
    for P in (P0, P1):  # the cancellations above can leave values far below 2^-128 (the core refuses them)
        P[np.abs(P) < 2.0**-100] = 0.0
    return P0, P1, l


@settings(max_examples=300, deadline=None)
@given(moving_loops())
def test_contour_test_ccd_matches_twin_and_is_sound(args):
    P0, P1, l = args
    ids = np.arange(len(P0), dtype=np.int32)
    Q0, Q1 = [tuple(p) for p in P0], [tuple(p) for p in P1]
    m0, m1 = ex.float_mean(Q0), ex.float_mean(Q1)
    # Alg. 3 as printed (the mean at t = 0, fixed) against the twin, with the core's ray ...
    fixed = C.contour_test_ccd(ids, P0, P1, l, o=np.array(m0))
    assert fixed["kernel_end"] == fixed["kernel"] == m0
    assert (fixed["passed"], fixed["reason"]) == ex.contour_test_ccd(Q0, Q1, tuple(l), fixed["ray"], o=m0)[:2]
    # ... the core's first attempt, the mean moving from t = 0 to t = 1 ...
    first = C.contour_test_ccd(ids, P0, P1, l, o=np.array(m0), o1=np.array(m1))
    passed, reason, edge = ex.contour_test_ccd(Q0, Q1, tuple(l), first["ray"])
    assert (first["passed"], first["reason"]) == (passed, reason)
    if reason in (1, 2, 3, 4):
        assert first["edge"] == edge  # where the retry's clipping starts
    # ... and the core's full test: after a kernel failure, a kernel point of the loop at t = 0
    # moving to one of the loop at t = 1 (the clipped kernels' points), if both ends have one.
    res = C.contour_test_ccd(ids, P0, P1, l)
    o2 = ex.retry_kernel(reason, edge, Q0, tuple(l))
    o2_end = ex.retry_kernel(reason, edge, Q1, tuple(l)) if o2 is not None else None
    if o2_end is None:
        assert (res["passed"], res["reason"], res["kernel"], res["kernel_end"]) == (
            first["passed"], first["reason"], m0, m1)
    else:
        assert (res["kernel"], res["kernel_end"]) == (o2, o2_end)
        assert (res["passed"], res["reason"]) == ex.contour_test_ccd(Q0, Q1, tuple(l), res["ray"], o=o2, o1=o2_end)[:2]
    if res["passed"]:
        for t in TS:
            Pt = [tuple(float(c) for c in ex.lerp(p0, p1, t)) if t in (0, 1) else ex.lerp(p0, p1, t)
                  for p0, p1 in zip(P0, P1)]
            assert projected_simple_exact(Pt, l), f"passed, but the contour is not simple at t = {t}"


def test_ccd_kernel_retry_on_a_moving_spiked_star():
    """The spiked star of tests/contour (mean outside the kernel) translated and slightly turned
    over the step: Alg. 3 with the mean fails, the clipped kernels' points at t = 0 and t = 1
    pass, and the twin agrees on them."""
    l = np.array([0.0, 0.0, 1.0])
    P0 = np.array([[1, 0, 0], [0.7, 0.7, 0], [0.1, 0.9, 0], [0.05, 6, 0], [0, 6.2, 0], [-0.05, 6, 0], [-0.1, 0.9, 0],
                   [-0.7, 0.7, 0], [-1, 0, 0], [-0.7, -0.7, 0], [0, -1, 0], [0.7, -0.7, 0]], float)
    P1 = P0 + np.array([0.01, -0.02, 0.3]) + 0.002 * np.cross(l, P0)
    ids = np.arange(len(P0), dtype=np.int32)
    Q0, Q1 = [tuple(p) for p in P0], [tuple(p) for p in P1]
    assert not C.contour_test_ccd(ids, P0, P1, l, o=np.array(ex.float_mean(Q0)))["passed"]
    first = C.contour_test_ccd(ids, P0, P1, l, o=np.array(ex.float_mean(Q0)), o1=np.array(ex.float_mean(Q1)))
    assert not first["passed"]
    res = C.contour_test_ccd(ids, P0, P1, l)
    e = first["edge"]
    o2, o2_end = ex.clipped_kernel_candidate(Q0, tuple(l), e)[1], ex.clipped_kernel_candidate(Q1, tuple(l), e)[1]
    assert res["passed"] and res["kernel"] == o2 and res["kernel_end"] == o2_end
    assert ex.contour_test_ccd(Q0, Q1, tuple(l), res["ray"], o=o2, o1=res["kernel_end"])[0]


def test_moving_kernel_point_culls_a_translating_loop():
    """A convex loop sliding across the plane by three times its size over the step: with the
    kernel point fixed (as printed) the loop leaves it, so the test fails; the mean moving with
    the loop passes, and the twin agrees with both verdicts."""
    l = np.array([0.0, 0.0, 1.0])
    ang = np.linspace(0, 2 * np.pi, 7)[:-1]
    P0 = np.stack([np.cos(ang), np.sin(ang), 0.1 * np.sin(3 * ang)], axis=1)
    P1 = P0 + np.array([3.0, 1.0, 0.5])
    ids = np.arange(len(P0), dtype=np.int32)
    Q0, Q1 = [tuple(p) for p in P0], [tuple(p) for p in P1]
    m0 = ex.float_mean(Q0)
    fixed = C.contour_test_ccd(ids, P0, P1, l, o=np.array(m0))
    assert not fixed["passed"]
    assert (fixed["passed"], fixed["reason"]) == ex.contour_test_ccd(Q0, Q1, tuple(l), fixed["ray"], o=m0)[:2]
    res = C.contour_test_ccd(ids, P0, P1, l)
    assert res["passed"] and res["kernel"] == m0 and res["kernel_end"] == ex.float_mean(Q1)
    assert ex.contour_test_ccd(Q0, Q1, tuple(l), res["ray"])[0]


def test_contour_test_ccd_o1_needs_o():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    with pytest.raises(ValueError, match="o1"):
        C.contour_test_ccd(np.arange(3, dtype=np.int32), V, V, np.array([0.0, 0.0, 1.0]), o1=np.zeros(3))


def projected_simple_exact(points, l):
    """projected_simple on exact (Fraction) points."""
    return projected_simple([tuple(float(c) for c in p) for p in points], l) if all(
        isinstance(c, float) for p in points for c in p) else _projected_simple_fr(points, l)


def _projected_simple_fr(points, l):
    lf = ex.fr3(l)
    r = ex.fr3(ex.ray_direction(tuple(l)))
    w = ex.cross(lf, r)
    P = [(ex.dot(p, r), ex.dot(p, w)) for p in points]
    n = len(P)

    def orient(a, b, c):
        return ex.sgn((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))

    def on_seg(a, b, c):
        return min(a[0], b[0]) <= c[0] <= max(a[0], b[0]) and min(a[1], b[1]) <= c[1] <= max(a[1], b[1])

    if len(set(P)) != n:
        return False
    for i in range(n):
        for j in range(i + 2, n):
            if i == 0 and j == n - 1:
                continue
            a, b, c, d = P[i], P[(i + 1) % n], P[j], P[(j + 1) % n]
            d1, d2, d3, d4 = orient(c, d, a), orient(c, d, b), orient(a, b, c), orient(a, b, d)
            if d1 * d2 < 0 and d3 * d4 < 0:
                return False
            if (d1 == 0 and on_seg(c, d, a)) or (d2 == 0 and on_seg(c, d, b)) or (d3 == 0 and on_seg(a, b, c)) or (
                    d4 == 0 and on_seg(a, b, d)):
                return False
    return True


@st.composite
def moving_triangles(draw):
    base = np.array([[draw(coord) for _ in range(3)] for _ in range(3)])
    amp = draw(st.sampled_from([0.0, 1e-6, 0.01, 0.3, 2.0]))
    move = np.array([[draw(coord) for _ in range(3)] for _ in range(3)]) * amp
    if draw(st.booleans()):  # nearly degenerate at the start: a vertex near the opposite edge
        base[2] = 0.5 * (base[0] + base[1]) + 1e-9 * base[2]
    end = base + move
    for P in (base, end):  # keep the values the core takes (0 or magnitudes >= 2^-128)
        P[np.abs(P) < 2.0**-100] = 0.0
    return base, end


@settings(max_examples=400, deadline=None)
@given(moving_triangles())
def test_ccd_cone_holds_the_normal_for_every_t(tri):
    T0, T1 = tri
    axis, cb, sb = C.triangle_cone_ccd(*[np.array([p]) for p in (*T0, *T1)])
    assume(cb[0] > 0)  # a full cone claims nothing (Hypothesis fails the test if most are full)
    a = ex.fr3(axis[0])
    cb2 = Fr(float(cb[0])) ** 2
    for t in TS + [Fr(1, 1000), Fr(999, 1000)]:
        A, B, Cc = (ex.lerp(p0, p1, t) for p0, p1 in zip(T0, T1))
        n = ex.cross(ex.sub(B, A), ex.sub(Cc, A))
        na = ex.dot(n, a)
        assert na > 0 and na * na >= cb2 * ex.dot(n, n) * ex.dot(a, a), f"t = {t}"


def test_ccd_kernel_retry_off_the_line_search_on_a_moving_sideways_spike():
    """The sideways spike of tests/contour (the line search of [SPO10] finds no kernel point on
    its line) translated and turned a little over the step: the moving mean fails, and the
    clipped kernels' points at both ends pass, exactly as the twin says."""
    l = np.array([0.0, 0.0, 1.0])
    P0 = _sideways_spike()
    P1 = P0 + np.array([0.3, 0.1, -0.2]) + 0.003 * np.cross(l, P0)
    ids = np.arange(len(P0), dtype=np.int32)
    Q0, Q1 = [tuple(p) for p in P0], [tuple(p) for p in P1]
    assert ex.sct_candidate(Q0, tuple(l))[0] is None and ex.sct_candidate(Q1, tuple(l))[0] is None
    first = C.contour_test_ccd(ids, P0, P1, l, o=np.array(ex.float_mean(Q0)), o1=np.array(ex.float_mean(Q1)))
    assert first["reason"] == 2
    res = C.contour_test_ccd(ids, P0, P1, l)
    e = first["edge"]
    o0, o1 = ex.clipped_kernel_candidate(Q0, tuple(l), e)[1], ex.clipped_kernel_candidate(Q1, tuple(l), e)[1]
    assert res["passed"] and (res["kernel"], res["kernel_end"]) == (o0, o1)
    assert ex.contour_test_ccd(Q0, Q1, tuple(l), res["ray"], o=o0, o1=o1)[0]
