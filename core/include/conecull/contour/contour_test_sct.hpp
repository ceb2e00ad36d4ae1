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

#include "conecull/contour/contour_test.hpp"
#include "conecull/contour/kernel_point.hpp"
#include "conecull/predicates/orient.hpp"
#include "conecull/vec3.hpp"

namespace conecull {

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

// SCT on one contour: `loop` holds n vertex ids in boundary order, V the positions, l the axis.
inline ContourVerdict projected_contour_test(const int32_t* loop, int32_t n, const double* V, const Vec3& l,
                                           ProjectionScratch& scratch) {
    ContourVerdict out;
    const ProjectionFrame f = projection_frame(l);
    // Steps 1-2: projection (relative to the first vertex, so that delta scales with the
    // contour) and the line search through the projected centroid (kernel_point.hpp).
    double d1 = 0.0;
    int32_t searched = 0;
    out.kernel = kernel_point(loop, n, V);
    out.ray = f.u;
    const bool found = search_kernel_point(loop, n, V, f, out.kernel, scratch, out.kernel, d1, searched);
    out.kernel_end = out.kernel;
    if (!found) {
        out.reason = ContourReason::kNoKernelOnSearchLine;
        out.edges_visited = searched;
        return out;
    }
    double Xo, Yo;
    d1 = std::fmax(d1, project(out.kernel, load(V, loop[0]), f, Xo, Yo));
    const double delta = 16.0 * kEps * d1 * f.scale;
    // Step 3: the star test on the projected polygon (Sec. 3.3), with the ray of the second slope
    // if the first passes exactly through a vertex.
    ContourVerdict v;
    int32_t before = searched;  // the line search's pass
    for (int attempt = 0; attempt < 2; ++attempt) {
        const double phi = kSctRaySlopes[attempt];
        Vec3 r = f.u;
        (f.k == 0 ? r.x : (f.k == 1 ? r.y : r.z)) = phi;
        out.ray = r;
        v = star_contour_test(n, ProjectedSigns{scratch.X.data(), scratch.Y.data(), Xo, Yo, delta, loop, V, out.kernel, l, r, phi},
                              out);
        v.edges_visited += before;
        before = v.edges_visited;
        if (v.reason != ContourReason::kRayThroughVertex) break;
    }
    return v;
}

}  // namespace conecull
