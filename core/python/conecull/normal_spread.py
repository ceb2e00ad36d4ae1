"""Why a normal cone failed: do the node's normals fit in an open hemisphere?

Alg. 2 line 5 skips the contour test of a node whose normal cone is not bounded below 180 degrees.
The core's cones are merged bottom-up from the children's (Sec. 3.6) and widened for rounding, so
a failed cone test means one of two things, told apart here with a witness checked exactly:

- "beyond": the normals span a hemisphere or more. The origin lies in the convex hull of 1 to 4
  of them, so by Gordan's alternative no axis l has l . n > 0 for them all: no cone, however
  tight, holds them below 180 degrees. Witness: those triangles (one alone: it has no normal).
- "within": an axis l has l . n > 0 for every normal, so a cone about l is bounded below 180
  degrees: the test failed on the bound (the merge of the children's cones, or a normal too small
  to resolve in floating point), not on the shape of the patch. Witness: l.
- "undecided": neither witness the floating-point search found survived the exact check.

Normals are the exact n = (b - a) x (c - a) of the double coordinates, as the cones bound them
(normal_cone.hpp). For CCD they are each triangle's Bernstein control vectors n0, 2 n1, n2 over the
step, which the CCD cones bound (ccd_cone.hpp): a cone holding them holds n(t) for every t.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

EPS = 2.0**-53
# The float filter on sign(l . (u x w)) (u, w rounded differences, l exact): the rounded value is
# within 7 eps of the sum of the absolute products (Shewchuk's orient3d bound, as det_sum.hpp);
# twice that covers a sum of two such determinants (CCD's 2 n1) and the rounding of the bound.
FILTER = 16.0 * EPS
TINY = 2.0**-960  # far above the rounding errors of subnormal products, far below any normal-range value
CONTROL_NAMES = ("n0", "n2", "2 n1")  # the CCD rows' control vectors, in normal_rows' order


@dataclass(frozen=True)
class Spread:
    kind: str                 # "beyond", "within", "undecided" (module doc), or "unsearched" (node_spreads' cap)
    witness: tuple = ()       # beyond: 1-4 (triangle, control) rows whose normals hold 0 in their hull
    axis: np.ndarray | None = None  # within: l, with l . n > 0 for every normal (exact)
    half_angle: float = math.nan    # within: the widest angle (degrees, rounded) from l to a normal
    analysed: bool = True     # False: not searched (inherited from a descendant's witness)

    def sentence(self, ccd: bool = False) -> str:
        """In words, for logs and `conecull explain` (after 'its normal cone could not be bounded ...')."""
        what = "the control vectors of its normals over the step" if ccd else "its triangles' normals"
        # CCD cones bound the control vectors (ccd_cone.hpp), not n(t) itself, which may fit where they do not
        no_cone = ("so no cone holding the control vectors, which is what a CCD cone bounds, is below 180 degrees"
                   if ccd else "so no cone, however tight, holds them below 180 degrees")
        if self.kind == "beyond":
            if len(self.witness) == 1:
                t, c = self.witness[0]
                part = (f"triangle {t} has zero area at the {'start' if c == 0 else 'end'} of the step" if ccd and c < 2
                        else f"control vector 2 n1 of triangle {t} is zero" if ccd else
                        f"triangle {t} has no normal (zero area)")
                return f"{what} span a hemisphere or more: {part}, {no_cone}"
            names = ", ".join(f"{t} ({CONTROL_NAMES[c]})" if ccd else str(t) for t, c in self.witness)
            return (f"{what} span a hemisphere or more: those of triangles {names} point in opposing directions "
                    f"(their convex hull holds the origin, checked exactly), {no_cone}")
        if self.kind == "within":
            ax = np.round(self.axis / np.linalg.norm(self.axis), 3).tolist()
            return (f"{what} fit in an open hemisphere (a cone of about {self.half_angle:.1f} degrees of half-angle "
                    f"about {ax} holds them, checked exactly): the node's cone bound, merged from its children's "
                    f"(Sec. 3.6) and widened for rounding (a sliver whose normal cannot be resolved has a full "
                    f"cone), is looser than they are; a cone this tight could have passed the cone test")
        if self.kind == "unsearched":
            return (f"whether {what} fit in a hemisphere was not searched (past the searches a frame makes; "
                    f"`conecull explain --node` searches one node)")
        return (f"whether {what} fit in a hemisphere was not decided (the floating-point search found no witness "
                f"that held exactly)")


class Normals:
    """Every triangle's normal rows at one pose (DCD: V1 None) or over a step (CCD: three control
    vectors n0, n2, 2 n1 per triangle, CONTROL_NAMES, in blocks of m rows): each row the sum of
    u_k x w_k over `terms` [(u, w), ...] of rounded differences (a row with fewer terms has zero
    vectors in the others), its rounded value, and its direction."""

    def __init__(self, faces: np.ndarray, V0: np.ndarray, V1: np.ndarray | None = None):
        from conecull._api import _as_faces, _as_positions, _asarray
        from conecull.datasets.checks import _first_non_finite

        F = _as_faces(faces).astype(np.int64)
        V0 = _asarray(V0, "V0")
        V0 = _as_positions(V0, len(V0) if V0.ndim == 2 else -1, "V0")
        V1 = None if V1 is None else _as_positions(V1, len(V0), "V1")
        for name, V in (("V0", V0), ("V1", V1)):
            if V is not None and not np.isfinite(V).all():  # the exact rows need finite doubles
                raise ValueError(f"{name}: {_first_non_finite(V)}")
        if len(F) and F.max() >= len(V0):
            raise ValueError(f"faces: vertex index {int(F.max())} but V0 has {len(V0)} rows")
        self.faces, self.V0, self.V1 = F, V0, V1
        self.m = len(F)
        a0, b0, c0 = V0[F[:, 0]], V0[F[:, 1]], V0[F[:, 2]]
        u0, w0 = b0 - a0, c0 - a0
        if V1 is None:
            self.terms = [(u0, w0)]
        else:
            a1, b1, c1 = V1[F[:, 0]], V1[F[:, 1]], V1[F[:, 2]]
            u1, w1 = b1 - a1, c1 - a1
            z = np.zeros_like(u0)
            # ccd_cone.hpp: n0 = e1(0) x e2(0), n2 = e1(1) x e2(1), 2 n1 = e1(0) x e2(1) + e1(1) x e2(0)
            self.terms = [(np.concatenate([u0, u1, u0]), np.concatenate([w0, w1, w1])),
                          (np.concatenate([z, z, u1]), np.concatenate([z, z, w0]))]
        self.rounded = sum(np.cross(u, w) for u, w in self.terms)
        self.length = np.linalg.norm(self.rounded, axis=1)
        self._exact = {}
        with np.errstate(invalid="ignore", divide="ignore"):
            self.unit = self.rounded / self.length[:, None]

    def rows(self, tris: np.ndarray) -> np.ndarray:
        """The rows of triangles `tris`."""
        return tris if self.V1 is None else np.concatenate([tris, tris + self.m, tris + 2 * self.m])

    def row_id(self, r: int) -> tuple:
        """Row -> (triangle, control): control 0 for DCD, else an index into CONTROL_NAMES."""
        return int(r % self.m), int(r // self.m)

    def exact(self, r: int) -> tuple:
        """Row r exactly (scaled, in integers; _exact_row), computed once (the refinement rounds and
        the nodes above ask again)."""
        row = self._exact.get(r)
        if row is None:
            row = self._exact[r] = _exact_row(self.faces, self.V0, self.V1, *self.row_id(r))
        return row

    def direction(self, r: int) -> np.ndarray:
        """Row r's direction in floats from its exact value (for a row whose rounded value is 0)."""
        x = self.exact(r)
        big = max(abs(v) for v in x)  # > 0: callers ask only for rows that are not exactly zero
        d = np.array([v / big for v in x])  # int / int: correctly rounded, no overflow
        return d / np.linalg.norm(d)


def _exact_row(faces, V0, V1, t: int, control: int) -> tuple:
    """The exact normal (or control vector) of triangle t times a positive power of two, in
    integers: each coordinate is an integer over a power of two, so one common scale makes them
    all integers. Scaling a row by a positive factor changes neither the sign of l . n nor whether
    the origin is in a hull of rows, so each row may have its own."""
    poses = (V0,) if V1 is None or control == 0 else (V1,) if control == 1 else (V0, V1)
    flat = _int_scaled([x for V in poses for v in faces[t] for x in V[v]])  # one scale for all
    pts = [flat[i : i + 3] for i in range(0, len(flat), 3)]  # per pose: a, b, c

    def edges(a, b, c):
        return [y - x for y, x in zip(b, a)], [z - x for z, x in zip(c, a)]

    if len(poses) == 1:
        return _cross(*edges(*pts[:3]))
    (u0, w0), (u1, w1) = edges(*pts[:3]), edges(*pts[3:])
    return tuple(p + q for p, q in zip(_cross(u0, w1), _cross(u1, w0)))


def _cross(u, w) -> tuple:
    return (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])


def _dot(u, w) -> int:
    return u[0] * w[0] + u[1] * w[1] + u[2] * w[2]


def _int_scaled(v) -> tuple:
    """Doubles times one positive power of two, in integers (each is an integer over a power of
    two: the largest denominator scales them all)."""
    ratios = [float(x).as_integer_ratio() for x in v]
    den = max(d for _, d in ratios)
    return tuple(q * (den // d) for q, d in ratios)


def exact_dot_signs(l: np.ndarray, normals: Normals, rows: np.ndarray) -> np.ndarray:
    """sign(l . n) for the given rows, exactly: the rounded value where it clears the filter's
    bound (FILTER times the absolute products), else from the exact row in integers."""
    l = np.asarray(l, np.float64)
    value = np.zeros(len(rows))
    perm = np.zeros(len(rows))
    for u, w in normals.terms:
        u, w = u[rows], w[rows]
        m = (u[:, 1] * w[:, 2], u[:, 2] * w[:, 1], u[:, 2] * w[:, 0], u[:, 0] * w[:, 2], u[:, 0] * w[:, 1],
             u[:, 1] * w[:, 0])
        value += l[0] * (m[0] - m[1]) + l[1] * (m[2] - m[3]) + l[2] * (m[4] - m[5])
        perm += (abs(l[0]) * (np.abs(m[0]) + np.abs(m[1])) + abs(l[1]) * (np.abs(m[2]) + np.abs(m[3]))
                 + abs(l[2]) * (np.abs(m[4]) + np.abs(m[5])))
    # Products in the subnormal range carry absolute errors the relative bound misses: values
    # that small are decided exactly (a review: l with components 2^-821 and coordinates near
    # 2^-127 gave +2^-1074 for a negative value).
    bound = FILTER * perm + TINY
    signs = np.where(value > bound, 1, np.where(-value > bound, -1, 0)).astype(np.int8)
    li = _int_scaled(l)
    for i in np.flatnonzero(signs == 0):  # borderline (or exactly zero): decide exactly
        d = _dot(li, normals.exact(int(rows[i])))
        signs[i] = (d > 0) - (d < 0)
    return signs


def _det(a, b, c) -> int:
    return _dot(a, _cross(b, c))


def holds_origin(vs: list) -> bool:
    """Whether the convex hull of 1 to 4 exact integer 3-vectors holds the origin, decided from
    signs of exact determinants. Only for affinely independent vectors (else False: by
    Caratheodory, an independent subset decides)."""
    t = len(vs)
    if t == 1:
        return not any(vs[0])
    if t == 2:  # on the segment: collinear with the origin between them
        a, b = vs
        return any(a) and any(b) and not any(_cross(a, b)) and _dot(a, b) < 0
    if t == 3:
        a, b, c = vs
        m = _cross([y - x for y, x in zip(b, a)], [z - x for z, x in zip(c, a)])
        if not any(m) or _det(a, b, c) != 0:
            return False  # collinear, or the origin off their plane
        # barycentric weights of the origin, times |m|^2 > 0 (they sum to it)
        return _det(b, c, m) >= 0 and _det(c, a, m) >= 0 and _det(a, b, m) >= 0
    # t == 4, Cramer on [v1 .. v4; 1 1 1 1] lambda = (0, 0, 0, 1): lambda_i = s_i / sum(s),
    # s_i = (-1)^(i + 4) det(the other three), i = 1..4.
    a, b, c, d = vs
    s = (-_det(b, c, d), _det(a, c, d), -_det(a, b, d), _det(a, b, c))
    total = sum(s)
    if total == 0:
        return False
    return all(x * total >= 0 for x in s)


def origin_in_hull(vectors: list) -> tuple | None:
    """Indices of 1 to 4 of `vectors` (exact integer 3-vectors) whose convex hull holds the
    origin, all of them first (Caratheodory: if the origin is in the hull of all, it is in the
    hull of an affinely independent subset of at most 4); or None."""
    k = len(vectors)
    subsets = [tuple(range(k))] if 1 <= k <= 4 else []
    subsets += [sub for size in range(1, min(k, 4) + 1) for sub in itertools.combinations(range(k), size)]
    for sub in subsets:
        if holds_origin([vectors[i] for i in sub]):
            return sub
    return None


def min_norm_point(P: np.ndarray, max_iter: int = 200) -> tuple[np.ndarray, list]:
    """Wolfe's algorithm (1976): the point x of the convex hull of the rows of P nearest the
    origin, and the rows whose hull holds it (at most 4 in 3D). If x != 0, every row has
    p . x >= |x|^2 > 0; if x == 0, those rows hold the origin. Floating point: the callers check
    its answer exactly."""
    j = int(np.argmax(P @ P.mean(axis=0)))
    S, w = [j], np.array([1.0])
    x = P[j].copy()
    for _ in range(max_iter):
        d = P @ x
        j = int(np.argmin(d))
        xx = float(x @ x)
        if xx <= 1e-30 or xx - d[j] <= 1e-12 * xx or j in S or len(S) >= 4:
            break
        S.append(j)
        w = np.append(w, 0.0)
        while True:  # minor cycle: the affine minimiser of S, moved back into the hull
            Q = P[S]
            n = len(S)
            A = np.ones((n + 1, n + 1))
            A[:n, :n] = Q @ Q.T
            A[n, n] = 0.0
            rhs = np.zeros(n + 1)
            rhs[n] = 1.0
            try:
                v = np.linalg.solve(A, rhs)[:n]
            except np.linalg.LinAlgError:  # affinely dependent rows
                v = np.linalg.lstsq(A, rhs, rcond=None)[0][:n]
            if (v > 1e-14).all():
                w = v
                break
            out = [i for i in range(n) if v[i] <= 1e-14 and w[i] - v[i] > 0]
            theta = min([1.0] + [w[i] / (w[i] - v[i]) for i in out])
            w = w + theta * (v - w)
            keep = w > 1e-14
            if keep.all():
                keep[int(np.argmin(w))] = False
            S = [s for s, k in zip(S, keep) if k]
            w = w[keep] / w[keep].sum()
        x = w @ P[S]
    return x, S


def normal_spread(normals: Normals, tris) -> Spread:
    """Spread of the normal rows of triangles `tris` (ids into the mesh's faces). See the module doc."""
    a = np.asarray(tris)
    if a.dtype.kind not in "iu" or a.ndim > 1:
        raise ValueError(f"tris: expected triangle ids (integers, 0-d or 1-d), got dtype {a.dtype} shape {a.shape}")
    tris = a.astype(np.int64).reshape(-1)
    if len(tris) == 0:
        raise ValueError("tris: expected at least one triangle")
    if tris.min() < 0 or tris.max() >= normals.m:
        bad = int(tris.min() if tris.min() < 0 else tris.max())
        raise ValueError(f"tris: triangle id {bad} is outside [0, {normals.m})")
    all_rows = rows = normals.rows(tris)
    zero = np.flatnonzero(~(normals.length[rows] > 0))
    for i in zero:  # a rounded zero: exactly zero (no normal), unless the rounding cancelled it
        if not any(normals.exact(int(rows[i]))):
            return Spread("beyond", witness=(normals.row_id(int(rows[i])),))
    P = normals.unit[rows]  # a copy (fancy indexing)
    for i in zero:  # such rows search with their exact directions (they were left out: "undecided")
        P[i] = normals.direction(int(rows[i]))
    mean = P.sum(axis=0)  # most sets that fit have their mean as a witness: no search
    d = P @ mean
    if (d > 0).all() and (exact_dot_signs(mean, normals, all_rows) > 0).all():
        return _within(mean, d)
    x, S = min_norm_point(P)
    d = P @ x
    if float(x @ x) > 0 and (d > 0).all():
        if (exact_dot_signs(x, normals, all_rows) > 0).all():
            return _within(x, d)
    # Near the hemisphere's edge the rounded x (a difference of unit vectors) has lost its
    # direction, and perhaps its support: Wolfe's iteration again, exactly, on a few rows (the
    # support, then the rows an axis fails on), each axis checked against every row.
    T = [int(rows[i]) for i in S] + [int(r) for r in rows[np.argsort(d)[:3]] if int(r) not in {int(rows[i]) for i in S}]
    sub = origin_in_hull([normals.exact(r) for r in T[: len(S)]])  # the usual case: the support holds 0
    if sub is not None:
        return Spread("beyond", witness=tuple(normals.row_id(T[i]) for i in sub))
    for _ in range(MAX_EXACT_ROUNDS):
        x, U = _min_norm_exact([_unitish(normals.exact(r)) for r in T])
        if not any(x):
            return Spread("beyond", witness=tuple(normals.row_id(T[i]) for i in U))
        big = max(abs(v) for v in x)
        l = np.array([float(v / big) for v in x])  # rounded once: the margins are far above it
        signs = exact_dot_signs(l, normals, all_rows)
        if (signs > 0).all():
            return _within(l, P @ l)
        bad = np.flatnonzero(signs <= 0)  # positions in rows (and in P)
        new = [int(rows[i]) for i in bad[np.argsort(P[bad] @ l)] if int(rows[i]) not in T][:4]
        if not new:
            break  # the rounded axis fails on its own support's rows: undecided
        T = [T[i] for i in U] + new
    return Spread("undecided")


MAX_EXACT_ROUNDS = 30


def _unitish(v: tuple) -> tuple:
    """v scaled by a power of two to a length between 1/2 and 2, exactly: the rows' own scales
    (_exact_row) differ by up to 2^200, and a nearest point among vectors of such different
    lengths has margins far below the rounding of the axis made from it."""
    k = max(abs(c) for c in v).bit_length()
    return tuple(Fraction(c, 1 << k) for c in v) if k else v


def _min_norm_exact(T: list) -> tuple:
    """The point of the convex hull of the exact integer vectors T nearest the origin, in
    Fractions, and the indices of the face it lies on: the nearest of the points of the faces'
    affine hulls (1 to 3 vectors) that lie in their face, or the origin if it is in the hull
    (of a face, or of 4 of them). Enumerates the faces: for the handful of rows of a refinement."""
    best = None
    for size in (1, 2, 3):
        for U in itertools.combinations(range(len(T)), size):
            x = _nearest_in_face([T[i] for i in U])
            if x is None:
                continue
            n2 = sum(v * v for v in x)
            if n2 == 0:
                return x, U
            if best is None or n2 < best[0]:
                best = (n2, x, U)
    for U in itertools.combinations(range(len(T)), 4):
        if holds_origin([T[i] for i in U]):
            return (Fraction(0),) * 3, U
    return best[1], best[2]


def _nearest_in_face(vs: list) -> tuple | None:
    """The point of the affine hull of 1 to 3 affinely independent integer vectors nearest the
    origin, in Fractions, if it lies in their convex hull; else None."""
    if len(vs) == 1:
        return tuple(Fraction(v) for v in vs[0])
    if len(vs) == 2:
        a, b = vs
        e = [q - p for p, q in zip(a, b)]
        ee = _dot(e, e)
        if ee == 0:
            return None
        t = Fraction(-_dot(a, e), ee)
        return tuple(p + t * q for p, q in zip(a, e)) if 0 <= t <= 1 else None
    a, b, c = vs
    m = _cross([q - p for p, q in zip(a, b)], [r - p for p, r in zip(a, c)])
    mm = _dot(m, m)
    if mm == 0:
        return None
    x = tuple(Fraction(_dot(a, m), mm) * v for v in m)
    # barycentric weights of x, times mm: the signed areas of the sub-triangles along m
    def area(p, q):
        return _dot(_cross([pi - xi for pi, xi in zip(p, x)], [qi - xi for qi, xi in zip(q, x)]), m)
    return x if area(b, c) >= 0 and area(c, a) >= 0 and area(a, b) >= 0 else None


def _within(l: np.ndarray, d: np.ndarray) -> Spread:
    """A "within" spread about l; d: the unit normals' dot products with l."""
    cos = float(np.min(d) / np.linalg.norm(l))
    return Spread("within", axis=np.array(l, np.float64), half_angle=math.degrees(math.acos(min(1.0, max(-1.0, cos)))))


def node_spreads(normals: Normals, bvh: dict, nodes, max_searches: int | None = None) -> dict:
    """normal_spread of each node in `nodes` (BVH node ids; bvh as SelfCollider.bvh_arrays()),
    deepest first: a node holding the triangles of a descendant's "beyond" witness spans a
    hemisphere too, so it takes that witness without a search (analysed=False). max_searches: at
    most this many searches (each about 0.1-0.3 ms, mostly Python's overhead: falling's 4500
    failed cones took 0.65-1.1 s); the nodes past it are "unsearched"."""
    order, begin, end, depth = bvh["order"], bvh["begin"], bvh["end"], bvh["depth"]
    position = np.empty(len(order), np.int64)
    position[order] = np.arange(len(order))
    out, found = {}, []
    w_lo, w_hi = np.empty(0, np.int64), np.empty(0, np.int64)  # per witness: its triangles' leaf-order span
    for n in sorted({int(n) for n in nodes}, key=lambda n: -int(depth[n])):
        lo, hi = int(begin[n]), int(end[n])
        held = np.flatnonzero((w_lo >= lo) & (w_hi < hi))
        if len(held):
            out[n] = Spread("beyond", witness=found[held[0]].witness, analysed=False)
            continue
        if max_searches is not None:
            if max_searches <= 0:
                out[n] = Spread("unsearched", analysed=False)
                continue
            max_searches -= 1
        s = normal_spread(normals, order[lo:hi])
        if s.kind == "beyond":
            at = [int(position[t]) for t, _ in s.witness]
            found.append(s)
            w_lo, w_hi = np.append(w_lo, min(at)), np.append(w_hi, max(at))
        out[n] = s
    return out
