"""Exact-arithmetic twins (fractions.Fraction) of the formulas the core evaluates in floating point.

Every function takes float coordinates, converts them exactly, and returns exact values or signs.
These are derived from the paper independently of the C++ code (see README, "Verified formulas").
"""

from __future__ import annotations

import math
from fractions import Fraction as Fr


def fr3(p):
    """Exact coordinates: floats converted exactly, Fractions (exact points at rational t) kept."""
    return tuple(x if isinstance(x, Fr) else Fr(float(x)) for x in p)


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


def cside1_value(o, b0, c0, b1, c1, l, t, o1=None):
    """CSide1(o(t), b(t), c(t), l) = ((o(t) - c(t)) x (b(t) - c(t))) . l, exactly, by its
    definition; the kernel point moves from o to o1 (default: fixed)."""
    o, l = lerp(o, o if o1 is None else o1, t), fr3(l)
    b, c = lerp(b0, b1, t), lerp(c0, c1, t)
    return dot(cross(sub(o, c), sub(b, c)), l)


def cside1_coefficients(o, b0, c0, b1, c1, l, o1=None):
    """Our Bernstein coefficients (k0, k1, k2): k0 = (B0 x C0).l, k1 = (B0 x C1 + B1 x C0).l / 2,
    k2 = (B1 x C1).l with B_t = b_t - o_t, C_t = c_t - o_t; o_t moves from o to o1 (default: fixed)."""
    o0, o1, l = fr3(o), fr3(o if o1 is None else o1), fr3(l)
    B0, C0 = sub(fr3(b0), o0), sub(fr3(c0), o0)
    B1, C1 = sub(fr3(b1), o1), sub(fr3(c1), o1)
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


def csidesign1(o, b0, c0, b1, c1, l, o1=None) -> int:
    k = cside1_coefficients(o, b0, c0, b1, c1, l, o1)
    s = sgn(k[0])
    return s if s != 0 and all(sgn(x) == s for x in k) else 0


def csidesign2(v0, v1, o, r, l, o1=None) -> int:
    s0, s1 = ray_side_sign_literal(v0, o, r, l), ray_side_sign_literal(v1, o if o1 is None else o1, r, l)
    return s0 if s0 != 0 and s0 == s1 else 0


def contour_test_ccd(pts0, pts1, l, r, o=None, o1=None):
    """Alg. 3 in exact arithmetic (with our k2), the kernel point moving from o to o1. Default:
    the core's float means at t = 0 and t = 1; o alone: fixed at o, as printed."""
    n = len(pts0)
    if o is None:
        o, o1 = float_mean(pts0), float_mean(pts1)
    return star_test(n, lambda i, j: csidesign1(o, pts0[i], pts0[j], pts1[i], pts1[j], l, o1),
                     lambda i: csidesign2(pts0[i], pts1[i], o, r, l, o1))


# ---- Baselines (Sec. 6.1): SCT [SPO10] and CBC [TCYM09] --------------------------------------

def _fsub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _fdot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _fcross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _frame(l):
    """kernel_point.hpp, projection_frame: u = l x e_k (exact), w = l x u (rounded), |u|^2, k."""
    ax, ay, az = abs(l[0]), abs(l[1]), abs(l[2])
    k = 0 if (ax <= ay and ax <= az) else (1 if ay <= az else 2)
    u = [(0.0, l[2], -l[1]), (-l[2], 0.0, l[0]), (l[1], -l[0], 0.0)][k]
    w = _fcross(l, u)
    return u, w, _fdot(u, u), k


def _frame_scale(l, u, w):
    """projection_frame's scale: the largest |u_j|, |w~_j| and max|l_j| max|u_j|."""
    mx = lambda a: max(abs(a[0]), abs(a[1]), abs(a[2]))  # noqa: E731
    return max(mx(u), mx(w), mx(l) * mx(u))


def _fproject(p, c, u, w):
    """kernel_point.hpp project(): d = fl(p - c), X = fl(d . u), Y = fl(d . w~), |d|_1."""
    d = _fsub(p, c)
    return _fdot(d, u), _fdot(d, w), abs(d[0]) + abs(d[1]) + abs(d[2])


SWEEP_PHI = 0.6180339887498949  # contour_test_simple.hpp's phi: Z_g = fl(X + phi Y), Z_h = fl(Y - phi X)


def _predicate_domain(o):
    """in_predicate_domain (kernel_point.hpp): a computed kernel point's coordinates must be 0 or
    of magnitude in [2^-128, 2^128]; tiny ones become 0 (any o is valid), a huge or non-finite one
    means no point (None)."""
    if not all(abs(x) <= 2.0**128 for x in o):
        return None
    return tuple(0.0 if abs(x) < 2.0**-128 else x for x in o)


def sct_candidate(loop_pts, l):
    """SCT's float steps replicated operation by operation (IEEE doubles, no FMA, as the core is
    built): the projection frame, the projected coordinates, and the [SPO10] line search.
    Returns (o, u, k) with o the candidate kernel point, or (None, u, k) if the search fails.
    These steps only choose o; the verdict is then exact (sct_test)."""
    l = tuple(float(x) for x in l)
    u, w, uu, k = _frame(l)
    c = tuple(float(x) for x in loop_pts[0])
    X, Y = [], []
    for p in loop_pts:
        d = _fsub(tuple(float(x) for x in p), c)
        X.append(_fdot(d, u))
        Y.append(_fdot(d, w))
    m = float_mean([tuple(float(x) for x in p) for p in loop_pts])
    dm = _fsub(m, c)
    Xm, Ym = _fdot(dm, u), _fdot(dm, w)
    inf = float("inf")
    lo, hi = [-inf, -inf], [inf, inf]
    n = len(loop_pts)
    for i in range(n):
        j = (i + 1) % n
        ex_, ey = X[j] - X[i], Y[j] - Y[i]
        if ey == 0.0:
            side_ = ex_ * (Ym - Y[i])
            if not side_ > 0:
                lo[0] = inf
            if not side_ < 0:
                lo[1] = inf
            continue
        x = X[i] + ex_ * (Ym - Y[i]) / ey
        if ey > 0:
            hi[0], lo[1] = min(hi[0], x), max(lo[1], x)
        else:
            lo[0], hi[1] = max(lo[0], x), min(hi[1], x)
    for s in range(2):
        if lo[s] < hi[s] and abs(lo[s]) != inf and abs(hi[s]) != inf:
            xo = 0.5 * (lo[s] + hi[s])
            t = (xo - Xm) / uu
            return _predicate_domain((m[0] + t * u[0], m[1] + t * u[1], m[2] + t * u[2])), u, k
    return None, u, k


MAX_KERNEL_CORNERS = 64


def clip_stride(n):
    """clip_stride (kernel_point.hpp): the largest g <= 0.618 n coprime to n (at least 1)."""
    g = n * 618 // 1000
    while g > 1 and math.gcd(g, n) != 1:
        g -= 1
    return max(g, 1)


def clipped_kernel_candidate(loop_pts, l, start=0):
    """clipped_kernel_point (kernel_point.hpp) replicated operation by operation in doubles: the
    kernel polygon of the projected loop, clipped from its bounding box one edge at a time (edges
    start, start + g, start + 2g, ... mod n, g = clip_stride(n)), and o the point over the mean of
    its corners. Returns (status, o, visited) with status "found", "empty" or "too_many_corners"
    (o None unless found). Like sct_candidate, it only chooses o."""
    l = tuple(float(x) for x in l)
    u, w, uu, _ = _frame(l)
    pts = [tuple(float(x) for x in p) for p in loop_pts]
    c = pts[0]
    n = len(pts)
    X, Y = [0.0] * n, [0.0] * n
    area2, x0, x1, y0, y1 = 0.0, 0.0, 0.0, 0.0, 0.0
    for i in range(1, n):
        d = _fsub(pts[i], c)
        X[i], Y[i] = _fdot(d, u), _fdot(d, w)
        area2 += X[i - 1] * Y[i] - X[i] * Y[i - 1]
        x0, x1, y0, y1 = min(x0, X[i]), max(x1, X[i]), min(y0, Y[i]), max(y1, Y[i])
    if not area2 != 0.0 or not x0 < x1 or not y0 < y1:
        return "empty", None, 0
    sg = 1.0 if area2 > 0 else -1.0
    poly = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    g = clip_stride(n)
    for step in range(n):
        i = ((start if 0 <= start < n else 0) + step * g) % n
        j = (i + 1) % n
        ax_, ay_ = X[i], Y[i]
        ex_, ey = X[j] - ax_, Y[j] - ay_
        if ex_ == 0.0 and ey == 0.0:
            continue
        sd = [sg * (ex_ * (q[1] - ay_) - ey * (q[0] - ax_)) for q in poly]
        if all(v > 0 for v in sd):
            continue
        out = []
        sp = sd[-1]
        for a in range(len(poly)):
            b = a - 1
            sa = sd[a]
            if (sp > 0) != (sa > 0):
                t = sp / (sp - sa)
                out.append((poly[b][0] + t * (poly[a][0] - poly[b][0]), poly[b][1] + t * (poly[a][1] - poly[b][1])))
                if len(out) > MAX_KERNEL_CORNERS:
                    return "too_many_corners", None, step + 1
            if sa > 0:
                out.append(poly[a])
                if len(out) > MAX_KERNEL_CORNERS:
                    return "too_many_corners", None, step + 1
            sp = sa
        if len(out) < 3:
            return "empty", None, step + 1
        poly = out
    sx = sy = 0.0
    for q in poly:
        sx += q[0]
        sy += q[1]
    A, B = (sx / len(poly)) / uu, (sy / len(poly)) / _fdot(w, w)
    o = _predicate_domain(tuple(c[i] + A * u[i] + B * w[i] for i in range(3)))
    return ("found", o, n) if o is not None else ("empty", None, n)


def kernel_candidate(loop_pts, l, start=0):
    """find_kernel_point: the clipped kernel's point (clipping from edge `start`), or [SPO10]'s
    line-search point when the kernel polygon has too many corners; None if neither finds one."""
    status, o, _ = clipped_kernel_candidate(loop_pts, l, start)
    if status == "too_many_corners":
        return sct_candidate(loop_pts, l)[0]
    return o


def retry_kernel(first_reason, first_edge, loop_pts, l):
    """The second kernel point the core tries (contour_test.hpp, with_kernel_retry): after the
    mean failed the kernel test or the ray crossed twice (reasons 1, 2, 4) at edge first_edge,
    kernel_candidate clipping from that edge; else None (the first verdict stands)."""
    if first_reason not in (1, 2, 4):
        return None
    return kernel_candidate(loop_pts, l, first_edge)


def kernel_area(loop_pts, l):
    """Exactly: twice the area of the kernel of the loop projected along l (in the coordinates
    (p . u, p . w) with w = l x u, a linear map of the plane perpendicular to l), 0 if the kernel
    has no interior; twice the area of the loop's bounding box in the same coordinates; and the
    ratio of the shortest projected edge to the box's diagonal, squared."""
    l = fr3(l)
    ax, ay, az = abs(l[0]), abs(l[1]), abs(l[2])
    k = 0 if (ax <= ay and ax <= az) else (1 if ay <= az else 2)
    u = [(0, l[2], -l[1]), (-l[2], 0, l[0]), (l[1], -l[0], 0)][k]
    w = cross(l, u)
    P = [(dot(fr3(p), u), dot(fr3(p), w)) for p in loop_pts]
    n = len(P)
    area2 = sum(P[i][0] * P[(i + 1) % n][1] - P[(i + 1) % n][0] * P[i][1] for i in range(n))
    xs, ys = [p[0] for p in P], [p[1] for p in P]
    box2 = 2 * (max(xs) - min(xs)) * (max(ys) - min(ys))
    diag2 = (max(xs) - min(xs)) ** 2 + (max(ys) - min(ys)) ** 2
    short2 = min((P[(i + 1) % n][0] - P[i][0]) ** 2 + (P[(i + 1) % n][1] - P[i][1]) ** 2 for i in range(n))
    short2 = short2 / diag2 if diag2 else Fr(0)
    if area2 == 0:
        return Fr(0), box2, short2
    sg = 1 if area2 > 0 else -1
    poly = [(min(xs), min(ys)), (max(xs), min(ys)), (max(xs), max(ys)), (min(xs), max(ys))]
    for i in range(n):
        a, b = P[i], P[(i + 1) % n]
        sd = [sg * ((b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0])) for q in poly]
        out = []
        for j in range(len(poly)):
            sp, sa = sd[j - 1], sd[j]
            if (sp > 0) != (sa > 0):
                t = sp / (sp - sa)
                out.append(tuple(poly[j - 1][d] + t * (poly[j][d] - poly[j - 1][d]) for d in range(2)))
            if sa > 0:
                out.append(poly[j])
        if len(out) < 3:
            return Fr(0), box2, short2
        poly = out
    m = len(poly)
    return abs(sum(poly[i][0] * poly[(i + 1) % m][1] - poly[(i + 1) % m][0] * poly[i][1] for i in range(m))), box2, short2


SCT_RAY_SLOPES = (0.6180339887498949, -1.3247179572447460)


def sct_test(loop_pts, l):
    """SCT with exact signs: the candidate o of sct_candidate, then the star test (Sec. 3.3) on the
    exact projections, whose orientations are Side (Sec. 3.4); the ray r = u + phi e_k of the
    first slope, then of the second if the first passes through a vertex. Returns (passed, reason, edge, o, r) with the core's codes."""
    o, u, k = sct_candidate(loop_pts, l)
    if o is None:
        return False, 6, -1, None, None
    n = len(loop_pts)
    kernel = lambda i, j: side_sign(o, loop_pts[i], loop_pts[j], l)  # noqa: E731
    for phi in SCT_RAY_SLOPES:
        r = tuple(phi if i == k else u[i] for i in range(3))  # u + phi e_k (u_k = 0)
        passed, reason, edge = star_test(n, kernel, lambda i: ray_side_sign_literal(loop_pts[i], o, r, l))
        if reason != 3:
            break
    return passed, reason, edge, o, r


def _strict(s):
    return s in (1, -1)


def _cbc_pairs(n, side, along_dir, along):
    """The O(n^2) pair loop of [TCYM09] on sign functions that hold over the whole motion
    (2 = not one sign throughout); returns (passed, reason, edge, other_edge)."""
    def apart(a, b, c, d):
        s1, s2, s3, s4 = side(a, b, c), side(a, b, d), side(c, d, a), side(c, d, b)
        if _strict(s1) and s1 == s2 or _strict(s3) and s3 == s4:
            return True
        if (s1, s2, s3, s4) != (0, 0, 0, 0):
            return False
        nv = along_dir(a, b)
        g = along(c, a, nv)
        return _strict(g) and along(c, b, nv) == g and along(d, a, nv) == g and along(d, b, nv) == g

    def adjacent(a, b, c):
        t = side(a, b, c)
        if _strict(t):
            return True
        if t != 0:
            return False
        nv = along_dir(a, b)
        ga = along(a, b, nv)
        return _strict(ga) and along(c, b, nv) == -ga

    for i in range(n):
        i1 = (i + 1) % n
        for j in range(i + 1, n):
            j1 = (j + 1) % n
            if j == i1:
                ok = adjacent(i, i1, j1)
            elif j1 == i:
                ok = adjacent(j, i, i1)
            else:
                ok = apart(i, i1, j, j1)
            if not ok:
                return False, 7, i, j
    return True, 0, -1, -1


def cbc_test_ccd(pts0, pts1, l):
    """CBC over a linear step with exact signs: Side(a(t), b(t), c(t), l) by its Bernstein
    coefficients (all three of one strict sign, or all zero), f(p(t)) - f(q(t)) by its values at
    t = 0 and t = 1; n of f from edge (a, b) at t = 0, rounded as the core does."""
    lq = fr3(l)

    def side(a, b, c):
        A0, B0 = sub(fr3(pts0[a]), fr3(pts0[c])), sub(fr3(pts0[b]), fr3(pts0[c]))
        A1, B1 = sub(fr3(pts1[a]), fr3(pts1[c])), sub(fr3(pts1[b]), fr3(pts1[c]))
        k = (dot(cross(A0, B0), lq), dot(cross(A0, B1), lq) + dot(cross(A1, B0), lq), dot(cross(A1, B1), lq))
        s = [sgn(x) for x in k]
        if s == [0, 0, 0]:
            return 0
        return s[0] if s[0] != 0 and s[0] == s[1] == s[2] else 2

    def along_dir(a, b):
        lf = tuple(float(x) for x in l)
        return _fcross(lf, _fsub(tuple(float(x) for x in pts0[b]), tuple(float(x) for x in pts0[a])))

    def along(p, q, nv):
        s0 = ray_side_sign_literal(pts0[p], pts0[q], nv, l)
        s1 = ray_side_sign_literal(pts1[p], pts1[q], nv, l)
        return s0 if s0 != 0 and s0 == s1 else 2

    return _cbc_pairs(len(pts0), side, along_dir, along)


def cbc_test(pts, l):
    """CBC at one pose (the DCD use): the CCD test with no motion."""
    return cbc_test_ccd(pts, pts, l)


def det3(p, q, r):
    """det[p; q; r] = p . (q x r), exact."""
    return dot(p, cross(q, r))


def coplanarity_rows(kind, x0, x1):
    """The rows of the coplanarity determinant of a VF pair (x = v, a, b, c: b - a, c - a, v - a)
    or an EE pair (x = a, b, c, d: b - a, d - c, c - a), at t = 0 and at t = 1, exact."""
    def rows(x):
        x = [fr3(p) for p in x]
        if kind == "vf":
            v, a, b, c = x
            return sub(b, a), sub(c, a), sub(v, a)
        a, b, c, d = x
        return sub(b, a), sub(d, c), sub(c, a)
    return rows(x0), rows(x1)


def coplanarity_cubic(rows0, rows1, t):
    """det[p(t); q(t); r(t)] with each row moving linearly from rows0 to rows1 (t exact)."""
    return det3(*[tuple(u + t * (w - u) for u, w in zip(r0, r1)) for r0, r1 in zip(rows0, rows1)])


def coplanarity_bernstein(rows0, rows1):
    """The cubic's Bernstein coefficients, derived from trilinearity: blossom values at (0,0,0),
    (0,0,1) symmetrised, (0,1,1) symmetrised, (1,1,1); b1 and b2 carry the 1/3."""
    (p0, q0, r0), (p1, q1, r1) = rows0, rows1
    return (det3(p0, q0, r0),
            (det3(p1, q0, r0) + det3(p0, q1, r0) + det3(p0, q0, r1)) / 3,
            (det3(p1, q1, r0) + det3(p1, q0, r1) + det3(p0, q1, r1)) / 3,
            det3(p1, q1, r1))


def never_coplanar(kind, x0, x1) -> bool:
    """The non-penetration filter's exact answer: all four Bernstein coefficients of one strict sign."""
    s = {sgn(c) for c in coplanarity_bernstein(*coplanarity_rows(kind, x0, x1))}
    return s == {1} or s == {-1}
