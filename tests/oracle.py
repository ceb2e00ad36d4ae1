"""Brute-force exact oracle for triangle-mesh self-collision.

Definition (the one the C++ core is checked against)
----------------------------------------------------
For faces i < j let T_i, T_j be the CLOSED triangles (convex hulls of the three
vertex positions; a triangle may be degenerate: a segment or a point).  Let S be
the convex hull of the positions of the vertex INDICES the two faces share
(hull of nothing = empty set).  The pair (i, j) collides iff

    (T_i  intersect  T_j)  is not a subset of  S.

Algorithm
---------
All arithmetic is exact (``fractions.Fraction``; every float64 coordinate is
converted with ``Fraction(float(x))``, which is exact).  P = T_i ∩ T_j is convex
and S ⊆ P, so P ⊄ S iff some extreme point of P lies outside S.  Every extreme
point of P is one of the candidate points

  * a vertex of one triangle lying in the other triangle, or
  * an endpoint of the sub-segment (edge ∩ other triangle), for each of the
    three edges of each triangle (degenerate triangles included).

(Proof sketch: let x be extreme in P and F_i, F_j the minimal faces of T_i, T_j
containing x.  If both were 2-dimensional, x would lie in the relative interior
of both triangles, and two planes through x meet in at least a line through x,
so x would not be extreme.  Hence x lies on an edge e (or is a vertex) of one
triangle; then x is extreme in e ∩ other ⊆ P, i.e. an endpoint of it.)

Hence: compute all candidates, the pair collides iff some candidate is not in S.

"x lies in the closed hull(a, b, c)" is expressed as affine constraints
f(x) = w·x + w0 (equalities ``= 0`` and inequalities ``>= 0``).  Evaluated on a
segment x(t) = p + t (q - p) each becomes g0 + g1 t, which is clipped against
t ∈ [0, 1].

An optional exact separating-plane shortcut (``fast=True``, default) only skips
work in situations where the full test provably returns False; the test-suite
checks that both paths agree.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

__all__ = ["triangle_pair_collides", "brute_force_pairs", "aabb_candidate_pairs"]

# Exact numbers: ints or Fractions (ints are used after exact rescaling, see
# _to_common_integers; every formula below is valid for both).
_ZERO = 0
_ONE = 1


# ---------------------------------------------------------------------------
# tiny exact vector helpers (points are 3-tuples of Fractions)
# ---------------------------------------------------------------------------

def _F(x) -> Fraction:
    if isinstance(x, Fraction):
        return x
    if isinstance(x, int) and not isinstance(x, bool):
        return Fraction(x)
    return Fraction(float(x))


def _to_common_integers(points):
    """Scale exact rational points by one positive integer D (the lcm of all
    denominators) so that every coordinate becomes an int.

    The collision predicate is invariant under the uniform scaling x -> D x
    (intersections, convex hulls and containment are preserved), and the
    scaling is exact, so this only speeds up the arithmetic.
    """
    D = 1
    for p in points:
        for c in p:
            D = math.lcm(D, c.denominator)
    return [tuple(int(c * D) for c in p) for p in points]


def _pt(p) -> tuple:
    p = tuple(p)
    if len(p) != 3:
        raise ValueError("points must have 3 coordinates")
    return (_F(p[0]), _F(p[1]), _F(p[2]))


def _sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0])


def _is_zero(v) -> bool:
    return v[0] == 0 and v[1] == 0 and v[2] == 0


def _lerp(p, q, t):
    if t == 0:
        return p
    if t == 1:
        return q
    return (p[0] + t * (q[0] - p[0]),
            p[1] + t * (q[1] - p[1]),
            p[2] + t * (q[2] - p[2]))


# ---------------------------------------------------------------------------
# hull(a, b, c) as affine constraints
# ---------------------------------------------------------------------------

def _affine(w, anchor):
    """Functional f(x) = w · (x - anchor), stored as (w, w0)."""
    return (w, -_dot(w, anchor))


def _hull_constraints(a, b, c):
    """Constraints describing the closed convex hull of points a, b, c.

    Returns (eqs, ineqs): lists of (w, w0); x is in the hull iff
    w·x + w0 == 0 for every eq and w·x + w0 >= 0 for every ineq.
    """
    ab = _sub(b, a)
    ac = _sub(c, a)
    n = _cross(ab, ac)
    if not _is_zero(n):
        # (x-a)·n = 0 ;  ((b-a)×(x-a))·n = (x-a)·(n×(b-a)) >= 0, etc.
        eqs = [_affine(n, a)]
        ineqs = [_affine(_cross(n, ab), a),
                 _affine(_cross(n, _sub(c, b)), b),
                 _affine(_cross(n, _sub(a, c)), c)]
        return eqs, ineqs
    # collinear (or coincident) vertices
    pairs = [(a, b), (b, c), (a, c)]
    best = None
    best_len = -1
    for m, M in pairs:
        d = _sub(M, m)
        L = _dot(d, d)
        if L > best_len:
            best, best_len = (m, M), L
    if best_len == 0:
        # all three equal: x = a
        eqs = [(((_ONE, _ZERO, _ZERO)), -a[0]),
               (((_ZERO, _ONE, _ZERO)), -a[1]),
               (((_ZERO, _ZERO, _ONE)), -a[2])]
        return eqs, []
    m, M = best
    d = _sub(M, m)
    # (x-m) × d = 0, component-wise
    eqs = [_affine((_ZERO, d[2], -d[1]), m),
           _affine((-d[2], _ZERO, d[0]), m),
           _affine((d[1], -d[0], _ZERO), m)]
    # 0 <= (x-m)·d <= |d|^2
    neg_d = (-d[0], -d[1], -d[2])
    ineqs = [_affine(d, m),
             (neg_d, best_len + _dot(d, m))]
    return eqs, ineqs


def _clip_segment(p, q, cons):
    """Sub-interval [lo, hi] of t in [0, 1] with p + t (q-p) in the hull, or None."""
    eqs, ineqs = cons
    lo, hi = _ZERO, _ONE
    for w, w0 in eqs:
        g0 = _dot(w, p) + w0
        g1 = _dot(w, q) + w0 - g0
        if g1 == 0:
            if g0 != 0:
                return None
        else:
            t = Fraction(-g0, g1)
            if t < lo or t > hi:
                return None
            lo = hi = t
    for w, w0 in ineqs:
        g0 = _dot(w, p) + w0
        g1 = _dot(w, q) + w0 - g0
        # g0 + g1 t >= 0
        if g1 == 0:
            if g0 < 0:
                return None
        elif g1 > 0:
            t = Fraction(-g0, g1)
            if t > lo:
                lo = t
        else:
            t = Fraction(-g0, g1)
            if t < hi:
                hi = t
        if lo > hi:
            return None
    return lo, hi


def _point_in(x, cons) -> bool:
    eqs, ineqs = cons
    for w, w0 in eqs:
        if _dot(w, x) + w0 != 0:
            return False
    for w, w0 in ineqs:
        if _dot(w, x) + w0 < 0:
            return False
    return True


# ---------------------------------------------------------------------------
# pair test
# ---------------------------------------------------------------------------

def _candidates(A, consB):
    """Candidate extreme points contributed by triangle A against hull B."""
    for v in A:
        if _point_in(v, consB):
            yield v
    for k in range(3):
        p, q = A[k], A[(k + 1) % 3]
        iv = _clip_segment(p, q, consB)
        if iv is not None:
            lo, hi = iv
            yield _lerp(p, q, lo)
            if hi != lo:
                yield _lerp(p, q, hi)


def _separates(w, o, P, Q, s_points) -> bool:
    """Exact sufficient condition for (P ∩ Q) ⊆ S using the plane w·(x-o) = 0.

    If P lies in one closed half-space and Q in the other, P ∩ Q ⊆ H.  With P
    on one closed side, P ∩ H is the hull of the vertices of P lying on H; if
    all of those are S points then P ∩ Q ⊆ P ∩ H ⊆ S (likewise for Q).
    Returns (proved, sp, sq) where sp, sq are the signed values.
    """
    sp = [_dot(w, _sub(v, o)) for v in P]
    sq = [_dot(w, _sub(v, o)) for v in Q]
    ok = ((all(s >= 0 for s in sp) and all(s <= 0 for s in sq)) or
          (all(s <= 0 for s in sp) and all(s >= 0 for s in sq)))
    if ok:
        if all(v in s_points for v, s in zip(P, sp) if s == 0):
            return True, sp, sq
        if all(v in s_points for v, s in zip(Q, sq) if s == 0):
            return True, sp, sq
    return False, sp, sq


def _shortcut(P, Q, s_points) -> bool:
    """True if cheap exact separating-plane arguments prove (P ∩ Q) ⊆ S.

    Only ever used to skip the full test when it would return False anyway.
    Planes tried: the plane of Q, the plane of P and, when the two triangles
    are coplanar, the planes through each edge perpendicular to that plane.
    """
    nQ = _cross(_sub(Q[1], Q[0]), _sub(Q[2], Q[0]))
    coplanar = False
    if not _is_zero(nQ):
        proved, sp, _ = _separates(nQ, Q[0], P, Q, s_points)
        if proved:
            return True
        coplanar = all(s == 0 for s in sp)
    nP = _cross(_sub(P[1], P[0]), _sub(P[2], P[0]))
    if not _is_zero(nP) and not coplanar:
        proved, _, _ = _separates(nP, P[0], P, Q, s_points)
        if proved:
            return True
    if coplanar:
        for T in (P, Q):
            for k in range(3):
                x, y = T[k], T[(k + 1) % 3]
                w = _cross(nQ, _sub(y, x))
                if _is_zero(w):
                    continue
                if _separates(w, x, P, Q, s_points)[0]:
                    return True
    return False


def _collides(P, Q, shared, fast=True, consP=None, consQ=None) -> bool:
    shared = sorted(set(int(k) for k in shared))
    for k in shared:
        if not 0 <= k < 3:
            raise ValueError("shared_P_idx entries must be in {0, 1, 2}")
    if len(shared) == 3:
        return False  # T_i = T_j = S
    s_pts = [P[k] for k in shared]
    if fast:
        s_set = set(s_pts)
        if _shortcut(P, Q, s_set):
            return False
    if s_pts:
        while len(s_pts) < 3:
            s_pts.append(s_pts[-1])
        consS = _hull_constraints(*s_pts)
    else:
        consS = None
    if consP is None:
        consP = _hull_constraints(*P)
    if consQ is None:
        consQ = _hull_constraints(*Q)
    for A, consB in ((P, consQ), (Q, consP)):
        for x in _candidates(A, consB):
            if consS is None or not _point_in(x, consS):
                return True
    return False


def triangle_pair_collides(P, Q, shared_P_idx=(), *, fast=True,
                           exact_ints=True) -> bool:
    """Exact collision test of two closed triangles.

    P, Q: 3x3 array-likes (rows = vertex positions; floats are converted with
    ``Fraction(float(x))``; Fractions/ints are used as is).
    shared_P_idx: indices k in {0,1,2} of the vertices of P that are shared
    (same vertex index) with Q.  S is the convex hull of {P[k]}.  The caller
    guarantees that each such P[k] also is a vertex position of Q.
    Returns True iff (P ∩ Q) ⊄ S.
    ``fast=False`` disables the (provably conservative) separating-plane
    shortcut; ``exact_ints=False`` computes directly on the Fractions instead
    of on the exactly rescaled integer coordinates (same result, slower).
    """
    P3 = [_pt(v) for v in P]
    Q3 = [_pt(v) for v in Q]
    if len(P3) != 3 or len(Q3) != 3:
        raise ValueError("triangles must have exactly 3 vertices")
    if exact_ints:
        pts = _to_common_integers(P3 + Q3)
        P3, Q3 = pts[:3], pts[3:]
    return _collides(tuple(P3), tuple(Q3), shared_P_idx, fast=fast)


# ---------------------------------------------------------------------------
# whole-mesh brute force
# ---------------------------------------------------------------------------

def aabb_candidate_pairs(faces, V, chunk=256):
    """All (i, j), i < j, whose closed float AABBs overlap (exact comparisons).

    Returns an int64 array of shape (k, 2), sorted lexicographically.
    """
    faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    V = np.asarray(V, dtype=np.float64).reshape(-1, 3)
    m = len(faces)
    if m < 2:
        return np.zeros((0, 2), dtype=np.int64)
    T = V[faces]  # (m, 3, 3)
    lo = T.min(axis=1)
    hi = T.max(axis=1)
    out = []
    for s in range(0, m, chunk):
        e = min(m, s + chunk)
        # rows i in [s, e), columns j in (i, m)
        ov = np.all(lo[s:e, None, :] <= hi[None, :, :], axis=2)
        ov &= np.all(lo[None, :, :] <= hi[s:e, None, :], axis=2)
        ii, jj = np.nonzero(ov)
        ii = ii + s
        keep = jj > ii
        out.append(np.stack([ii[keep], jj[keep]], axis=1))
    return np.concatenate(out, axis=0).astype(np.int64)


def brute_force_pairs(faces, V, *, prefilter=True, fast=True,
                      exact_ints=True) -> set:
    """Set of colliding face pairs (i, j), i < j, by the exact definition.

    faces: int array (m, 3); V: float64 array (n, 3).
    prefilter=False tests all m(m-1)/2 pairs (slow; used to validate the
    AABB prefilter).  fast / exact_ints: see triangle_pair_collides.
    """
    faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    V = np.asarray(V, dtype=np.float64).reshape(-1, 3)
    m = len(faces)
    if m and (faces.min() < 0 or faces.max() >= len(V)):
        raise ValueError("face index out of range")
    if not np.all(np.isfinite(V)):
        raise ValueError("non-finite vertex coordinates")
    if prefilter:
        cand = aabb_candidate_pairs(faces, V)
        pair_iter = ((int(i), int(j)) for i, j in cand)
    else:
        pair_iter = ((i, j) for i in range(m) for j in range(i + 1, m))

    # exact coordinates of every referenced vertex (Fraction(float(x))), then
    # one common exact rescaling of the whole mesh to integers
    used = sorted(set(faces.ravel().tolist()))
    Vl = V.tolist()
    pts = [_pt(Vl[k]) for k in used]
    if exact_ints:
        pts = _to_common_integers(pts)
    vmap = dict(zip(used, pts))
    vert = vmap.__getitem__

    flist = faces.tolist()
    tris = [None] * m
    cons = [None] * m

    def tri(i):
        t = tris[i]
        if t is None:
            t = tuple(vert(k) for k in flist[i])
            tris[i] = t
        return t

    def hull(i):
        c = cons[i]
        if c is None:
            c = _hull_constraints(*tri(i))
            cons[i] = c
        return c

    result = set()
    for i, j in pair_iter:
        fi, fj = flist[i], flist[j]
        sj = set(fj)
        shared = [k for k in range(3) if fi[k] in sj]
        if len(set(fi[k] for k in shared)) == 3:
            continue
        P, Q = tri(i), tri(j)
        if _collides(P, Q, shared, fast=fast, consP=hull(i), consQ=hull(j)):
            result.add((i, j))
    return result
