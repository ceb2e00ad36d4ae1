"""The enclosures exact CCD's time-axis test starts from (interval_filter.cpp) against an exact
twin: every Bernstein coefficient of the coplanarity cubic f and of each sign condition h, on
[0, 1], computed with Python fractions, must lie inside the interval the core computes. The
core computes these in floating point with one derived error bound per coefficient (16u times
the permanent, see `Approx` there; the rounding count behind it is checked by the compiler, a
static_assert there), so the inputs here stress that bound: heavy cancellation
(large coordinates, tiny differences), both ends of the supported coordinate range (2^-128 and
2^128), exact zeros and near-coplanar motion."""

from fractions import Fraction as Fr
from math import comb

import numpy as np
import pytest

import exact_twin as ex
from conecull._core import ccd as C


def lin(q0, q1, r0, r1):
    """q(t) - r(t) per axis, Bernstein coefficients of degree 1 (exact)."""
    return [[Fr(q0[k]) - Fr(r0[k]), Fr(q1[k]) - Fr(r1[k])] for k in range(3)]


def bmul(a, b):
    m, n = len(a) - 1, len(b) - 1
    return [sum(Fr(comb(m, i) * comb(n, k - i), comb(m + n, k)) * a[i] * b[k - i]
                for i in range(max(0, k - n), min(m, k) + 1)) for k in range(m + n + 1)]


def badd(a, b):
    return [x + y for x, y in zip(a, b)]


def bsub(a, b):
    return [x - y for x, y in zip(a, b)]


def cross(a, b):
    return [bsub(bmul(a[(k + 1) % 3], b[(k + 2) % 3]), bmul(a[(k + 2) % 3], b[(k + 1) % 3])) for k in range(3)]


def dot(a, b):
    return badd(badd(bmul(a[0], b[0]), bmul(a[1], b[1])), bmul(a[2], b[2]))


def bern_value(c, t):
    n = len(c) - 1
    return sum(comb(n, i) * c[i] * t**i * (1 - t) ** (n - i) for i in range(n + 1))


def exact_vf(x):
    p0, a0, b0, c0, p1, a1, b1, c1 = x
    ba, ca, pa = lin(b0, b1, a0, a1), lin(c0, c1, a0, a1), lin(p0, p1, a0, a1)
    cb, pb, ac, pc = lin(c0, c1, b0, b1), lin(p0, p1, b0, b1), lin(a0, a1, c0, c1), lin(p0, p1, c0, c1)
    n = cross(ba, ca)
    o = [cross(ba, pa), cross(cb, pb), cross(ac, pc)]
    return [dot(n, pa)] + [bmul(o[i][k], n[k]) for i in range(3) for k in range(3)]


def exact_ee(x):
    a0, b0, c0, d0, a1, b1, c1, d1 = x
    ba, dc, ca = lin(b0, b1, a0, a1), lin(d0, d1, c0, c1), lin(c0, c1, a0, a1)
    da, ac, bc = lin(d0, d1, a0, a1), lin(a0, a1, c0, c1), lin(b0, b1, c0, c1)
    T1, T2, T3, T4 = cross(ba, ca), cross(ba, da), cross(dc, ac), cross(dc, bc)
    h = []
    for k in range(3):
        h += [[-v for v in bmul(T1[k], T2[k])], [-v for v in bmul(T3[k], T4[k])]]
    return [dot(cross(ba, dc), ca)] + h


def check(kind, x):
    x = np.asarray(x, float)
    lo, hi = C.time_axis_enclosures(kind, x)
    polys = exact_vf(x) if kind == "vf" else exact_ee(x)
    coeffs = [c for poly in polys for c in poly]
    assert len(coeffs) == len(lo) == len(hi)
    for i, c in enumerate(coeffs):
        assert Fr(lo[i]) <= c <= Fr(hi[i]), (kind, i, float(c), lo[i], hi[i])
    return polys


def cases(seed):
    """Eight-point configurations (rows: the test's arguments in order) of several kinds."""
    rng = np.random.default_rng(seed)
    out = [rng.uniform(-2, 2, (8, 3))]
    # Cancellation: far from the origin, tiny motion and tiny features.
    base = rng.uniform(-1, 1, 3) * 1e6
    out.append(base + rng.uniform(-1, 1, (8, 3)) * 1e-7)
    # Nearly coplanar: every point within 1e-12 of the plane z = 0.5, moving little.
    y = rng.uniform(-1, 1, (8, 3))
    y[:, 2] = 0.5 + rng.uniform(-1, 1, 8) * 1e-12
    out.append(y)
    # The two ends of the supported range (non-zero magnitudes in [2^-128, 2^128]).
    out.append(rng.uniform(1, 2, (8, 3)) * rng.choice([-1.0, 1.0], (8, 3)) * 2.0**-128)
    out.append(rng.uniform(0.5, 1, (8, 3)) * rng.choice([-1.0, 1.0], (8, 3)) * 2.0**127)
    # Mixed scales, with exact zeros.
    z = rng.uniform(-1, 1, (8, 3)) * 2.0 ** rng.integers(-120, 120, (8, 3)).astype(float)
    z[rng.random((8, 3)) < 0.3] = 0.0
    out.append(z)
    return out


@pytest.mark.parametrize("seed", range(40))
@pytest.mark.parametrize("kind", ["vf", "ee"])
def test_enclosures_hold_the_exact_coefficients(kind, seed):
    for x in cases(seed):
        check(kind, x)


@pytest.mark.parametrize("kind", ["vf", "ee"])
def test_twin_coefficients_are_the_polynomials(kind):
    """The twin itself: its Bernstein coefficients evaluate to f and the conditions computed
    directly from the positions at rational t."""
    rng = np.random.default_rng(7)
    for _ in range(5):
        x = rng.uniform(-2, 2, (8, 3))
        polys = check(kind, x)
        for t in (Fr(0), Fr(1, 3), Fr(1, 2), Fr(1)):
            P = [ex.lerp(x[i], x[i + 4], t) for i in range(4)]
            if kind == "vf":
                p, a, b, c = P
                n = ex.cross(ex.sub(b, a), ex.sub(c, a))
                o = [ex.cross(ex.sub(b, a), ex.sub(p, a)), ex.cross(ex.sub(c, b), ex.sub(p, b)),
                     ex.cross(ex.sub(a, c), ex.sub(p, c))]
                direct = [ex.dot(n, ex.sub(p, a))] + [o[i][k] * n[k] for i in range(3) for k in range(3)]
            else:
                a, b, c, d = P
                T1, T2 = ex.cross(ex.sub(b, a), ex.sub(c, a)), ex.cross(ex.sub(b, a), ex.sub(d, a))
                T3, T4 = ex.cross(ex.sub(d, c), ex.sub(a, c)), ex.cross(ex.sub(d, c), ex.sub(b, c))
                direct = [ex.dot(ex.cross(ex.sub(b, a), ex.sub(d, c)), ex.sub(c, a))]
                for k in range(3):
                    direct += [-T1[k] * T2[k], -T3[k] * T4[k]]
            assert [bern_value(c, t) for c in polys] == direct


def test_bad_arguments():
    with pytest.raises(ValueError, match="kind"):
        C.time_axis_enclosures("vv", np.zeros((8, 3)))
    with pytest.raises(ValueError, match="points"):
        C.time_axis_enclosures("vf", np.zeros((7, 3)))
    with pytest.raises(ValueError, match="points"):
        C.time_axis_enclosures("ee", np.full((8, 3), 2.0**200))
