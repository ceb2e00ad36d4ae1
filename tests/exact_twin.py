"""Exact-arithmetic twins (fractions.Fraction) of the formulas the core evaluates in floating point.

Every function takes float coordinates, converts them exactly, and returns exact values or signs.
These are derived from the paper independently of the C++ code (see README, "Verified formulas").
"""

from __future__ import annotations

from fractions import Fraction as Fr


def fr3(p):
    return tuple(Fr(float(x)) for x in p)


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def sgn(x) -> int:
    return (x > 0) - (x < 0)


def orient3d(a, b, c, d) -> int:
    a, b, c, d = map(fr3, (a, b, c, d))
    return sgn(dot(cross(sub(b, a), sub(c, a)), sub(d, a)))


def orient2d(a, b, c) -> int:
    a, b, c = ([Fr(float(x)) for x in p] for p in (a, b, c))
    return sgn((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))


def side(a, b, c, l):
    """Sec. 3.3: Side(a, b, c, l) = ((a - c) x (b - c)) . l, exactly."""
    a, b, c, l = map(fr3, (a, b, c, l))
    return dot(cross(sub(a, c), sub(b, c)), l)


def side_sign(a, b, c, l) -> int:
    return sgn(side(a, b, c, l))


def ray_side_sign_literal(v, o, r, l) -> int:
    """SideSign(v, o, o + r, l) exactly as printed in Alg. 1 line 22, with o + r exact."""
    v, o, r, l = map(fr3, (v, o, r, l))
    opr = tuple(o[i] + r[i] for i in range(3))
    return sgn(dot(cross(sub(v, opr), sub(o, opr)), l))


def ray_direction(l):
    """Alg. 1 lines 3-7."""
    if l[0] == 0 and l[2] == 0:
        return (1.0, 0.0, 0.0)
    # l x (0, 1, 0)
    return (-l[2], 0.0, l[0])


def float_mean(pts):
    """The kernel point exactly as the core computes it: a float sum in order, times 1/n."""
    s = [0.0, 0.0, 0.0]
    for p in pts:
        s = [s[0] + p[0], s[1] + p[1], s[2] + p[2]]
    inv = 1.0 / len(pts)
    return (inv * s[0], inv * s[1], inv * s[2])


def contour_test(loop_pts, l, o=None, r=None):
    """Alg. 1 in exact arithmetic on the printed SideSign definitions.

    Returns (passed, reason, edge) with the C++ reason codes. `o` defaults to the float mean of
    the points computed like the core does (sum in order, times 1/n), so both test the same o;
    `r` defaults to the paper's l x (0, 1, 0).
    """
    n = len(loop_pts)
    if o is None:
        o = float_mean(loop_pts)
    if r is None:
        r = ray_direction(l)
    return star_test(n, lambda i, j: side_sign(o, loop_pts[i], loop_pts[j], l),
                     lambda i: ray_side_sign_literal(loop_pts[i], o, r, l))


def star_test(n, kernel, ray):
    """The loop of Alg. 1 / Alg. 3 given the sign functions kernel(i, j) and ray(i); returns
    (passed, reason, edge) with the core's reason codes."""
    s0, crossings = None, 0
    for i in range(n):
        j = (i + 1) % n
        s = kernel(i, j)
        if i == 0:
            s0 = s
        if s == 0:
            return False, 1, i
        if s != s0:
            return False, 2, i
        s1, s2 = ray(i), ray(j)
        if s1 == 0 or s2 == 0:
            return False, 3, i if s1 == 0 else j
        if s2 == s0 and s1 != s2:
            crossings += 1
            if crossings > 1:
                return False, 4, i
    return (True, 0, -1) if crossings == 1 else (False, 5, -1)


def triangle_normal(a, b, c):
    a, b, c = map(fr3, (a, b, c))
    return cross(sub(b, a), sub(c, a))


# ---- CCD (Sec. 3.6, Alg. 3) -----------------------------------------------------------------

def lerp(p0, p1, t):
    """Exact point of a linear trajectory at rational t."""
    p0, p1 = fr3(p0), fr3(p1)
    return tuple(p0[i] + (p1[i] - p0[i]) * t for i in range(3))


def cside1_value(o, b0, c0, b1, c1, l, t):
    """CSide1(o, b(t), c(t), l) = ((o - c(t)) x (b(t) - c(t))) . l, exactly, by its definition."""
    o, l = fr3(o), fr3(l)
    b, c = lerp(b0, b1, t), lerp(c0, c1, t)
    return dot(cross(sub(o, c), sub(b, c)), l)


def cside1_coefficients(o, b0, c0, b1, c1, l):
    """Our Bernstein coefficients (k0, k1, k2): k0 = (B0 x C0).l, k1 = (B0 x C1 + B1 x C0).l / 2,
    k2 = (B1 x C1).l with B_t = b_t - o, C_t = c_t - o."""
    o, l = fr3(o), fr3(l)
    B0, C0, B1, C1 = (sub(fr3(p), o) for p in (b0, c0, b1, c1))
    k0 = dot(cross(B0, C0), l)
    k1 = (dot(cross(B0, C1), l) + dot(cross(B1, C0), l)) / 2
    k2 = dot(cross(B1, C1), l)
    return k0, k1, k2


def cside1_printed_k2(o, b0, c0, b1, c1, l):
    """k2 exactly as printed in Sec. 3.6 (with v_c x (b0 - a))."""
    a, l = fr3(o), fr3(l)
    B0, C0 = sub(fr3(b0), a), sub(fr3(c0), a)
    vb, vc = sub(fr3(b1), fr3(b0)), sub(fr3(c1), fr3(c0))
    add = lambda u, w: tuple(u[i] + w[i] for i in range(3))  # noqa: E731
    return dot(cross(B0, C0), l) + dot(add(cross(vb, C0), cross(vc, B0)), l) + dot(cross(vb, vc), l)


def csidesign1(o, b0, c0, b1, c1, l) -> int:
    k = cside1_coefficients(o, b0, c0, b1, c1, l)
    s = sgn(k[0])
    return s if s != 0 and all(sgn(x) == s for x in k) else 0


def csidesign2(v0, v1, o, r, l) -> int:
    s0, s1 = ray_side_sign_literal(v0, o, r, l), ray_side_sign_literal(v1, o, r, l)
    return s0 if s0 != 0 and s0 == s1 else 0


def contour_test_ccd(pts0, pts1, l, r, o=None):
    """Alg. 3 in exact arithmetic (with our k2). o defaults to the core's float mean at t = 0."""
    n = len(pts0)
    if o is None:
        o = float_mean(pts0)
    return star_test(n, lambda i, j: csidesign1(o, pts0[i], pts0[j], pts1[i], pts1[j], l),
                     lambda i: csidesign2(pts0[i], pts1[i], o, r, l))
