"""The baselines' contour tests (Sec. 6.1) against exact twins (fractions, tests/exact_twin.py):

- "sct" ([SPO10], projected star-contour test): the float projection and line search only pick
  the candidate kernel point; the twin replicates them operation by operation, then decides
  every sign exactly. The core, whose signs are certified (filter on the projected coordinates,
  exact fallback), must give exactly the twin's verdict, reason and edge.
- "cbc" ([TCYM09], O(n^2) edge pairs): at one pose it passes exactly when the exact projection
  is a simple polygon (the independent brute force of test_contour.py); over a step it equals
  the exact twin of its Bernstein-coefficient formulation.
- Soundness: every loop either passes has a simple projection (at sampled t for CCD).
"""

from fractions import Fraction as Fr

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import exact_twin as ex
from conecull._core import contour as CT
from contour.test_contour import loops, projected_simple

TS = [Fr(0), Fr(1, 7), Fr(1, 3), Fr(1, 2), Fr(5, 7), Fr(1)]


def pts_list(P):
    return [tuple(float(x) for x in p) for p in P]


@settings(max_examples=500, deadline=None)
@given(loops())
def test_sct_matches_exact_twin_and_is_sound(loop):
    pts, l = loop
    ids = np.arange(len(pts), dtype=np.int32)
    res = CT.sct_contour_test(ids, pts, l)
    passed, reason, edge, o, r = ex.sct_test(pts_list(pts), tuple(l))
    assert (res["passed"], res["reason"]) == (passed, reason)
    if reason in (1, 2, 3, 4):
        assert res["edge"] == edge
    if o is not None:
        assert res["kernel"] == o and res["ray"] == tuple(r)  # the same candidate, bit for bit
    if res["passed"]:
        assert projected_simple(pts, l), "sct passed a loop whose projection is not simple"


@settings(max_examples=500, deadline=None)
@given(loops())
def test_cbc_at_one_pose_is_exactly_simplicity(loop):
    pts, l = loop
    res = CT.cbc_contour_test(np.arange(len(pts), dtype=np.int32), pts, l)
    twin = ex.cbc_test(pts_list(pts), tuple(l))
    assert (res["passed"], res["reason"], res["edge"], res["other_edge"]) == twin
    # Complete as well as sound: with exact signs, pass <=> the projected polygon is simple.
    assert res["passed"] == projected_simple(pts, l)
    n = len(pts)
    if res["passed"]:
        assert res["edges_visited"] == n * (n - 1)  # every pair, two edges each: the O(n^2)


@st.composite
def moving_loops(draw):
    pts0, l = draw(loops())
    kind = draw(st.sampled_from(["still", "small", "large", "lattice"]))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    if kind == "still":
        pts1 = pts0.copy()
    elif kind == "lattice":  # integer moves: exact zeros in the Bernstein coefficients
        pts1 = pts0 + rng.integers(-1, 2, pts0.shape).astype(float) * draw(st.sampled_from([0.0, 1.0]))
    else:
        pts1 = pts0 + (0.02 if kind == "small" else 0.5) * rng.standard_normal(pts0.shape)
    return pts0, pts1, l


def lerp_pts(P0, P1, t):
    return [ex.lerp(p, q, t) for p, q in zip(P0, P1)]


@settings(max_examples=400, deadline=None)
@given(moving_loops())
def test_cbc_ccd_matches_exact_twin_and_is_sound(m):
    P0, P1, l = m
    ids = np.arange(len(P0), dtype=np.int32)
    res = CT.cbc_contour_test_ccd(ids, P0, P1, l)
    twin = ex.cbc_test_ccd(pts_list(P0), pts_list(P1), tuple(l))
    assert (res["passed"], res["reason"], res["edge"], res["other_edge"]) == twin
    if res["passed"]:
        for t in TS:
            assert projected_simple(lerp_pts(P0, P1, t), l), f"cbc passed a step whose projection is not simple at t = {t}"
    # No motion: the CCD test is the DCD test.
    if np.array_equal(P0, P1):
        dcd = CT.cbc_contour_test(ids, P0, l)
        assert (dcd["passed"], dcd["reason"], dcd["edge"]) == (res["passed"], res["reason"], res["edge"])


def test_examples():
    l = np.array([0.0, 0.0, 1.0])
    k = 8
    ang = 2 * np.pi * np.arange(k) / k
    star = np.c_[np.cos(ang + 0.2), np.sin(ang + 0.2), 0.1 * np.sin(3 * ang)]
    ids = np.arange(k, dtype=np.int32)
    for f in (CT.sct_contour_test, CT.cbc_contour_test):
        assert f(ids, star, l)["passed"] and f(ids[::-1].copy(), star, l)["passed"]
    twice = np.c_[np.cos(2 * ang + 0.1), np.sin(2 * ang + 0.1), np.linspace(0, 1, k)]
    assert not CT.sct_contour_test(ids, twice, l)["passed"]
    r = CT.cbc_contour_test(ids, twice, l)
    assert not r["passed"] and r["reason"] == 7
    # A flat axis-aligned square with collinear runs along its sides (a grid node's contour):
    # cbc separates collinear edges along their line; sct and nc pass too.
    sq = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [2, 1, 0], [2, 2, 0], [1, 2, 0], [0, 2, 0], [0, 1, 0]], float)
    ids = np.arange(8, dtype=np.int32)
    assert CT.cbc_contour_test(ids, sq, l)["passed"]
    assert CT.sct_contour_test(ids, sq, l)["passed"]
    assert CT.cbc_contour_test_ccd(ids, sq, sq + [0.5, 0.25, 0.0], l)["passed"]
    # A U that folds onto itself in projection: two non-adjacent collinear edges overlap.
    u_shape = np.array([[0, 0, 0], [3, 0, 0], [3, 1, 0], [1, 1, 0], [1, 0, 1], [0, 1, 0]], float)
    r = CT.cbc_contour_test(np.arange(6, dtype=np.int32), u_shape, l)
    assert not r["passed"]
    assert not CT.sct_contour_test(np.arange(6, dtype=np.int32), u_shape, l)["passed"]


@pytest.mark.parametrize("bad", [np.zeros(2, np.int32), np.array([0, 1, 9], np.int32)])
def test_bad_loops_rejected(bad):
    V = np.eye(3)
    for f in (CT.sct_contour_test, CT.cbc_contour_test, CT.simplicity_test, CT.nc_contour_test):
        with pytest.raises(ValueError, match="loop:"):
            f(bad, V, np.array([0.0, 0.0, 1.0]))
    for f in (CT.cbc_contour_test_ccd, CT.simplicity_test_ccd, CT.nc_contour_test_ccd):
        with pytest.raises(ValueError, match="loop:"):
            f(bad, V, V, np.array([0.0, 0.0, 1.0]))


def test_bad_positions_and_axes_rejected():
    """The single-loop tests name the argument that is wrong: a non-finite position, a step whose
    two poses differ in size, an axis of the wrong shape."""
    ids, l = np.arange(3, dtype=np.int32), np.array([0.0, 0.0, 1.0])
    V = np.eye(3)
    bad = V.copy()
    bad[1, 2] = np.nan
    for f in (CT.simplicity_test, CT.nc_contour_test, CT.sct_contour_test):
        with pytest.raises(ValueError, match="V"):
            f(ids, bad, l)
        with pytest.raises(ValueError, match="l"):
            f(ids, V, np.zeros(2))
    for f in (CT.simplicity_test_ccd, CT.nc_contour_test_ccd):
        with pytest.raises(ValueError, match="V1"):
            f(ids, V, np.eye(4, 3), l)
