// The "cbc" baseline: the quadratic contour test of the continuous normal cone culling of
// Tang et al. [TCYM09], as Sec. 3.2 describes it: "projecting the continuously deforming
// edges to a plane and checking each pair for overlap" — O(n^2) in the n contour edges. The
// projected contour is simple at every t iff no two of its edges meet, except adjacent edges
// at their shared vertex; with the cone bounded that proves the patch free of self-collisions
// (same argument as Alg. 1's, contour.hpp).
//
// Certified: a pair passes only if one of these separations is proven for every t in [0, 1]
// (DCD: the one pose), every sign exact (filtered, then expansion arithmetic):
//   - the line of one edge strictly separates the other edge: Side(a, b, c, l) and
//     Side(a, b, d, l) of one strict sign (Sec. 3.3's Side; equal to the projected
//     orientation by the Unprojected Orientation Test Theorem, Sec. 3.4);
//   - all four points stay collinear in projection (every Side identically 0: straight runs of
//     a contour on a grid) and a linear function along the line, f(p) = p . (l x n), puts one
//     edge strictly before the other;
//   - adjacent edges (a, b), (b, c): Side(a, b, c, l) strict, or collinear with f(a) and f(c)
//     strictly on both sides of f(b).
// Anything else (a crossing, a touch, a sign that cannot be proven) fails the test. For CCD,
// Side(a(t), b(t), c(t), l) with all three points moving linearly and l fixed is quadratic in
// t: its Bernstein coefficients k0, k1, k2 (as Sec. 3.6's CSide1, with A_t = a_t - c_t,
// B_t = b_t - c_t: k0 = (A0 x B0) . l, k1 = (A0 x B1 + A1 x B0) . l / 2, k2 = (A1 x B1) . l)
// of one strict sign prove the sign for all t; all three 0 prove it identically 0. f(p(t)) -
// f(q(t)) is linear in t: its signs at t = 0 and t = 1.
#pragma once

#include <cstdint>

#include "conecull/contour/contour_test.hpp"
#include "conecull/predicates/det_sum.hpp"
#include "conecull/predicates/orient.hpp"

namespace conecull {

// A sign over the whole motion: +-1 strict throughout, 0 identically zero, kUnknownSign
// (predicates/orient.hpp) otherwise.

// One pose (DCD; cbc on a DCD query is this test at that pose).
struct QuadraticSignsDiscrete {
    const int32_t* loop;
    const double* V;
    Vec3 l;
    Vec3 p(int32_t i) const { return load(V, loop[i]); }
    int side(int32_t a, int32_t b, int32_t c) const { return side_sign(p(a), p(b), p(c), l); }
    // The direction n of f, from edge (a, b): l x n is then close to the edge's projected
    // direction (any exact n is valid; this one makes f separate points along that edge).
    Vec3 along_dir(int32_t a, int32_t b) const { return cross(l, p(b) - p(a)); }
    // sign(f(p) - f(q)) with f(x) = x . (l x n): ray_side_sign(p, q, n, l) = sign((p - q) . (l x n)).
    int along(int32_t pi, int32_t qi, const Vec3& n) const { return ray_side_sign(p(pi), p(qi), n, l); }
};

// A linear step V0 -> V1 (CCD), l fixed (the CCD cone's axis).
struct QuadraticSignsContinuous {
    const int32_t* loop;
    const double* V0;
    const double* V1;
    Vec3 l;
    int side(int32_t a, int32_t b, int32_t c) const {
        const Vec3 a0 = load(V0, loop[a]), b0 = load(V0, loop[b]), c0 = load(V0, loop[c]);
        const Vec3 a1 = load(V1, loop[a]), b1 = load(V1, loop[b]), c1 = load(V1, loop[c]);
        const int k0 = side_sign(a0, b0, c0, l);  // value at t = 0
        const int k2 = side_sign(a1, b1, c1, l);  // value at t = 1
        if (k0 != k2) return kUnknownSign;
        // sign(k1) = sign(det[l; A0; B1] + det[l; A1; B0])   ((u x w) . l = det[l; u; w])
        const Vec3 zero{};
        const Det3 d[2] = {{{l, zero}, {a0, c0}, {b1, c1}}, {{l, zero}, {a1, c1}, {b0, c0}}};
        return det_sum_sign(d) == k0 ? k0 : kUnknownSign;
    }
    Vec3 along_dir(int32_t a, int32_t b) const { return cross(l, load(V0, loop[b]) - load(V0, loop[a])); }
    int along(int32_t pi, int32_t qi, const Vec3& n) const {
        const int s0 = ray_side_sign(load(V0, loop[pi]), load(V0, loop[qi]), n, l);
        if (s0 == 0) return kUnknownSign;
        return ray_side_sign(load(V1, loop[pi]), load(V1, loop[qi]), n, l) == s0 ? s0 : kUnknownSign;
    }
};

inline bool strict(int s) { return s == 1 || s == -1; }

// Edges (a, b) and (c, d), no shared vertex: proven apart in projection (for all t)?
template <class Signs>
bool edges_apart(const Signs& s, int32_t a, int32_t b, int32_t c, int32_t d) {
    const int s1 = s.side(a, b, c);
    const int s2 = s1 == kUnknownSign ? kUnknownSign : s.side(a, b, d);
    if (strict(s1) && s1 == s2) return true;  // line (a, b) separates c d
    const int s3 = s.side(c, d, a);
    const int s4 = s3 == kUnknownSign ? kUnknownSign : s.side(c, d, b);
    if (strict(s3) && s3 == s4) return true;  // line (c, d) separates a b
    if (s1 != 0 || s2 != 0 || s3 != 0 || s4 != 0) return false;  // crossing, touching, or unproven
    // Collinear throughout: separated along the line?
    const Vec3 n = s.along_dir(a, b);
    const int g = s.along(c, a, n);
    if (!strict(g)) return false;
    return s.along(c, b, n) == g && s.along(d, a, n) == g && s.along(d, b, n) == g;
}

// Adjacent edges (a, b), (b, c): they meet only at b (for all t)?
template <class Signs>
bool adjacent_edges_apart(const Signs& s, int32_t a, int32_t b, int32_t c) {
    const int t = s.side(a, b, c);
    if (strict(t)) return true;
    if (t != 0) return false;
    const Vec3 n = s.along_dir(a, b);
    const int ga = s.along(a, b, n);
    return strict(ga) && s.along(c, b, n) == -ga;
}

// [TCYM09]'s contour test: every pair of contour edges, O(n^2).
template <class Signs>
ContourVerdict quadratic_contour_test(int32_t n, const Signs& s, ContourVerdict out) {
    for (int32_t i = 0; i < n; ++i) {
        const int32_t i1 = i + 1 == n ? 0 : i + 1;
        for (int32_t j = i + 1; j < n; ++j) {
            const int32_t j1 = j + 1 == n ? 0 : j + 1;
            out.edges_visited += 2;
            bool apart;
            if (j == i1) apart = adjacent_edges_apart(s, i, i1, j1);       // (v_i, v_j) then (v_j, v_j+1)
            else if (j1 == i) apart = adjacent_edges_apart(s, j, i, i1);   // (v_j, v_i) then (v_i, v_i+1)
            else apart = edges_apart(s, i, i1, j, j1);
            if (!apart) {
                out.reason = ContourReason::kEdgesMayOverlap;
                out.edge = i;
                out.other_edge = j;
                return out;
            }
        }
    }
    return out;
}

inline ContourVerdict quadratic_contour_test(const int32_t* loop, int32_t n, const double* V, const Vec3& l) {
    ContourVerdict out;
    out.kernel = kernel_point(loop, n, V);  // reported only (the test has no kernel point)
    out.kernel_end = out.kernel;
    return quadratic_contour_test(n, QuadraticSignsDiscrete{loop, V, l}, out);
}

inline ContourVerdict quadratic_contour_test_ccd(const int32_t* loop, int32_t n, const double* V0, const double* V1,
                                                const Vec3& l) {
    ContourVerdict out;
    out.kernel = kernel_point(loop, n, V0);  // reported only, as the means at both ends
    out.kernel_end = kernel_point(loop, n, V1);
    return quadratic_contour_test(n, QuadraticSignsContinuous{loop, V0, V1, l}, out);
}

}  // namespace conecull
