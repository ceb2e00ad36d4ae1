// Unprojected contour test for DCD (Sec. 3.3-3.4, Alg. 1).
#pragma once

#include <cstdint>

#include "conecull/contour/kernel_point.hpp"
#include "conecull/predicates/orient.hpp"
#include "conecull/vec3.hpp"

namespace conecull {

// Why a contour test failed; also the reason codes of the trace.
enum class ContourReason : uint8_t {
    kPassed = 0,
    kKernelSignZero = 1,     // SideSign(o, v_i, v_i+1, l) = 0: o on an edge's line (Alg. 1 l. 12, 18)
    kNotStarShaped = 2,      // kernel side flips at edge i: o is not in the kernel (Alg. 1 l. 18)
    kRayThroughVertex = 3,   // the ray from o passes exactly through v_i (Alg. 1 l. 24)
    kMultipleCrossings = 4,  // the ray crosses the contour twice: it winds more than once (l. 29)
    kNoCrossing = 5,         // never crosses: impossible for a closed loop passing the kernel test
    // Baselines (Sec. 6.1):
    kNoKernelOnSearchLine = 6,  // "sct": the line search of [SPO10] found no kernel point on its line
    kEdgesMayOverlap = 7,       // "cbc": edges (edge, other_edge) not proven apart in projection [TCYM09]
};
inline constexpr int kContourReasons = 8;

struct ContourVerdict {
    ContourReason reason = ContourReason::kPassed;
    int32_t edge = -1;       // contour edge (v_edge, v_edge+1) where it failed
    int32_t crossings = 0;   // ray crossings counted so far
    int32_t edges_visited = 0;  // contour edges examined (over all ray attempts; cbc: 2 per edge pair)
    int32_t other_edge = -1;    // cbc: the second edge of the pair that failed
    Vec3 kernel;             // o (CCD: o at t = 0)
    Vec3 kernel_end;         // o at t = 1 for CCD (the kernel point moves linearly, Alg. 3 here); DCD: o
    Vec3 ray;                // r
    bool by_simplicity = false;  // "nc": Alg. 1 (Alg. 3) failed, the simplicity fallback passed (contour_test_simple.hpp)
    bool passed() const { return reason == ContourReason::kPassed; }
};

// Alg. 1 lines 3-7 pick r = l x (0, 1, 0). Any r works whose projection on the plane
// perpendicular to l is non-zero: SideSign(v, o, o + r, l) = det[r, v - o, l] only sees that
// projection, and it is evaluated exactly for the r actually used, so r need not be exactly
// perpendicular to l. The paper's choice is the worst one on grid-like meshes (cloth starts flat
// and axis-aligned): the ray then runs along a grid row and hits vertices exactly, and the test
// must give up. We use fixed generic directions instead, and a second one if the first hits a
// vertex exactly.
inline constexpr int kRayDirections = 2;
inline Vec3 ray_direction(const Vec3& l, int attempt) {
    static constexpr Vec3 g[kRayDirections + 1] = {{0.5257311121191336, 0.2628655560595668, -0.8090169943749475},
                                                   {-0.3090169943749474, 0.8506508083520400, 0.4253254041760200},
                                                   {0.7071067811865476, -0.5, 0.5}};
    // Skip a direction nearly parallel to l (its projection would be tiny). The three are far
    // enough apart that at most one is skipped.
    for (const Vec3& d : g) {
        if (norm(cross(d, l)) < 0.25) continue;
        if (attempt-- == 0) return d;
    }
    return g[kRayDirections];
}

// The star-shape test of Alg. 1 (DCD) and Alg. 3 (CCD), which differ only in their sign
// functions: Signs::kernel(i, j) is SideSign(o, v_i, v_j, l) (CSideSign1 for CCD) and
// Signs::ray(i) is SideSign(v_i, o, o + r, l) (CSideSign2). `out` arrives with kernel and ray
// set. Every sign is exact (filtered, then expansion arithmetic), so "passed" is a proof that
// the projection of the loop along l is a simple star-shaped polygon around o. Departures from
// the printed algorithm, all on the safe side: the ray direction (see ray_direction); the ray
// test at a vertex is computed once per vertex (s2 of edge i is s1 of edge i+1); and the final
// answer requires exactly one crossing (the printed `return true` would also accept zero,
// which exact signs never produce).
template <class Signs>
ContourVerdict star_contour_test(int32_t n, const Signs& signs, ContourVerdict out) {
    int s0 = 0;
    int s1 = signs.ray(0);  // Alg. 1 line 22
    for (int32_t i = 0; i < n; ++i) {
        const int32_t j = i + 1 == n ? 0 : i + 1;
        const int s = signs.kernel(i, j);  // Alg. 1 lines 11 and 18: kernel test
        if (i == 0) s0 = s;
        out.edges_visited = i + 1;
        if (s == 0) {
            out.reason = ContourReason::kKernelSignZero;
            out.edge = i;
            return out;
        }
        if (s != s0) {
            out.reason = ContourReason::kNotStarShaped;
            out.edge = i;
            return out;
        }
        const int s2 = signs.ray(j);  // Alg. 1 line 23
        if (s1 == 0 || s2 == 0) {     // Alg. 1 line 24
            out.reason = ContourReason::kRayThroughVertex;
            out.edge = s1 == 0 ? i : j;
            return out;
        }
        // Alg. 1 line 27: edge crosses the line of the ray, on the ray's side (see README,
        // "verified formulas": sweeping in the kernel sign's sense, a crossing of the ray ends
        // on the ray's s0 side).
        if (s2 == s0 && s1 != s2 && ++out.crossings > 1) {
            out.reason = ContourReason::kMultipleCrossings;
            out.edge = i;
            return out;
        }
        s1 = s2;
    }
    if (out.crossings != 1) out.reason = ContourReason::kNoCrossing;
    return out;
}

// Runs a test with the first ray direction, and once more with the second if the ray passed
// exactly through a vertex (the counts of visited edges add up).
template <class Test>
ContourVerdict with_ray_retry(const Vec3& l, Test test) {
    ContourVerdict v = test(ray_direction(l, 0));
    for (int attempt = 1; attempt < kRayDirections && v.reason == ContourReason::kRayThroughVertex; ++attempt) {
        const int32_t before = v.edges_visited;
        v = test(ray_direction(l, attempt));
        v.edges_visited += before;
    }
    return v;
}

struct DiscreteSigns {
    const int32_t* loop;
    const double* V;
    Vec3 o, r, l;
    int kernel(int32_t i, int32_t j) const { return side_sign(o, load(V, loop[i]), load(V, loop[j]), l); }
    int ray(int32_t i) const { return ray_side_sign(load(V, loop[i]), o, r, l); }
};

// Alg. 1 with kernel point o. `loop` holds n vertex ids in boundary order; l is the cone axis;
// r the ray.
inline ContourVerdict unprojected_contour_test_with_ray(const int32_t* loop, int32_t n, const double* V, const Vec3& l,
                                                     const Vec3& r, const Vec3& o) {
    ContourVerdict out;
    out.kernel = o;
    out.kernel_end = o;
    out.ray = r;
    return star_contour_test(n, DiscreteSigns{loop, V, o, r, l}, out);
}
inline ContourVerdict unprojected_contour_test_with_ray(const int32_t* loop, int32_t n, const double* V, const Vec3& l,
                                                     const Vec3& r) {
    return unprojected_contour_test_with_ray(loop, n, V, l, r, kernel_point(loop, n, V));
}

// o is not in the kernel of the projected loop (or on an edge's line): the kernel test failed,
// or the ray crossed the loop twice before an edge showed it (a loop star-shaped around o is
// crossed once; one that winds twice fails again with any o).
inline bool kernel_failed(const ContourVerdict& v) {
    return v.reason == ContourReason::kNotStarShaped || v.reason == ContourReason::kKernelSignZero ||
           v.reason == ContourReason::kMultipleCrossings;
}

// The kernel-point retry of Alg. 1 and Alg. 3: `v` is the verdict with the mean (Alg. 1 line 2);
// if that o is not in the kernel, find(scratch, o, searched, edge) looks for a kernel point K of
// the loop (find_kernel_point from the edge where the mean failed: the kernel polygon's centre;
// for CCD, K holds both ends), and test(o)
// runs once more when there is one. A departure on the safe side: any o is valid, as every sign
// is exact. The mean leaves the kernel of long bent contours (their vertices crowd one side), and
// then the whole subtree below the node is traversed. The verdict is the last attempt's;
// edges_visited adds up both attempts and the search's pass.
template <class K, class Find, class Test>
ContourVerdict with_kernel_retry(ContourVerdict v, Find find, Test test) {
    if (!kernel_failed(v)) return v;
    thread_local ProjectionScratch scratch;  // per thread: traversal tasks run on several
    K o{};
    int32_t searched = 0;
    const bool found = find(scratch, o, searched, v.edge);
    v.edges_visited += searched;
    if (!found) return v;
    const int32_t before = v.edges_visited;
    v = test(o);
    v.edges_visited += before;
    return v;
}

// Alg. 1 as printed: o the mean (line 2), with the ray retry.
inline ContourVerdict unprojected_contour_test_at_mean(const int32_t* loop, int32_t n, const double* V, const Vec3& l) {
    const Vec3 m = kernel_point(loop, n, V);
    return with_ray_retry(l, [&](const Vec3& r) { return unprojected_contour_test_with_ray(loop, n, V, l, r, m); });
}

// The kernel-point retry of a verdict `v` of unprojected_contour_test_at_mean (v.kernel the mean).
inline ContourVerdict retry_kernel_point(ContourVerdict v, const int32_t* loop, int32_t n, const double* V,
                                         const Vec3& l) {
    const Vec3 m = v.kernel;
    return with_kernel_retry<Vec3>(
        v,
        [&](ProjectionScratch& s, Vec3& o, int32_t& searched, int32_t edge) {
            return find_kernel_point(loop, n, V, l, m, s, o, searched, edge);
        },
        [&](const Vec3& o) {
            return with_ray_retry(l, [&](const Vec3& r) { return unprojected_contour_test_with_ray(loop, n, V, l, r, o); });
        });
}

inline ContourVerdict unprojected_contour_test(const int32_t* loop, int32_t n, const double* V, const Vec3& l) {
    return retry_kernel_point(unprojected_contour_test_at_mean(loop, n, V, l), loop, n, V, l);
}

}  // namespace conecull
