"""Tests of the brute-force oracle (tests/oracle.py) and the generated cases."""

from __future__ import annotations

import os
import sys
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import meshcases  # noqa: E402
from oracle import brute_force_pairs, triangle_pair_collides  # noqa: E402

collides = triangle_pair_collides


# ---------------------------------------------------------------------------
# hand-made pairs with known answers
# ---------------------------------------------------------------------------

P0 = [(0, 0, 0), (4, 0, 0), (0, 4, 0)]  # right triangle in z = 0


def both_ways(P, Q, shared_P=(), expected=None):
    """Check expected answer for (P, Q) and (Q, P), slow and fast paths."""
    shared_Q = []
    for k in shared_P:
        shared_Q.append([tuple(q) for q in Q].index(tuple(P[k])))
    for fast in (True, False):
        assert collides(P, Q, shared_P, fast=fast) is expected
        assert collides(Q, P, shared_Q, fast=fast) is expected
    assert collides(P, Q, shared_P, exact_ints=False) is expected


class TestNoSharedVertex:
    def test_disjoint_parallel(self):
        both_ways(P0, [(0, 0, 1), (4, 0, 1), (0, 4, 1)], expected=False)

    def test_disjoint_coplanar(self):
        both_ways(P0, [(3, 3, 0), (6, 3, 0), (3, 6, 0)], expected=False)

    def test_disjoint_coplanar_tiny_gap(self):
        g = 2.0 ** -40
        both_ways(P0, [(2 + g, 2 + g, 0), (6, 2, 0), (2, 6, 0)], expected=False)

    def test_disjoint_near_plane(self):
        both_ways(P0, [(1, 1, 1e-300), (2, 1, 1), (1, 2, 1)], expected=False)

    def test_piercing(self):
        both_ways(P0, [(1, 1, -1), (1, 1, 1), (5, 5, 5)], expected=True)

    def test_vertex_touches_face_interior(self):
        both_ways(P0, [(1, 1, 0), (2, 1, 1), (1, 2, 1)], expected=True)

    def test_vertex_touches_edge(self):
        both_ways(P0, [(2, 0, 0), (2, -1, 1), (3, -1, 1)], expected=True)

    def test_vertex_on_vertex_different_indices(self):
        both_ways(P0, [(4, 0, 0), (5, 1, 1), (5, -1, 1)], expected=True)

    def test_vertex_just_above_face(self):
        both_ways(P0, [(1, 1, 2.0 ** -60), (2, 1, 1), (1, 2, 1)], expected=False)

    def test_edge_crosses_edge(self):
        # Q in the plane x = 1, its bottom edge passes through P's edge y = 0
        both_ways(P0, [(1, -1, 1), (1, 1, -1), (1, -3, -3)], expected=True)

    def test_edge_misses_edge(self):
        both_ways(P0, [(1, -1, 1), (1, 1, 1 + 2.0 ** -30), (1, -3, -3)], expected=False)

    def test_coplanar_overlapping(self):
        both_ways(P0, [(1, 1, 0), (6, 1, 0), (1, 6, 0)], expected=True)

    def test_coplanar_crossing_edges(self):
        both_ways(P0, [(1, -1, 0), (1, 1, 0), (-5, 0, 0)], expected=True)

    def test_coplanar_touching_along_edge(self):
        both_ways(P0, [(4, 0, 0), (0, 4, 0), (4, 4, 0)], expected=True)

    def test_coplanar_touching_partial_edge(self):
        both_ways(P0, [(1, 3, 0), (3, 1, 0), (5, 5, 0)], expected=True)

    def test_coplanar_containment(self):
        both_ways(P0, [(1, 1, 0), (2, 1, 0), (1, 2, 0)], expected=True)

    def test_identical_positions_different_indices(self):
        both_ways(P0, list(P0), expected=True)

    def test_large_offset_touching(self):
        off = np.array([1e6, -1e6, 1e6])
        P = np.array(P0, dtype=float) * 0.1 + off
        Q = np.array([(0.4, 0.0, 0.0), (0.5, 0.1, 0.1), (0.5, -0.1, 0.1)]) + off
        assert collides(P, Q) is True
        Q2 = Q.copy()
        Q2[:, 2] = np.nextafter(Q2[:, 2], np.inf)
        assert collides(P, Q2) is False


class TestSharedVertex:
    V = (0, 0, 0)

    def test_fold_through(self):
        # Q stands vertically over the interior of P, through the shared v
        both_ways(P0, [self.V, (2, 2, 1), (2, 2, -1)], (0,), expected=True)

    def test_tilted_through(self):
        both_ways(P0, [self.V, (2, 1, 1), (1, 2, -1)], (0,), expected=True)

    def test_only_meeting_at_v_coplanar(self):
        both_ways(P0, [self.V, (-4, 0, 0), (0, -4, 0)], (0,), expected=False)

    def test_only_meeting_at_v_space(self):
        both_ways(P0, [self.V, (-1, -1, 1), (-1, 1, 1)], (0,), expected=False)

    def test_only_meeting_at_v_above(self):
        both_ways(P0, [self.V, (1, 1, 1), (2, 1, 3)], (0,), expected=False)

    def test_coplanar_wedges_touching_along_ray(self):
        # Q's edge v->(0,-4) and ... Q shares the ray along +x with P
        both_ways(P0, [self.V, (3, 0, 0), (3, -3, 0)], (0,), expected=True)

    def test_coplanar_overlapping_wedges(self):
        both_ways(P0, [self.V, (4, 1, 0), (4, -4, 0)], (0,), expected=True)

    def test_third_vertex_on_other_edge(self):
        # Q's vertex (2, 2, 0) lies on P's edge (4,0,0)-(0,4,0)
        both_ways(P0, [self.V, (2, 2, 0), (3, 3, 5)], (0,), expected=True)

    def test_third_vertex_on_shared_vertex_edge(self):
        # Q's vertex (2, 0, 0) lies on P's edge v-(4,0,0)
        both_ways(P0, [self.V, (2, 0, 0), (1, -1, 3)], (0,), expected=True)

    def test_edge_along_other_plane_outside(self):
        both_ways(P0, [self.V, (-2, 0, 0), (1, -1, 3)], (0,), expected=False)

    def test_shared_vertex_not_first(self):
        P = [(4, 0, 0), (0, 4, 0), (0, 0, 0)]
        both_ways(P, [(2, 2, 1), (0, 0, 0), (2, 2, -1)], (2,), expected=True)
        both_ways(P, [(-1, -1, 1), (0, 0, 0), (-1, 1, 1)], (2,), expected=False)

    def test_shared_index_far_touch(self):
        # they meet at v and also touch at another point: collides
        both_ways(P0, [self.V, (4, 0, 0), (1, -1, 0)], (0,), expected=True)


class TestSharedEdge:
    def test_non_coplanar(self):
        both_ways(P0, [(0, 0, 0), (4, 0, 0), (2, -3, 1)], (0, 1), expected=False)
        both_ways(P0, [(0, 0, 0), (4, 0, 0), (2, 3, 1)], (0, 1), expected=False)

    def test_coplanar_opposite_sides(self):
        both_ways(P0, [(4, 0, 0), (0, 0, 0), (2, -3, 0)], (0, 1), expected=False)

    def test_coplanar_same_side(self):
        both_ways(P0, [(4, 0, 0), (0, 0, 0), (1, 1, 0)], (0, 1), expected=True)
        both_ways(P0, [(4, 0, 0), (0, 0, 0), (7, 9, 0)], (0, 1), expected=True)

    def test_coplanar_same_side_nonfirst_edge(self):
        both_ways(P0, [(0, 4, 0), (4, 0, 0), (1, 1, 0)], (1, 2), expected=True)
        both_ways(P0, [(0, 4, 0), (4, 0, 0), (3, 3, 0)], (1, 2), expected=False)

    def test_degenerate_other_on_edge_line(self):
        # Q = segment (0,0,0)-(6,0,0) with shared edge (0,0,0)-(4,0,0): Q
        # sticks out of S, but P does not reach there -> P∩Q = S
        both_ways(P0, [(0, 0, 0), (4, 0, 0), (6, 0, 0)], (0, 1), expected=False)
        # Q's third vertex inside the shared edge: Q ⊆ S
        both_ways(P0, [(0, 0, 0), (4, 0, 0), (1, 0, 0)], (0, 1), expected=False)

    def test_all_three_shared(self):
        for fast in (True, False):
            assert collides(P0, P0, (0, 1, 2), fast=fast) is False
            assert collides(P0, [P0[1], P0[2], P0[0]], (0, 1, 2), fast=fast) is False


class TestDegenerate:
    SEG = [(1, 1, -1), (1, 1, 1), (1, 1, 0)]     # segment through P0's interior
    PT_IN = [(1, 1, 0)] * 3
    PT_OUT = [(3, 3, 0)] * 3

    def test_segment_through_triangle(self):
        both_ways(P0, self.SEG, expected=True)

    def test_segment_above_triangle(self):
        both_ways(P0, [(1, 1, 1), (1, 1, 3), (1, 1, 2)], expected=False)

    def test_segment_in_plane_crossing_edge(self):
        both_ways(P0, [(-1, 1, 0), (1, 1, 0), (-3, 1, 0)], expected=True)

    def test_point_in_triangle(self):
        both_ways(P0, self.PT_IN, expected=True)

    def test_point_outside_triangle(self):
        both_ways(P0, self.PT_OUT, expected=False)

    def test_point_on_edge(self):
        both_ways(P0, [(2, 2, 0)] * 3, expected=True)

    def test_segments_crossing(self):
        A = [(0, 0, 0), (2, 2, 0), (1, 1, 0)]
        B = [(0, 2, 0), (2, 0, 0), (1.5, 0.5, 0)]
        both_ways(A, B, expected=True)

    def test_segments_skew(self):
        A = [(0, 0, 0), (2, 2, 0), (1, 1, 0)]
        B = [(0, 2, 1), (2, 0, 1), (1.5, 0.5, 1)]
        both_ways(A, B, expected=False)

    def test_collinear_segments_overlap_and_gap(self):
        A = [(0, 0, 0), (2, 0, 0), (1, 0, 0)]
        both_ways(A, [(1.5, 0, 0), (3, 0, 0), (2.5, 0, 0)], expected=True)
        both_ways(A, [(2.5, 0, 0), (3, 0, 0), (2.75, 0, 0)], expected=False)
        both_ways(A, [(2, 0, 0), (3, 0, 0), (2.5, 0, 0)], expected=True)

    def test_points(self):
        both_ways([(1, 2, 3)] * 3, [(1, 2, 3)] * 3, expected=True)
        both_ways([(1, 2, 3)] * 3, [(1, 2, 3.5)] * 3, expected=False)

    def test_point_triangle_sharing_its_vertex(self):
        # P is a point; its index is shared with Q, so P ⊆ S
        assert collides([(0, 0, 0)] * 3, P0, (0,)) is False
        assert collides([(0, 0, 0)] * 3, P0, (0,), fast=False) is False

    def test_sliver_with_shared_vertex(self):
        # P = (v, a, midpoint of v-a) is a segment lying on Q's edge v-a,
        # but only v is shared: they overlap along the segment
        P = [(0, 0, 0), (4, 0, 0), (2, 0, 0)]
        both_ways(P, [(0, 0, 0), (2, 2, 5), (6, 0, 0)], (0,), expected=True)
        both_ways(P, [(0, 0, 0), (0, 4, 0), (-3, 1, 0)], (0,), expected=False)

    def test_sliver_sharing_edge(self):
        P = [(0, 0, 0), (4, 0, 0), (2, 0, 0)]   # segment = the shared edge
        both_ways(P, [(0, 0, 0), (4, 0, 0), (2, 2, 0)], (0, 1), expected=False)


def test_fraction_and_int_inputs():
    P = [(Fraction(0), Fraction(0), Fraction(0)), (Fraction(1, 3), 0, 0), (0, Fraction(1, 3), 0)]
    Q = [(Fraction(1, 9), Fraction(1, 9), -1), (Fraction(1, 9), Fraction(1, 9), 1), (5, 5, 5)]
    assert collides(P, Q) is True
    Q2 = [(Fraction(1, 6), Fraction(1, 6) + Fraction(1, 10**30), -1),
          (Fraction(1, 6), Fraction(1, 6) + Fraction(1, 10**30), 1), (5, 5, 5)]
    assert collides(P, Q2) is False


def test_bad_shared_index():
    with pytest.raises(ValueError):
        collides(P0, P0, (3,))


# ---------------------------------------------------------------------------
# independent reference formulas for non-degenerate triangles
# ---------------------------------------------------------------------------

def _sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def _dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _normal(T):
    return _cross(_sub(T[1], T[0]), _sub(T[2], T[0]))


def _nonzero(v):
    return any(x != 0 for x in v)


def ref_sat_intersect(P, Q):
    """Closed non-degenerate triangles intersect iff no candidate axis
    strictly separates them (separating axis theorem, exact integers)."""
    eP = [_sub(P[(k + 1) % 3], P[k]) for k in range(3)]
    eQ = [_sub(Q[(k + 1) % 3], Q[k]) for k in range(3)]
    nP, nQ = _normal(P), _normal(Q)
    axes = [nP, nQ] + [_cross(e, f) for e in eP for f in eQ]
    axes += [_cross(nP, e) for e in eP] + [_cross(nQ, f) for f in eQ]
    for a in axes:
        if not _nonzero(a):
            continue
        pp = [_dot(a, v) for v in P]
        qq = [_dot(a, v) for v in Q]
        if max(pp) < min(qq) or max(qq) < min(pp):
            return False
    return True


def _in_cone(r, u1, u2, n):
    """r (in the plane with normal n = u1 x u2) lies in cone{u1, u2}."""
    return _dot(_cross(u1, r), n) >= 0 and _dot(_cross(r, u2), n) >= 0


def ref_shared_vertex(P, Q):
    """P[0] is Q[0] (the one shared vertex); both non-degenerate.
    Collide iff the tangent cones at v meet in more than the apex."""
    v = P[0]
    u1, u2 = _sub(P[1], v), _sub(P[2], v)
    w1, w2 = _sub(Q[1], v), _sub(Q[2], v)
    nP, nQ = _cross(u1, u2), _cross(w1, w2)
    d = _cross(nP, nQ)
    if _nonzero(d):
        md = tuple(-x for x in d)
        return any(_in_cone(r, u1, u2, nP) and _in_cone(r, w1, w2, nQ) for r in (d, md))
    return (_in_cone(u1, w1, w2, nQ) or _in_cone(u2, w1, w2, nQ)
            or _in_cone(w1, u1, u2, nP) or _in_cone(w2, u1, u2, nP))


def ref_shared_edge(P, Q):
    """P = (u, v, p), Q = (u, v, q) or (v, u, q); both non-degenerate.
    Collide iff coplanar with p, q on the same side of line uv."""
    u, v, p = P
    q = Q[2]
    e = _sub(v, u)
    cp, cq = _cross(e, _sub(p, u)), _cross(e, _sub(q, u))
    if _dot(_cross(e, _sub(p, u)), _sub(q, u)) != 0:
        return False
    return _dot(cp, cq) > 0


coord = st.integers(-3, 3)
flat_coord = st.sampled_from([0, 0, 0, 1, -1, 2])
point = st.tuples(coord, coord, st.one_of(flat_coord, coord))


def _rot(T, r):
    return list(T[r:]) + list(T[:r])


SETTINGS = settings(max_examples=600, deadline=None,
                    suppress_health_check=[HealthCheck.filter_too_much])


def _flatten(planar, *pts):
    """planar=True puts every point into z = 0 (coplanar configurations)."""
    if not planar:
        return pts
    return tuple((p[0], p[1], 0) for p in pts)


@SETTINGS
@given(P=st.tuples(point, point, point), Q=st.tuples(point, point, point),
       planar=st.booleans())
def test_reference_no_shared(P, Q, planar):
    P, Q = _flatten(planar, *P), _flatten(planar, *Q)
    assume(_nonzero(_normal(P)) and _nonzero(_normal(Q)))
    assert collides(P, Q) is ref_sat_intersect(P, Q)
    assert collides(P, Q, fast=False) is ref_sat_intersect(P, Q)


@SETTINGS
@given(v=point, a=point, b=point, c=point, d=point, r=st.integers(0, 2), s=st.integers(0, 2),
       planar=st.booleans())
def test_reference_shared_vertex(v, a, b, c, d, r, s, planar):
    v, a, b, c, d = _flatten(planar, v, a, b, c, d)
    P, Q = (v, a, b), (v, c, d)
    assume(_nonzero(_normal(P)) and _nonzero(_normal(Q)))
    expected = ref_shared_vertex(P, Q)
    # present the triangles with the shared vertex in any slot
    Pr, Qr = _rot(P, r), _rot(Q, s)
    k = (-r) % 3
    assert collides(Pr, Qr, (k,)) is expected
    assert collides(Pr, Qr, (k,), fast=False) is expected


@SETTINGS
@given(u=point, v=point, p=point, q=point, flip=st.booleans(), r=st.integers(0, 2),
       planar=st.booleans())
def test_reference_shared_edge(u, v, p, q, flip, r, planar):
    u, v, p, q = _flatten(planar, u, v, p, q)
    P, Q = (u, v, p), ((v, u, q) if flip else (u, v, q))
    assume(_nonzero(_normal(P)) and _nonzero(_normal(Q)))
    expected = ref_shared_edge((u, v, p), (u, v, q))
    Pr = _rot(P, r)
    ks = ((-r) % 3, (1 - r) % 3)
    assert collides(Pr, Q, ks) is expected
    assert collides(Pr, Q, ks, fast=False) is expected


# ---------------------------------------------------------------------------
# invariances (degenerate triangles included)
# ---------------------------------------------------------------------------

small = st.sampled_from([-1, 0, 0, Fraction(1, 2), 1, 2])
spoint = st.tuples(small, small, st.sampled_from([0, 0, 0, 1, Fraction(-1, 2)]))


@st.composite
def tri_pair(draw):
    """(P, Q, shared_P, shared_Q): Q's first n_shared slots (after a
    shuffle) are copies of distinct P vertices (shared indices)."""
    P = [draw(spoint) for _ in range(3)]
    n = draw(st.integers(0, 3))
    sp = draw(st.permutations([0, 1, 2]))[:n]
    Q = [P[k] for k in sp] + [draw(spoint) for _ in range(3 - n)]
    perm = draw(st.permutations([0, 1, 2]))
    Q = [Q[i] for i in perm]
    # shared_Q: slot of Q holding P[sp[t]]; original slot t went to perm.index(t)
    sq = [perm.index(t) for t in range(n)]
    return P, Q, tuple(sp), tuple(sq)


@settings(max_examples=800, deadline=None)
@given(tp=tri_pair(), r=st.integers(0, 2), r2=st.integers(0, 2))
def test_symmetry_and_relabelling(tp, r, r2):
    P, Q, sp, sq = tp
    base = collides(P, Q, sp)
    # swap P and Q
    assert collides(Q, P, sq) is base
    # cyclic relabelling of P's (and Q's) vertices
    Pr = _rot(P, r)
    spr = tuple((k - r) % 3 for k in sp)
    assert collides(Pr, Q, spr) is base
    Qr = _rot(Q, r2)
    assert collides(Pr, Qr, spr) is base
    assert collides(Qr, Pr, tuple((k - r2) % 3 for k in sq)) is base
    # reversed orientation of P
    Pv = [P[0], P[2], P[1]]
    spv = tuple({0: 0, 1: 2, 2: 1}[k] for k in sp)
    assert collides(Pv, Q, spv) is base
    # fast shortcut and plain Fraction arithmetic give the same answer
    assert collides(P, Q, sp, fast=False) is base
    assert collides(P, Q, sp, exact_ints=False, fast=False) is base
    # uniform translation (exact) and scaling by 2 (exact) change nothing
    t = (Fraction(3, 4), -5, 7)
    Pt = [tuple(x + y for x, y in zip(p, t)) for p in P]
    Qt = [tuple(x + y for x, y in zip(q, t)) for q in Q]
    assert collides(Pt, Qt, sp) is base
    P2 = [tuple(2 * x for x in p) for p in P]
    Q2 = [tuple(2 * x for x in q) for q in Q]
    assert collides(P2, Q2, sp) is base


# ---------------------------------------------------------------------------
# brute_force_pairs and the generated cases
# ---------------------------------------------------------------------------

def slow_all_pairs(F, V):
    """All m(m-1)/2 pairs, no prefilter, no shortcut."""
    F = np.asarray(F).tolist()
    out = set()
    for i in range(len(F)):
        for j in range(i + 1, len(F)):
            shared = [k for k in range(3) if F[i][k] in F[j]]
            if collides(V[F[i]], V[F[j]], shared, fast=False):
                out.add((i, j))
    return out


SLOW_CHECK_CASES = [
    "fold_flat_exact_g9x7_at3",
    "crumple_noisy_s5",
    "sliver_midpoint_flat",
    "fan_ring_winds_twice_flat",
    "bowtie_double_cone_dup_apex",
    "grid_corner_foldover_8x6_h0.125_0.125",
]


@pytest.mark.parametrize("name", SLOW_CHECK_CASES)
def test_brute_force_matches_all_pairs(name):
    _, F, V = meshcases.case(name)
    fastres = brute_force_pairs(F, V)
    assert fastres == slow_all_pairs(F, V)
    assert all(i < j for i, j in fastres)


def test_brute_force_small_mesh():
    # two triangles pierce, a third shares an edge with the first only
    V = np.array([[0, 0, 0], [4, 0, 0], [0, 4, 0],
                  [1, 1, -1], [1, 1, 1], [5, 5, 5],
                  [0, -4, 0.5]], dtype=float)
    F = np.array([[0, 1, 2], [3, 4, 5], [1, 0, 6]])
    assert brute_force_pairs(F, V) == {(0, 1)}
    assert brute_force_pairs(np.zeros((0, 3), dtype=int), V) == set()


def test_brute_force_result_types():
    _, F, V = meshcases.case("edge_pair_foldover_coplanar")
    res = brute_force_pairs(F, V)
    assert res == {(0, 1)}
    assert all(type(i) is int and type(j) is int for i, j in res)


@pytest.fixture(scope="module")
def oracle_results():
    return {name: brute_force_pairs(F, V) for name, F, V in meshcases.all_cases()}


def test_cases_well_formed():
    cases = meshcases.all_cases()
    assert len(cases) >= 40
    names = [c[0] for c in cases]
    assert len(set(names)) == len(names)
    for name, F, V in cases:
        assert F.dtype == np.int64 and F.ndim == 2 and F.shape[1] == 3, name
        assert V.dtype == np.float64 and V.ndim == 2 and V.shape[1] == 3, name
        assert F.min() >= 0 and F.max() < len(V), name
        assert np.all(np.isfinite(V)), name
        assert all(len(set(f)) == 3 for f in F.tolist()), name
        _, F2, V2 = meshcases.case(name)
        assert np.array_equal(F, F2) and np.array_equal(V, V2), name


def test_cases_deterministic():
    import importlib
    a = meshcases.all_cases()
    mod = importlib.reload(meshcases)
    b = mod.all_cases()
    for (n1, F1, V1), (n2, F2, V2) in zip(a, b):
        assert n1 == n2 and np.array_equal(F1, F2)
        assert V1.tobytes() == V2.tobytes()


def test_case_collision_counts(oracle_results):
    with_coll = [n for n, r in oracle_results.items() if r]
    without = [n for n, r in oracle_results.items() if not r]
    assert len(with_coll) >= 25, with_coll
    assert len(without) >= 5, without


EXPECT_CLEAN = [
    "fold_single_090_g10", "fold_single_179_g10", "fold_single_180_float_hover",
    "fold_single_200_planar_nocross", "bent_sheet_parabola", "crumple_mild_s0",
    "cylinder_plain_16x8", "sphere_plain_16x10", "holes_flat",
    "components_two_parallel", "fan_vertex_fold_outside", "edge_pair_flat_opposite",
    "fan_ring_winds_twice_helix_open", "fins_four_on_one_edge", "fins_strip_clean",
    "bowtie_flat_clean", "bowtie_double_cone_clean", "near_vertex_point_gap",
]
EXPECT_COLLIDING = [
    "fold_zfold_200_back100_g14", "fold_flat_exact_g10x10_at5", "crumple_strong_s3",
    "sheet_rolled_420", "cylinder_twist_strong", "sphere_noise_strong",
    "components_two_interpenetrating", "components_coplanar_overlap_offset",
    "fan_vertex_fold_through", "edge_pair_foldover_coplanar",
    "fan_ring_winds_twice_flat", "fins_coplanar_overlap", "fins_strip_pierced_by_flap",
    "bowtie_crossing_discs", "bowtie_double_cone_dup_apex", "offset_1e6_zfold_200",
    "offset_1e6_flat_exact_fold", "sliver_midpoint_flat", "duplicate_seam_touching",
    "duplicate_vertex_point_touch",
]


def test_expected_clean_and_colliding(oracle_results):
    for n in EXPECT_CLEAN:
        assert oracle_results[n] == set(), n
    for n in EXPECT_COLLIDING:
        assert oracle_results[n], n


def test_known_small_case_answers(oracle_results):
    # by construction
    assert oracle_results["edge_pair_foldover_coplanar"] == {(0, 1)}
    assert oracle_results["fan_vertex_fold_through"] == {(1, 5)}
    # the winding fan: triangle k overlaps k+6 (same sector, coplanar) and
    # the two neighbours of k+6, which share only the centre with k
    exp = set()
    for k in range(12):
        for j in range(12):
            d = (j - k) % 12
            if d in (5, 6, 7) and k < j:
                exp.add((k, j))
    assert oracle_results["fan_ring_winds_twice_flat"] == exp
    # a double cone with separate apex indices: every upper face touches
    # every lower face at the apex
    assert len(oracle_results["bowtie_double_cone_dup_apex"]) == 36
