// The "sct" baseline: the projected star-contour test of Schvartzman et al. [SPO10], as Sec. 3.2
// and 6.1 describe it: "computing a projection of the contour of S and checking for
// self-intersections on the resulting plane" with "a line-search star-shaped test".
//
//   1. Projection: every contour vertex is projected on the plane perpendicular to the cone
//      axis l, in a frame (u, w) of that plane: 2D coordinates X = v . u, Y = v . w.
//   2. Line search for a kernel point: on a line of the plane (through the projected centroid,
//      along u), every contour edge keeps the side its inner half-plane allows; the kernel
//      meets the line iff these intervals overlap (Sec. 3.2: "checking for overlaps between
//      intervals"). The middle of the overlap is the candidate kernel point o.
//   3. Star test on the projected polygon: o on the inner side of every edge (kernel test) and
//      a ray from o crossing the contour once (Sec. 3.3's intersection test), the same loop as
//      Alg. 1 but on 2D coordinates; the ray has a generic slope in the frame.
//
// Certified, unlike [SPO10] (Sec. 3.2: the projections "are prone to floating-point errors"):
// the projected coordinates carry a rigorous absolute error bound `delta`, every 2D sign is
// accepted only when it exceeds its error bound, and otherwise decided exactly on the 3D
// points: with u = l x e_k exact and w = l x u, the exact projections satisfy
//     orient2d(P a, P b, P c) = |u|^2 Side(a, b, c, l)   (the Unprojected Orientation Test
// Theorem, Sec. 3.4), so the exact fallback is side_sign / ray_side_sign. Steps 1-2 only choose
// the candidate o (a rounded 3D point); any o is valid, so their rounding is harmless. A passed
// test is therefore a proof, exactly like Alg. 1's; a test that cannot prove a sign fails.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "conecull/contour/contour_test.hpp"
#include "conecull/predicates/orient.hpp"
#include "conecull/vec3.hpp"

namespace conecull {

// The frame of the projection plane: u = l x e_k with e_k the axis of l's smallest component,
// so u is exact (its components are +-l's or 0) and exactly perpendicular to l; w = l x u,
// rounded (w_exact is only used in the error analysis). The rays are u + phi e_k.
struct ProjectionFrame {
    Vec3 u, w;
    int k = 0;
    double uu = 0;     // |u|^2 (rounded; only scales the candidate o)
    double scale = 0;  // max(max |u_j|, max |w_j|, max |l_j| max |u_j|): see project()
};

inline ProjectionFrame projection_frame(const Vec3& l) {
    ProjectionFrame f;
    const double ax = std::fabs(l.x), ay = std::fabs(l.y), az = std::fabs(l.z);
    f.k = (ax <= ay && ax <= az) ? 0 : (ay <= az ? 1 : 2);
    f.u = f.k == 0 ? Vec3{0.0, l.z, -l.y} : (f.k == 1 ? Vec3{-l.z, 0.0, l.x} : Vec3{l.y, -l.x, 0.0});
    f.w = cross(l, f.u);
    f.uu = dot(f.u, f.u);
    auto mx = [](const Vec3& a) { return std::fmax(std::fabs(a.x), std::fmax(std::fabs(a.y), std::fabs(a.z))); };
    f.scale = std::fmax(std::fmax(mx(f.u), mx(f.w)), mx(l) * mx(f.u));
    return f;
}

// Scratch buffers reused between tests (one per traversal; never shared between threads).
struct ProjectionScratch {
    std::vector<double> X, Y;
};

// Projects p relative to the reference vertex c: X = fl(fl(p - c) . u), Y = fl(fl(p - c) . w~).
// With d = fl(p - c) and D1 = |d|_1, the exact projections X* = (p - c) . u, Y* = (p - c) . w
// (w = l x u exactly) satisfy |X - X*| <= (gamma_3 + 1.01 eps) D1 max|u_j| and
// |Y - Y*| <= (gamma_3 + 1.01 eps) D1 max|w~_j| + D1 max|w~_j - w_j| with
// |w~_j - w_j| <= gamma_2 * 2 max|l_j| max|u_j|; so both are within 9 eps D1 scale, and
// delta = 16 eps max(D1) scale bounds every coordinate of the contour (and of o).
inline double project(const Vec3& p, const Vec3& c, const ProjectionFrame& f, double& X, double& Y) {
    const Vec3 d = p - c;
    X = dot(d, f.u);
    Y = dot(d, f.w);
    return std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z);
}

// Ray directions of the intersection test, in the plane frame: r = u + phi e_k (exact: u_k = 0),
// whose projection is (|u|^2, phi |u|^2 ... ) up to the frame: SideSign(v, o, o + r, l) =
// sign((v - o) . (l x r)) = sign((Y* - Yo*) + phi (X* - Xo*)), as l x u = w and l x e_k = u.
// Generic slopes, as Alg. 1 here (contour_test.hpp): an axis-aligned ray on a grid-like contour
// would run through vertices; a second slope if the first still does.
inline constexpr double kSctRaySlopes[2] = {0.6180339887498949, -1.3247179572447460};

struct ProjectedSigns {
    const double* X;
    const double* Y;
    double Xo, Yo, delta;
    const int32_t* loop;
    const double* V;
    Vec3 o, l, r;
    double phi;  // r = u + phi e_k

    // Kernel test: orient2d(o, v_i, v_j) on the projected coordinates. Bound on the error
    // against the exact projections (each coordinate within delta): rounding of the two
    // products and the difference, relative, 8 eps (|P1| + |P2|) with margin; coordinates off
    // by delta shift each difference by 2 delta: 2.1 delta S + 32 delta^2.
    int kernel(int32_t i, int32_t j) const {
        const double a1 = X[i] - Xo, b1 = Y[j] - Yo, a2 = Y[i] - Yo, b2 = X[j] - Xo;
        const double p1 = a1 * b1, p2 = a2 * b2, det = p1 - p2;
        const double s = std::fabs(a1) + std::fabs(b1) + std::fabs(a2) + std::fabs(b2);
        const double bound = 8.0 * kEps * (std::fabs(p1) + std::fabs(p2)) + 2.1 * delta * s + 32.0 * delta * delta;
        if (det > bound) return 1;
        if (-det > bound) return -1;
        return side_sign(o, load(V, loop[i]), load(V, loop[j]), l);  // = sign of the exact orient2d
    }
    // Intersection test: SideSign(v_i, o, o + r, l) = sign((Y* - Yo*) + phi (X* - Xo*)). Filter:
    // each difference is within 2 delta (+ its rounding) of the exact one; the products and the
    // sum add relative roundings, 4 eps with margin.
    int ray(int32_t i) const {
        const double dy = Y[i] - Yo, pdx = phi * (X[i] - Xo), y = dy + pdx;
        const double bound = 2.2 * delta * (1.0 + std::fabs(phi)) + 4.0 * kEps * (std::fabs(dy) + std::fabs(pdx));
        if (y > bound) return 1;
        if (-y > bound) return -1;
        return ray_side_sign(load(V, loop[i]), o, r, l);
    }
};

// The line search of [SPO10] on the projected polygon (step 2): the line Y = Ym through the
// projected centroid (Xm, Ym). Edge (a, b) keeps the side cross2(b - a, p - a) > 0 for a
// counter-clockwise polygon (< 0 clockwise); on the line that is a half-line bounded by
// x* = a_x + e_x (Ym - a_y) / e_y. Both orientations are searched in the same pass. Returns the
// middle of the non-empty overlap, or NaN if there is none (SCT then gives up).
inline double line_search_kernel(int32_t n, const double* X, const double* Y, double Ym) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    double lo[2] = {-inf, -inf}, hi[2] = {inf, inf};  // [0]: counter-clockwise, [1]: clockwise
    for (int32_t i = 0; i < n; ++i) {
        const int32_t j = i + 1 == n ? 0 : i + 1;
        const double ex = X[j] - X[i], ey = Y[j] - Y[i];
        if (ey == 0.0) {  // edge parallel to the line: all or nothing
            const double side = ex * (Ym - Y[i]);
            if (!(side > 0)) lo[0] = inf;
            if (!(side < 0)) lo[1] = inf;
            continue;
        }
        const double x = X[i] + ex * (Ym - Y[i]) / ey;
        if (ey > 0) {
            hi[0] = std::fmin(hi[0], x);
            lo[1] = std::fmax(lo[1], x);
        } else {
            lo[0] = std::fmax(lo[0], x);
            hi[1] = std::fmin(hi[1], x);
        }
    }
    for (int s = 0; s < 2; ++s)
        if (lo[s] < hi[s] && std::isfinite(lo[s]) && std::isfinite(hi[s])) return 0.5 * (lo[s] + hi[s]);
    return std::numeric_limits<double>::quiet_NaN();
}

// SCT on one contour: `loop` holds n vertex ids in boundary order, V the positions, l the axis.
inline ContourVerdict projected_contour_test(const int32_t* loop, int32_t n, const double* V, const Vec3& l,
                                           ProjectionScratch& scratch) {
    ContourVerdict out;
    const ProjectionFrame f = projection_frame(l);
    scratch.X.resize(n);
    scratch.Y.resize(n);
    double* X = scratch.X.data();
    double* Y = scratch.Y.data();
    // Step 1: projection (relative to the first vertex, so that delta scales with the contour).
    const Vec3 c = load(V, loop[0]);
    double d1 = 0.0;
    for (int32_t i = 0; i < n; ++i) d1 = std::fmax(d1, project(load(V, loop[i]), c, f, X[i], Y[i]));
    // Step 2: line search through the projected centroid (the projection of the 3D mean).
    const Vec3 m = kernel_point(loop, n, V);
    double Xm, Ym;
    project(m, c, f, Xm, Ym);
    const double xo = line_search_kernel(n, X, Y, Ym);
    out.kernel = m;
    out.ray = f.u;
    if (!(xo == xo)) {
        out.reason = ContourReason::kNoKernelOnSearchLine;
        out.edges_visited = n;
        return out;
    }
    // The candidate back in 3D: o = m + ((xo - Xm) / |u|^2) u projects to about (xo, Ym).
    out.kernel = m + ((xo - Xm) / f.uu) * f.u;
    double Xo, Yo;
    d1 = std::fmax(d1, project(out.kernel, c, f, Xo, Yo));
    const double delta = 16.0 * kEps * d1 * f.scale;
    // Step 3: the star test on the projected polygon (Sec. 3.3), with the ray of the second slope
    // if the first passes exactly through a vertex.
    ContourVerdict v;
    int32_t before = n;  // the line search's pass
    for (int attempt = 0; attempt < 2; ++attempt) {
        const double phi = kSctRaySlopes[attempt];
        Vec3 r = f.u;
        (f.k == 0 ? r.x : (f.k == 1 ? r.y : r.z)) = phi;
        out.ray = r;
        v = star_contour_test(n, ProjectedSigns{X, Y, Xo, Yo, delta, loop, V, out.kernel, l, r, phi}, out);
        v.edges_visited += before;
        before = v.edges_visited;
        if (v.reason != ContourReason::kRayThroughVertex) break;
    }
    return v;
}

}  // namespace conecull
