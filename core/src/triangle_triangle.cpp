#include "conecull/elementary/triangle_triangle.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "conecull/predicates/orient.hpp"

namespace conecull {

namespace {

// An axis whose coordinate plane shows triangle (a, b, c) non-degenerate, with the sign of the
// projected orientation there, or -1 if a, b, c are collinear. Tries the axis of the largest
// floating-point normal component first, which is the one that succeeds in practice.
std::pair<int, int> projection_axis(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 n = cross(b - a, c - a);
    const double an[3] = {std::fabs(n.x), std::fabs(n.y), std::fabs(n.z)};
    int first = an[0] >= an[1] && an[0] >= an[2] ? 0 : (an[1] >= an[2] ? 1 : 2);
    for (int t = 0; t < 3; ++t) {
        const int k = (first + t) % 3;
        const int s = orient2d_drop(k, a, b, c);
        if (s != 0) return {k, s};
    }
    return {-1, 0};
}

struct P2 {
    double x, y;
};
P2 drop(int k, const Vec3& v) { return {v[(k + 1) % 3], v[(k + 2) % 3]}; }
int orient(const P2& a, const P2& b, const P2& c) { return orient2d(a.x, a.y, b.x, b.y, c.x, c.y); }
bool in_box(const P2& p, const P2& q, const P2& x) {
    return std::min(p.x, q.x) <= x.x && x.x <= std::max(p.x, q.x) && std::min(p.y, q.y) <= x.y &&
           x.y <= std::max(p.y, q.y);
}

// Closed 2D segments; degenerate ones (points) included.
bool segments_meet_2d(const P2& p, const P2& q, const P2& a, const P2& b) {
    const int d1 = orient(a, b, p), d2 = orient(a, b, q), d3 = orient(p, q, a), d4 = orient(p, q, b);
    if (d1 * d2 < 0 && d3 * d4 < 0) return true;
    return (d1 == 0 && in_box(a, b, p)) || (d2 == 0 && in_box(a, b, q)) || (d3 == 0 && in_box(p, q, a)) ||
           (d4 == 0 && in_box(p, q, b));
}

// Closed 2D triangle (non-degenerate) contains x.
bool point_in_triangle_2d(const P2& a, const P2& b, const P2& c, const P2& x) {
    const int d1 = orient(a, b, x), d2 = orient(b, c, x), d3 = orient(c, a, x);
    return (d1 >= 0 && d2 >= 0 && d3 >= 0) || (d1 <= 0 && d2 <= 0 && d3 <= 0);
}

// Axis along which not all of the points share a coordinate, or -1 if they coincide.
int spread_axis(std::initializer_list<Vec3> pts) {
    for (int k = 0; k < 3; ++k) {
        const double v0 = pts.begin()->operator[](k);
        for (const Vec3& p : pts)
            if (p[k] != v0) return k;
    }
    return -1;
}

// The hull of collinear a, b, c as a segment [lo, hi] (possibly a point).
std::pair<Vec3, Vec3> collinear_hull(const Vec3& a, const Vec3& b, const Vec3& c) {
    const int k = spread_axis({a, b, c});
    if (k < 0) return {a, a};
    Vec3 lo = a, hi = a;
    for (const Vec3& v : {b, c}) {
        if (v[k] < lo[k]) lo = v;
        if (v[k] > hi[k]) hi = v;
    }
    return {lo, hi};
}

// Direction x - v (x != v) enters triangle (v, c, d) at its vertex v: v + s (x - v) lies in the
// triangle for some s > 0.
bool enters_at_vertex(const Vec3& x, const Vec3& v, const Vec3& c, const Vec3& d) {
    const auto [k, s] = projection_axis(v, c, d);
    if (k >= 0) {
        if (orient3d(v, c, d, x) != 0) return false;
        const P2 V = drop(k, v), C = drop(k, c), D = drop(k, d), X = drop(k, x);
        // Inside the wedge between v->c and v->d (angle < pi), boundary rays included.
        return orient(V, C, X) * s >= 0 && orient(V, X, D) * s >= 0;
    }
    // Degenerate triangle: a segment (or the point v). x - v must point along v->c or v->d.
    for (const Vec3& w : {c, d}) {
        if (w == v) continue;
        if (!collinear(v, w, x)) return false;
        const int a = spread_axis({v, w});
        if ((x[a] > v[a]) == (w[a] > v[a])) return true;
    }
    return false;
}

// (closed segment [p, q]) n (closed triangle (v, c, d)) is not inside {v}.
bool segment_meets_triangle_beyond(const Vec3& p, const Vec3& q, const Vec3& v, const Vec3& c, const Vec3& d) {
    if (!point_on_segment(v, p, q)) return segment_meets_triangle(p, q, v, c, d);
    // v is on the segment and in the triangle; the intersection is a sub-segment through v,
    // larger than {v} iff it leaves v towards p or towards q.
    return (!(p == v) && enters_at_vertex(p, v, c, d)) || (!(q == v) && enters_at_vertex(q, v, c, d));
}

// segment_meets_triangle when the sides of p and q of the triangle's plane are known (its
// orient3d signs, op and oq): the plane test is skipped, and done once per pair by the caller.
bool segment_meets_triangle_sides(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c, int op,
                                  int oq) {
    if (op * oq > 0) return false;
    if (op == 0 && oq == 0) return segment_meets_triangle(p, q, a, b, c);  // in the plane (or a degenerate triangle)
    return segment_crosses_triangle(p, q, a, b, c);  // the triangle is proper: some orient3d is not 0
}

bool strictly_one_side(int a, int b, int c) { return (a > 0 && b > 0 && c > 0) || (a < 0 && b < 0 && c < 0); }

// Cheap proof that P and Q are disjoint: their projections along P's dominant normal axis are
// strictly separated by the line through an edge of either (2D separating axes; filtered
// signs). Disjoint projections, disjoint triangles. Asked only when orient3d's filter fails
// (near-coplanar pairs, as on a flat or rigidly moved sheet). False: not proven.
bool apart_in_projection(const Vec3 P[3], const Vec3 Q[3]) {
    const auto [k, s] = projection_axis(P[0], P[1], P[2]);
    if (k < 0) return false;
    const P2 p[3] = {drop(k, P[0]), drop(k, P[1]), drop(k, P[2])};
    const P2 q[3] = {drop(k, Q[0]), drop(k, Q[1]), drop(k, Q[2])};
    // One triangle lies on side `side` of its edge line (a, b); the other strictly beyond it?
    const auto beyond = [](const P2& a, const P2& b, int side, const P2(&o)[3]) {
        return orient(a, b, o[0]) == -side && orient(a, b, o[1]) == -side && orient(a, b, o[2]) == -side;
    };
    for (int i = 0; i < 3; ++i)
        if (beyond(p[i], p[(i + 1) % 3], s, q)) return true;
    const int t = orient(q[0], q[1], q[2]);
    if (t == 0) return false;
    for (int i = 0; i < 3; ++i)
        if (beyond(q[i], q[(i + 1) % 3], t, p)) return true;
    return false;
}

// The index of the corner alone strictly on its side of the other plane, when the three signs
// are all non-zero and not all alike (the plane cuts the triangle); -1 otherwise.
int lone_corner(const int o[3]) {
    if (o[0] == 0 || o[1] == 0 || o[2] == 0) return -1;
    if (o[1] == o[2]) return o[0] != o[1] ? 0 : -1;
    return o[0] == o[1] ? 2 : 1;
}

// Each plane cuts the other triangle, no corner on a plane (the generic case of crossing
// neighbours): P n plane(Q) and Q n plane(P) are segments of the line L = plane(P) n plane(Q),
// and the triangles meet iff the segments overlap. Two orient3d signs order their ends along L
// (as Guigue & Devillers 2003; derived here for our orient3d):
//
//   Normalise: p1 the lone corner of P, on the + side of Q's plane; q1 the lone corner of Q, on
//   the + side of P's plane (rotations keep a triangle's orientation; swapping the two other
//   corners of one triangle flips the other's signs against its plane). Let n_P, n_Q be the
//   normals, d = n_P x n_Q (non-zero: the planes cross), i, j where p1p2, p1p3 cross plane(Q),
//   and k, l where q1q2, q1q3 cross plane(P); all four lie on L. With i = p1 + s (p2 - p1),
//   k = q1 + t (q2 - q1), s, t in (0, 1], column operations give
//     det[p2 - p1, q1 - p1, q2 - p1] = det[i - p1, k - i, k - q1] / (s t),
//   and with k - i = lambda d, u = i - p1 = a d + b (n_P x d) (b > 0: n_Q . u = -b |d|^2 < 0 as
//   u runs from the + side to plane(Q)) and w = k - q1 = c d + e (n_Q x d) (e < 0 likewise),
//     det[u, d, w] = b e det[n_P x d, d, n_Q x d] = -b e |d|^4 > 0.
//   So orient3d(p1, p2, q1, q2) = sign(lambda): the order of i and k along d; likewise
//   orient3d(p1, p3, q1, q3) orders j and l. (i - p1) x (j - p1) . n_P > 0 puts j before i
//   along d, (k - q1) x (l - q1) . n_Q > 0 puts k before l, so the closed segments [j, i] and
//   [k, l] overlap iff k <= i and j <= l.
// Checked against the rational oracle (tests/elementary).
bool crossing_planes_meet(const Vec3 P[3], const Vec3 Q[3], const int op[3], const int oq[3], int lp, int lq) {
    const Vec3* p1 = &P[lp];
    const Vec3* p2 = &P[(lp + 1) % 3];
    const Vec3* p3 = &P[(lp + 2) % 3];
    const Vec3* q1 = &Q[lq];
    const Vec3* q2 = &Q[(lq + 1) % 3];
    const Vec3* q3 = &Q[(lq + 2) % 3];
    if (oq[lp] < 0) std::swap(q2, q3);  // oq: P's corners against Q's plane
    if (op[lq] < 0) std::swap(p2, p3);  // op: Q's corners against P's plane
    return orient3d(*p1, *p2, *q1, *q2) <= 0 && orient3d(*p1, *p3, *q1, *q3) >= 0;
}

bool collide_no_shared(const Vec3 P[3], const Vec3 Q[3]) {
    // Plane rejection: one triangle strictly on one side of the other's plane. Filtered signs
    // first; where they fail, the 2D proof above before the exact fallback.
    const FilteredPlane plane_p(P[0], P[1], P[2]);
    if (plane_p.strictly_one_side(Q)) return false;
    const FilteredPlane plane_q(Q[0], Q[1], Q[2]);
    if (plane_q.strictly_one_side(P)) return false;
    int op[3], oq[3];
    bool unknown = false;
    for (int j = 0; j < 3; ++j) {
        op[j] = plane_p.sign(Q[j]);
        oq[j] = plane_q.sign(P[j]);
        unknown = unknown || op[j] == kUnknownSign || oq[j] == kUnknownSign;
    }
    if (unknown) {
        if (apart_in_projection(P, Q)) return false;
        for (int j = 0; j < 3; ++j) {
            if (op[j] == kUnknownSign) op[j] = detail::orient3d_exact(P[0], P[1], P[2], Q[j]);
            if (oq[j] == kUnknownSign) oq[j] = detail::orient3d_exact(Q[0], Q[1], Q[2], P[j]);
        }
        if (strictly_one_side(op[0], op[1], op[2]) || strictly_one_side(oq[0], oq[1], oq[2])) return false;
    }
    // Every sign is now known. Generic crossing planes: two more signs decide.
    const int lp = lone_corner(oq), lq = lone_corner(op);
    if (lp >= 0 && lq >= 0) return crossing_planes_meet(P, Q, op, oq, lp, lq);
    // Otherwise an edge meets the other triangle only if its ends are not strictly on one side
    // of that triangle's plane.
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        if (segment_meets_triangle_sides(P[i], P[j], Q[0], Q[1], Q[2], oq[i], oq[j])) return true;
        if (segment_meets_triangle_sides(Q[i], Q[j], P[0], P[1], P[2], op[i], op[j])) return true;
    }
    return false;
}

// Cheap proof that triangles P = (v, a, b), Q = (v, c, d) meet only at v, from one projection
// that keeps P non-degenerate: a line through v and one of the four other corners with one
// projected triangle on one side and the other's two free corners strictly on the other side.
// Then the projections meet only at v, and as the projection is injective on P, so do P and Q.
// Asked only when orient3d's filter fails (near-coplanar neighbours, as on a flat or rigidly
// moved sheet), where it usually saves the exact fallback. False: not proven.
bool apart_beyond_shared_vertex(const Vec3 P[3], const Vec3 Q[3]) {
    const auto [k, s] = projection_axis(P[0], P[1], P[2]);
    if (k < 0) return false;
    const P2 V = drop(k, P[0]), A = drop(k, P[1]), B = drop(k, P[2]), C = drop(k, Q[1]), D = drop(k, Q[2]);
    // Lines through P's edges: P lies on the side (s) of its own third corner.
    if (orient(V, A, C) == -s && orient(V, A, D) == -s) return true;
    if (orient(V, B, C) == s && orient(V, B, D) == s) return true;
    // Lines through Q's edges, when Q projects to a proper triangle (t its orientation).
    const int t = orient(V, C, D);
    if (t == 0) return false;
    if (orient(V, C, A) == -t && orient(V, C, B) == -t) return true;
    return orient(V, D, A) == t && orient(V, D, B) == t;
}

// P = (v, a, b), Q = (v, c, d).
bool collide_shared_vertex(const Vec3 P[3], const Vec3 Q[3]) {
    const Vec3 &v = P[0];
    // If c and d lie strictly on one side of P's plane, Q meets that plane only at v.
    const FilteredPlane plane_p(P[0], P[1], P[2]);
    int oc = plane_p.sign(Q[1]), od = plane_p.sign(Q[2]);
    if (oc != kUnknownSign && od != kUnknownSign && oc * od > 0) return false;
    if (oc == kUnknownSign || od == kUnknownSign) {
        if (apart_beyond_shared_vertex(P, Q)) return false;
        if (oc == kUnknownSign) oc = detail::orient3d_exact(P[0], P[1], P[2], Q[1]);
        if (od == kUnknownSign) od = detail::orient3d_exact(P[0], P[1], P[2], Q[2]);
        if (oc * od > 0) return false;
    }
    const int oa = orient3d(Q[0], Q[1], Q[2], P[1]), ob = orient3d(Q[0], Q[1], Q[2], P[2]);
    if (oa * ob > 0) return false;
    // Generic: a, b strictly on opposite sides of Q's plane, c, d of P's. Then P n plane(Q) =
    // [v, x] with x inside ab, Q n plane(P) = [v, y] with y inside cd, both on the line
    // L = plane(P) n plane(Q) through v, and the triangles meet beyond v iff x and y lie on the
    // same side of v. Along d = n_P x n_Q (coordinates xi, eta; v at 0) the identity of
    // crossing_planes_meet holds without normalising, with sign(det[x - a, d, y - c]) = oa oc:
    // for the segments a->b, c->v it gives orient3d(a, b, c, v) = sign(0 - xi) oa oc, for a->v,
    // c->d orient3d(a, v, c, d) = sign(eta - 0) oa oc. As orient3d(a, b, c, v) = -oc and
    // orient3d(a, v, c, d) = -oa (4-cycles of the points), sign(xi) = oa and sign(eta) = -oc.
    if (oa != 0 && ob != 0 && oc != 0 && od != 0) return oa * oc < 0;
    for (int i = 0; i < 3; ++i) {
        if (segment_meets_triangle_beyond(P[i], P[(i + 1) % 3], v, Q[1], Q[2])) return true;
        if (segment_meets_triangle_beyond(Q[i], Q[(i + 1) % 3], v, P[1], P[2])) return true;
    }
    return false;
}

// P = (a, b, c), Q = (a, b, d): shared edge [a, b].
bool collide_shared_edge(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    // Not coplanar: the planes meet in line ab, and each triangle meets it in [a, b] only.
    int o = orient3d_filtered(a, b, c, d);
    if (o == kUnknownSign) {
        // Near-coplanar. A cheaper proof first (as apart_beyond_shared_vertex): in a projection
        // that keeps P proper, c and d strictly on opposite sides of line ab, so the projections,
        // and P and Q, meet in [a, b] only.
        if (const auto [k, s] = projection_axis(a, b, c); k >= 0 && orient2d_drop(k, a, b, d) == -s) return false;
        o = detail::orient3d_exact(a, b, c, d);
    }
    if (o != 0) return false;
    if (a == b) {
        // Both are segments from a: they overlap beyond a iff c, d leave a the same way.
        if (c == a || d == a || !collinear(a, c, d)) return false;
        const int k = spread_axis({a, c});
        return (c[k] > a[k]) == (d[k] > a[k]);
    }
    const bool c_on = collinear(a, b, c), d_on = collinear(a, b, d);
    if (c_on && d_on) {
        // All on line ab: intervals; they overlap beyond a or beyond b.
        const int k = spread_axis({a, b});
        const double ta = std::min(a[k], b[k]), tb = std::max(a[k], b[k]);
        return (c[k] < ta && d[k] < ta) || (c[k] > tb && d[k] > tb);
    }
    // One is a segment on line ab: the other triangle meets that line in [a, b] only.
    if (c_on || d_on) return false;
    // Coplanar, both proper: they overlap iff c and d are on the same side of line ab.
    const auto [k, s] = projection_axis(a, b, c);
    return orient2d_drop(k, a, b, d) == s;
}

}  // namespace

bool collinear(const Vec3& a, const Vec3& b, const Vec3& c) { return projection_axis(a, b, c).first < 0; }

bool point_on_segment(const Vec3& x, const Vec3& p, const Vec3& q) {
    for (int k = 0; k < 3; ++k)
        if (x[k] < std::min(p[k], q[k]) || x[k] > std::max(p[k], q[k])) return false;
    return collinear(p, q, x);
}

bool segment_meets_segment(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b) {
    if (orient3d(p, q, a, b) != 0) return false;
    // Coplanar: project along an axis that keeps their common plane (or line) injective.
    for (const auto& tri : {std::array<Vec3, 3>{p, q, a}, {p, q, b}, {a, b, p}, {a, b, q}}) {
        const int k = projection_axis(tri[0], tri[1], tri[2]).first;
        if (k >= 0) return segments_meet_2d(drop(k, p), drop(k, q), drop(k, a), drop(k, b));
    }
    // All four collinear: compare intervals along an axis where they spread.
    const int k = spread_axis({p, q, a, b});
    if (k < 0) return true;
    return std::max(std::min(p[k], q[k]), std::min(a[k], b[k])) <= std::min(std::max(p[k], q[k]), std::max(a[k], b[k]));
}

bool segment_meets_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
    const auto [k, s] = projection_axis(a, b, c);
    if (k < 0) {
        const auto [lo, hi] = collinear_hull(a, b, c);
        return segment_meets_segment(p, q, lo, hi);
    }
    const int op = orient3d(a, b, c, p), oq = orient3d(a, b, c, q);
    if (op * oq > 0) return false;
    if (op == 0 && oq == 0) {
        const P2 A = drop(k, a), B = drop(k, b), C = drop(k, c), Pp = drop(k, p), Qq = drop(k, q);
        return point_in_triangle_2d(A, B, C, Pp) || point_in_triangle_2d(A, B, C, Qq) ||
               segments_meet_2d(Pp, Qq, A, B) || segments_meet_2d(Pp, Qq, B, C) || segments_meet_2d(Pp, Qq, C, A);
    }
    return segment_crosses_triangle(p, q, a, b, c);
}

bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
    // The segment crosses the plane at one point; it is in the triangle iff the line pq passes
    // on the same side of all three edges (signed volumes; zero on an edge).
    const int s1 = orient3d(p, q, a, b), s2 = orient3d(p, q, b, c), s3 = orient3d(p, q, c, a);
    return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

bool triangles_collide(const int32_t fp[3], const Vec3 P[3], const int32_t fq[3], const Vec3 Q[3]) {
    int sp[3], sq[3], shared = 0;  // shared corners: sp[k] in P matches sq[k] in Q
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (fp[i] == fq[j]) {
                sp[shared] = i;
                sq[shared] = j;
                ++shared;
            }
    switch (shared) {
        case 0:
            return collide_no_shared(P, Q);
        case 1: {
            const int i = sp[0], j = sq[0];
            const Vec3 Pr[3] = {P[i], P[(i + 1) % 3], P[(i + 2) % 3]};
            const Vec3 Qr[3] = {Q[j], Q[(j + 1) % 3], Q[(j + 2) % 3]};
            return collide_shared_vertex(Pr, Qr);
        }
        case 2: {
            const int c = 3 - sp[0] - sp[1], d = 3 - sq[0] - sq[1];
            return collide_shared_edge(P[sp[0]], P[sp[1]], P[c], Q[d]);
        }
        default:
            return false;
    }
}

}  // namespace conecull
