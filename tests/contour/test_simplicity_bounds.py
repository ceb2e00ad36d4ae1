"""The rounding bounds the simplicity fallback rests on (contour_test_simple.hpp), against an
exact twin: the float arithmetic of project() and of the (g, h) coordinates replayed in Python
(IEEE doubles, the same operations in the same order; the core is built without contraction), and
the exact values in fractions with the exact frame w = l x u. If a bound in the comments were
wrong (a printed constant too small), a separation or a turn would be "proven" from rounded values
that do not prove it; these tests measure the worst error on adversarial inputs and compare it to
the constants the code uses. (Measured worst: about 1.4 eps D1 scale for X, Y, g, h and 3-4.4
eps (D1 scale)^2 for the products: the analytic bounds hold with a wide margin.)"""

from fractions import Fraction as Fr

import numpy as np
import pytest

import exact_twin as ex

EPS = Fr(1, 2**53)
PHI = ex.SWEEP_PHI


def _case(rng, k):
    """Points around an offset, at scales from 1e-30 to 1e30, some nearly collinear, and a random
    axis (not unit): the inputs where the rounded and exact values part most."""
    scale = 10.0 ** rng.uniform(-30, 30)
    offset = rng.uniform(-1, 1, 3) * scale * (10.0 ** rng.uniform(0, 6) if k % 3 == 0 else 1.0)
    P = offset + scale * rng.uniform(-1, 1, (4, 3))
    if k % 3 == 1:  # c nearly on the line through a and b, on either side of b
        t = rng.choice([-1.0, 1.0]) * rng.uniform(0.1, 2.0)
        P[2] = P[1] + t * (P[0] - P[1]) + 1e-12 * scale * rng.uniform(-1, 1, 3)
    l = rng.uniform(-1, 1, 3) * 10.0 ** rng.uniform(-3, 3)
    return [tuple(map(float, p)) for p in P], tuple(map(float, l))


def _coords(P, l):
    """Rounded (g, h) of each point (as the core), their exact values, and D1 scale (computed)."""
    u, w, _, _ = ex._frame(l)
    c = P[0]
    lf, uf = ex.fr3(l), ex.fr3(u)
    w_exact = ex.cross(lf, uf)
    phi = Fr(PHI)
    rounded, exact, d1 = [], [], 0.0
    for p in P:
        X, Y, n1 = ex._fproject(p, c, u, w)
        d1 = max(d1, n1)
        rounded.append((X + PHI * Y, Y - PHI * X, X, Y))
        dp = ex.sub(ex.fr3(p), ex.fr3(c))
        Xs, Ys = ex.dot(dp, uf), ex.dot(dp, w_exact)
        exact.append((Xs + phi * Ys, Ys - phi * Xs, Xs, Ys))
    return rounded, exact, Fr(d1) * Fr(ex._frame_scale(l, u, w))


def test_projection_and_sweep_coordinates_within_their_bounds():
    """|X - X*|, |Y - Y*| <= 9 eps D1 scale (project, kernel_point.hpp) and |Z - Z*| <= 18 eps D1
    scale for Z = g, h (the sweep's separating axes): the worst measured stays below."""
    rng = np.random.default_rng(11)
    worst_xy = worst_z = Fr(0)
    for k in range(300):
        P, l = _case(rng, k)
        rounded, exact, ds = _coords(P, l)
        if ds == 0:
            continue
        for r, e in zip(rounded, exact):
            worst_z = max(worst_z, abs(Fr(r[0]) - e[0]) / (EPS * ds), abs(Fr(r[1]) - e[1]) / (EPS * ds))
            worst_xy = max(worst_xy, abs(Fr(r[2]) - e[2]) / (EPS * ds), abs(Fr(r[3]) - e[3]) / (EPS * ds))
    assert worst_xy <= 9 and worst_z <= 18, (float(worst_xy), float(worst_z))
    assert worst_z > 0.5  # the inputs do round (a twin that never rounds proves nothing)


def _turn_products(v):
    """turn_apart's dot and cross of A = a - b, C = c - b over points (g, h) (floats or fractions)."""
    (ga, ha), (gb, hb), (gc, hc) = v
    ag, ah, cg, ch = ga - gb, ha - hb, gc - gb, hc - hb
    return ag * cg + ah * ch, ag * ch - ah * cg


@pytest.mark.parametrize("poses", [1, 2])
def test_turn_products_within_the_bound(poses):
    """turn_apart's products, rounded vs exact: k0 and k2 within 551 eps (D1 scale)^2, the four
    products of 2 k1 within 1188 (the derivation in contour_test_simple.hpp); the code tests
    against 1024 and 2048. D1 scale is over all the points of both poses, as in the sweep."""
    rng = np.random.default_rng(12 + poses)
    worst = {"k0": Fr(0), "k1": Fr(0)}
    for k in range(300):
        P, l = _case(rng, k)
        Q = [P[:3]] if poses == 1 else [P[:3], [tuple(x + 0.3 * y for x, y in zip(p, P[3])) for p in P[:3]]]
        rounded, exact, ds = _coords([p for pose in Q for p in pose], l)
        if ds == 0:
            continue
        unit = EPS * ds * ds
        r = [[x[:2] for x in rounded[3 * i:3 * i + 3]] for i in range(poses)]
        e = [[x[:2] for x in exact[3 * i:3 * i + 3]] for i in range(poses)]
        for i in range(poses):  # k0 (and k2): dot and cross at one pose
            for fr, xe in zip(_turn_products(r[i]), _turn_products(e[i])):
                worst["k0"] = max(worst["k0"], abs(Fr(fr) - xe) / unit)
        if poses == 2:  # 2 k1 = P(A0, C1) + P(A1, C0), as turn_apart sums it
            def mixed(v0, v1, exact_arith):
                a0 = [v0[0][j] - v0[1][j] for j in (0, 1)]
                c0 = [v0[2][j] - v0[1][j] for j in (0, 1)]
                a1 = [v1[0][j] - v1[1][j] for j in (0, 1)]
                c1 = [v1[2][j] - v1[1][j] for j in (0, 1)]
                dot = a0[0] * c1[0] + a0[1] * c1[1] + a1[0] * c0[0] + a1[1] * c0[1]
                crs = a0[0] * c1[1] - a0[1] * c1[0] + a1[0] * c0[1] - a1[1] * c0[0]
                return dot, crs
            for fr, xe in zip(mixed(r[0], r[1], False), mixed(e[0], e[1], True)):
                worst["k1"] = max(worst["k1"], abs(Fr(fr) - xe) / unit)
    assert worst["k0"] <= 551, float(worst["k0"])
    assert worst["k0"] > 1  # rounding happened
    if poses == 2:
        assert worst["k1"] <= 1188, float(worst["k1"])
