"""The certified time-axis test of exact mode (interval_filter.cpp) proves pairs apart and in
contact; its proofs must never disagree with the exact answer. Random configurations whose
answer is known exactly by construction (Python fractions), many of them within 2^-30 of the
boundary between contact and miss, where the test must NOT decide and leaves the pair to the
exact decision. Every coordinate is a multiple of 2^-16 below 16 in magnitude, and so is every
common translation added, so all inputs and their sums are exact doubles."""

from fractions import Fraction as Fr

import numpy as np
import pytest

from conecull._core import ccd as C

Q = 2.0**-16


def vf(p0, a0, b0, c0, p1, a1, b1, c1):
    return bool(C.vertex_face_ccd_rows(*[np.array([x], float) for x in (p0, a0, b0, c0, p1, a1, b1, c1)], "exact")[0])


def ee(a0, b0, c0, d0, a1, b1, c1, d1):
    return bool(C.edge_edge_ccd_rows(*[np.array([x], float) for x in (a0, b0, c0, d0, a1, b1, c1, d1)], "exact")[0])


def grid(rng, lo=-4.0, hi=4.0, size=None):
    return np.round(rng.uniform(lo, hi, size) / Q) * Q


def orient2(a, b, c):
    return (Fr(b[0]) - Fr(a[0])) * (Fr(c[1]) - Fr(a[1])) - (Fr(b[1]) - Fr(a[1])) * (Fr(c[0]) - Fr(a[0]))


def on_closed_segment_2d(q, a, b):
    """q (Fractions) on the closed segment ab, all in the plane (exact)."""
    if orient2(a, b, q) != 0:
        return False
    return all(min(Fr(a[k]), Fr(b[k])) <= q[k] <= max(Fr(a[k]), Fr(b[k])) for k in range(2))


def segments_meet_2d(a, b, c, d):
    o1, o2, o3, o4 = orient2(a, b, c), orient2(a, b, d), orient2(c, d, a), orient2(c, d, b)
    if o1 * o2 < 0 and o3 * o4 < 0:
        return True
    F = lambda p: tuple(Fr(x) for x in p)  # noqa: E731
    return (on_closed_segment_2d(F(c), a, b) or on_closed_segment_2d(F(d), a, b) or
            on_closed_segment_2d(F(a), c, d) or on_closed_segment_2d(F(b), c, d))


def point_near_segment(rng, a, b):
    """A point on line ab at parameter s near 0 or 1 or inside, nudged off by 0 or +-2^-30 (edge cases)."""
    s = rng.choice([0.0, 1.0, 0.5, rng.uniform(-0.2, 1.2)])
    s += rng.choice([0.0, 2.0**-30, -(2.0**-30)])
    x = np.asarray(a) + s * (np.asarray(b) - np.asarray(a))
    return np.round(x / 2.0**-40) * 2.0**-40  # exact doubles, possibly a hair off the line


def place(rng, pts3, axes, shift0, shift1):
    """Embed (x, y, z) points with a coordinate permutation and a common translation at t0 / t1."""
    out0 = [np.asarray(p, float)[axes] + shift0 for p in pts3[0]]
    out1 = [np.asarray(p, float)[axes] + shift1 for p in pts3[1]]
    return out0, out1


def random_frame(rng):
    return rng.permutation(3), grid(rng, -8, 8, 3), grid(rng, -8, 8, 3)


@pytest.mark.parametrize("seed", range(4))
def test_vf_vertical_pass_against_fractions(seed):
    """A static face in a plane z = h, p falling through it at (x, y) fixed: contact iff (x, y) lies
    in the closed triangle (exact 2D orientations). Many (x, y) on or 2^-30 off an edge."""
    rng = np.random.default_rng(seed)
    for _ in range(60):
        a, b, c = (grid(rng, size=2) for _ in range(3))
        if orient2(a, b, c) == 0:
            continue
        xy = point_near_segment(rng, *[(a, b), (b, c), (c, a)][rng.integers(3)]) if rng.random() < 0.7 else grid(rng, size=2)
        o = [orient2(a, b, xy), orient2(b, c, xy), orient2(c, a, xy)]
        truth = all(s >= 0 for s in o) or all(s <= 0 for s in o)
        h = grid(rng, -1, 1)
        up, down = h + grid(rng, 0.01, 2), h - grid(rng, 0.01, 2)
        face = [[*a, h], [*b, h], [*c, h]]
        axes, s0, s1 = random_frame(rng)
        (p0, *f0), (p1, *f1) = place(rng, ([[*xy, up], *face], [[*xy, down], *face]), axes, s0, s1)
        assert vf(p0, *f0, p1, *f1) == truth, (a, b, c, xy)


@pytest.mark.parametrize("seed", range(4))
def test_ee_horizontal_pass_against_fractions(seed):
    """Segment ab static in the plane z = h, segment cd horizontal and falling through it: contact iff
    the two segments meet in the plane (exact 2D test). Many endpoints on or 2^-30 off the other."""
    rng = np.random.default_rng(100 + seed)
    for _ in range(60):
        a, b = grid(rng, size=2), grid(rng, size=2)
        c = point_near_segment(rng, a, b) if rng.random() < 0.5 else grid(rng, size=2)
        d = grid(rng, size=2)
        if rng.random() < 0.3:  # d near ab too, or cd through an endpoint of ab
            d = point_near_segment(rng, a, b)
        truth = segments_meet_2d(a, b, c, d)
        h = grid(rng, -1, 1)
        up, down = h + grid(rng, 0.01, 2), h - grid(rng, 0.01, 2)
        axes, s0, s1 = random_frame(rng)
        x0, x1 = place(rng, ([[*a, h], [*b, h], [*c, up], [*d, up]], [[*a, h], [*b, h], [*c, down], [*d, down]]), axes, s0, s1)
        assert ee(*x0, *x1) == truth, (a, b, c, d)


def planar_crossing(rng):
    """q moving in the plane y = k across the static segment ab (also in y = k): returns the 2D (x, z)
    data and whether q(t) meets the closed segment ab for some t in [0, 1] (exact)."""
    a, b = grid(rng, size=2), grid(rng, size=2)
    x = point_near_segment(rng, a, b)  # where q crosses line ab (or just misses it)
    dirn = grid(rng, -1, 1, 2)
    q0, q1 = x - dirn, x + grid(rng, 0.1, 1.5) * dirn
    q0, q1 = np.round(q0 / 2.0**-40) * 2.0**-40, np.round(q1 / 2.0**-40) * 2.0**-40
    # q(t) = q0 + t (q1 - q0) meets line ab where orient(a, b, q(t)) = 0 (linear in t).
    g0, g1 = orient2(a, b, q0), orient2(a, b, q1)
    if g0 == g1:  # q moves parallel to ab: it meets ab only if it slides along the line
        hit = g0 == 0 and segments_meet_2d(a, b, q0, q1)
    elif g0 * g1 > 0:
        hit = False
    else:
        t = g0 / (g0 - g1)
        qt = tuple(Fr(q0[k]) + t * (Fr(q1[k]) - Fr(q0[k])) for k in range(2))
        hit = on_closed_segment_2d(qt, a, b)
    return a, b, q0, q1, hit


def lift(p2, k):
    """(x, z) in the plane y = k."""
    return [p2[0], k, p2[1]]


@pytest.mark.parametrize("seed", range(4))
def test_ee_endpoint_crossing_in_an_axis_plane(seed):
    """c crosses segment ab with a, b, c sharing one coordinate exactly (the planar vertex-segment
    proof; cloth-funnel has such pairs), d off the plane: contact iff c meets the closed segment ab.
    Endpoints 2^-30 beyond the segment's ends must not be proven."""
    rng = np.random.default_rng(200 + seed)
    for _ in range(60):
        a, b, c0, c1, truth = planar_crossing(rng)
        if orient2(a, b, (a[0] + 1, a[1])) == 0 and orient2(a, b, (a[0], a[1] + 1)) == 0:
            continue  # a == b
        k = grid(rng, -2, 2)
        off = [grid(rng, -1, 1), grid(rng, 0.25, 1), grid(rng, -1, 1)]  # d = c + off, y component != 0
        d0, d1 = np.add(lift(c0, k), off), np.add(lift(c1, k), off)
        axes, s0, s1 = random_frame(rng)
        x0, x1 = place(rng, ([lift(a, k), lift(b, k), lift(c0, k), d0], [lift(a, k), lift(b, k), lift(c1, k), d1]), axes, s0, s1)
        assert ee(*x0, *x1) == truth, (a, b, c0, c1)
        # the same pair with the segments swapped: (c, d) against (a, b)
        assert ee(x0[2], x0[3], x0[0], x0[1], x1[2], x1[3], x1[0], x1[1]) == truth


@pytest.mark.parametrize("seed", range(4))
def test_vf_vertex_crossing_a_face_edge_in_an_axis_plane(seed):
    """p crosses the face edge ab with p, a, b sharing one coordinate exactly, the third vertex off
    the plane (the face meets the plane only in ab): contact iff p meets the closed segment ab."""
    rng = np.random.default_rng(300 + seed)
    for _ in range(60):
        a, b, p0, p1, truth = planar_crossing(rng)
        if orient2(a, b, (a[0] + 1, a[1])) == 0 and orient2(a, b, (a[0], a[1] + 1)) == 0:
            continue
        k = grid(rng, -2, 2)
        c = [grid(rng, -2, 2), k + grid(rng, 0.25, 1) * rng.choice([-1, 1]), grid(rng, -2, 2)]
        axes, s0, s1 = random_frame(rng)
        x0, x1 = place(rng, ([lift(p0, k), lift(a, k), lift(b, k), c], [lift(p1, k), lift(a, k), lift(b, k), c]), axes, s0, s1)
        assert vf(*x0, *x1) == truth, (a, b, p0, p1)
        assert vf(x0[0], x0[2], x0[3], x0[1], x1[0], x1[2], x1[3], x1[1]) == truth  # rotated face order


def test_boundary_cases_by_name():
    """Named cases at the boundary: the proof must fire inside, and not 2^-40 outside."""
    k = 0.5
    a, b = [0.0, k, 0.0], [1.0, k, 0.0]
    off = np.array([0.1, 0.5, 0.2])
    for x, expected in ((0.5, True), (1.0, True), (0.0, True), (1.0 + 2.0**-40, False), (-(2.0**-40), False)):
        c0, c1 = [x, k, 1.0], [x, k, -1.0]
        assert ee(a, b, c0, np.add(c0, off), a, b, c1, np.add(c1, off)) == expected, x
        assert vf(c0, a, b, [0.3, k + 1.0, 0.0], c1, a, b, [0.3, k + 1.0, 0.0]) == expected, x


@pytest.mark.parametrize("seed", range(4))
def test_generic_motion_contact_at_half(seed):
    """Generic linear motions built around a contact at t = 1/2: x(1/2) = X, x(0) = X - V/2,
    x(1) = X + V/2 (all exact), with the contact point inside, on an edge (u = 0, u + v = 1) or
    at a vertex: always a contact, whatever else f does. Boundary contacts must reach the exact
    decision (no time-axis proof can show them) and still come out as contacts."""
    rng = np.random.default_rng(400 + seed)
    half = 2.0**-8
    for _ in range(60):
        A, B, Cc = (grid(rng, -2, 2, 3) for _ in range(3))
        u, v = (np.round(rng.uniform(0, 1, 2) / half) * half).tolist()
        if u + v > 1:
            u, v = 1 - u, 1 - v
        u, v = [(u, v), (0.0, v), (u, 1 - u), (0.0, 0.0), (1.0, 0.0)][rng.integers(5)]
        P = A + u * (B - A) + v * (Cc - A)  # exact: multiples of 2^-24 below 2^6
        pts = [P, A, B, Cc]
        V = [grid(rng, -1, 1, 3) for _ in pts]
        x0 = [X - 0.5 * W for X, W in zip(pts, V)]
        x1 = [X + 0.5 * W for X, W in zip(pts, V)]
        assert vf(*x0, *x1), (u, v)
        # EE: edge (A, B) against an edge through the point A + s (B - A) at t = 1/2
        s = [0.0, 1.0, np.round(rng.uniform(0, 1) / half) * half][rng.integers(3)]
        M = A + s * (B - A)
        D = grid(rng, -2, 2, 3)
        r = np.round(rng.uniform(0, 1) / half) * half
        Cd = M + r * (M - D)  # M = (Cd + r D) / (1 + r): on segment [Cd, D]
        Cd = np.round(Cd / 2.0**-40) * 2.0**-40
        if not np.array_equal(M + r * (M - D), Cd):
            continue
        pts = [A, B, Cd, D]
        V = [grid(rng, -1, 1, 3) for _ in pts]
        y0 = [X - 0.5 * W for X, W in zip(pts, V)]
        y1 = [X + 0.5 * W for X, W in zip(pts, V)]
        assert ee(*y0, *y1), (s, r)
