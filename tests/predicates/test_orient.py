"""Exact predicates against their fractions twins, with hypothesis and near-degenerate inputs."""

import numpy as np
from hypothesis import given, settings, strategies as st

import exact_twin as ex
from conecull._core import predicates as P

# The predicates are exact on the domain the façade admits: every coordinate is 0 or has a
# magnitude in [2^-128, 2^128] (products of differences then never under- or overflow).
TINY = 2.0**-128


def in_domain(x: float) -> float:
    return 0.0 if abs(x) < TINY else float(x)


finite = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False, allow_infinity=False).map(in_domain)
point = st.tuples(finite, finite, finite)


def near(base, scale):
    """Points within `scale` of `base` (coordinates stay doubles)."""
    return st.tuples(*[st.floats(min_value=b - scale, max_value=b + scale, allow_nan=False) for b in base])


@st.composite
def near_degenerate_quad(draw):
    """Four points close to a plane or a line, on small or huge offsets: the hard cases."""
    offset = draw(st.sampled_from([0.0, 1.0, 1e6, -3.7e5, 1e-3]))
    a = np.array(draw(point)) * 1e-6 + offset
    u = np.array(draw(point)) * 1e-6 + 1.0
    w = np.array(draw(point)) * 1e-6
    s, t, q = draw(finite), draw(finite), draw(finite)
    kind = draw(st.sampled_from(["plane", "line", "tiny"]))
    b = a + u
    c = a + (w if kind == "plane" else u * 2.0)
    d = a + (s * 1e-6) * u + (t * 1e-6) * w
    if kind == "tiny":
        d = d + np.nextafter(0, 1) * 0 + q * 1e-22
    return [tuple(in_domain(x) for x in p) for p in (a, b, c, d)]


def rows(*pts):
    return [np.array([p], dtype=np.float64) for p in pts]


@settings(max_examples=400, deadline=None)
@given(point, point, point, point)
def test_orient3d_random(a, b, c, d):
    assert P.orient3d(*rows(a, b, c, d))[0] == ex.orient3d(a, b, c, d)


@settings(max_examples=600, deadline=None)
@given(near_degenerate_quad())
def test_orient3d_near_degenerate(q):
    a, b, c, d = q
    assert P.orient3d(*rows(a, b, c, d))[0] == ex.orient3d(a, b, c, d)


@settings(max_examples=600, deadline=None)
@given(near_degenerate_quad(), point)
def test_side_sign_near_degenerate(q, l):
    a, b, c, _ = q
    assert P.side_sign(*rows(a, b, c, l))[0] == ex.side_sign(a, b, c, l)
    # Exactly coplanar-with-l configurations: c on the line a + s*l has Side = 0.
    c2 = tuple(in_domain(a[i] + 0.5 * l[i]) for i in range(3)) if all(abs(x) < 1e3 for x in l) else c
    assert P.side_sign(*rows(a, b, c2, l))[0] == ex.side_sign(a, b, c2, l)


@settings(max_examples=600, deadline=None)
@given(near_degenerate_quad(), point)
def test_ray_side_sign_matches_printed_definition(q, l):
    """ray_side_sign evaluates (r x (v - o)) . l, which must equal SideSign(v, o, o + r, l) as printed."""
    v, o, _, _ = q
    r = ex.ray_direction(l)
    assert P.ray_side_sign(*rows(v, o, r, l))[0] == ex.ray_side_sign_literal(v, o, r, l)


@settings(max_examples=400, deadline=None)
@given(st.tuples(finite, finite), st.tuples(finite, finite), st.tuples(finite, finite), st.sampled_from([1.0, 1e-9, 1e6]))
def test_orient2d(a, b, c, scale):
    a2 = np.vectorize(in_domain)(np.array([a]) * scale)
    b2 = np.vectorize(in_domain)(np.array([b]) * scale)
    c2 = np.vectorize(in_domain)((a2 + b2) / 2.0 if scale == 1e-9 else np.array([c]) * scale)  # near-collinear
    assert P.orient2d(a2, b2, c2)[0] == ex.orient2d(a2[0], b2[0], c2[0])


def test_zero_is_rare_on_nondegenerate_input():
    """A certified sign is never 0 unless the exact value is 0: on random inputs, never."""
    rng = np.random.default_rng(1)
    a, b, c, d = (rng.standard_normal((2000, 3)) for _ in range(4))
    s = P.orient3d(a, b, c, d)
    assert np.count_nonzero(s == 0) == 0
    s = P.side_sign(a, b, c, d)
    assert np.count_nonzero(s == 0) == 0


def test_exactly_degenerate_inputs_give_zero():
    a = np.array([[0.1, 0.2, 0.3]])
    b = np.array([[0.7, -0.2, 1.3]])
    assert P.orient3d(a, b, a, b)[0] == 0
    # midpoint-collinear points that are exact in binary
    c = np.array([[0.5, 0.5, 0.5]])
    d = np.array([[1.0, 1.0, 1.0]])
    e = np.array([[2.0, 2.0, 2.0]])
    f = np.array([[3.0, -1.0, 7.0]])
    assert P.orient3d(c, d, e, f)[0] == 0
    assert P.side_sign(c, d, e, f)[0] == 0


def test_huge_offset_tiny_difference():
    base = 1e6
    ulp = np.spacing(base)
    a = np.array([[base, base, base]])
    b = np.array([[base + ulp, base, base]])
    c = np.array([[base, base + ulp, base]])
    for dz, expect in ((ulp, 1), (0.0, 0), (-ulp, -1)):
        d = np.array([[base + 3 * ulp, base + 5 * ulp, base + dz]])
        assert P.orient3d(a, b, c, d)[0] == expect == ex.orient3d(a[0], b[0], c[0], d[0])


@settings(max_examples=300, deadline=None)
@given(point, point, point, st.sampled_from([(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]))
def test_repeated_point_gives_zero(a, b, c, pair):
    """A repeated point (the exact fallback's shortcut, as adjacent triangles ask) agrees with
    the twin: zero, in every position, also for orient2d."""
    pts = [a, b, c, None]
    i, j = pair
    pts[j if j < 3 else 3] = pts[i]
    pts = [p if p is not None else c for p in pts]
    assert P.orient3d(*rows(*pts))[0] == ex.orient3d(*pts) == 0
    if j < 3:
        p2 = [(p[0], p[1]) for p in pts[:3]]
        assert P.orient2d(*rows(*p2))[0] == ex.orient2d(*p2) == 0
