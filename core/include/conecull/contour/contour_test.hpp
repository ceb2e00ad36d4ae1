// Unprojected contour test for DCD (Sec. 3.3-3.4, Alg. 1).
#pragma once

#include <cstdint>

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
};

struct ContourVerdict {
    ContourReason reason = ContourReason::kPassed;
    int32_t edge = -1;       // contour edge (v_edge, v_edge+1) where it failed
    int32_t crossings = 0;   // ray crossings counted so far
    Vec3 kernel;             // o
    Vec3 ray;                // r
    bool passed() const { return reason == ContourReason::kPassed; }
};

// Alg. 1 lines 3-7: any direction perpendicular to l serves; l x (0, 1, 0) = (-l_z, 0, l_x) is
// computed without rounding.
inline Vec3 ray_direction(const Vec3& l) {
    if (l.x == 0.0 && l.z == 0.0) return {1.0, 0.0, 0.0};
    return {-l.z, 0.0, l.x};
}

// Alg. 1. `loop` holds n vertex ids in boundary order; l is the cone axis.
// Every sign is exact (filtered, then expansion arithmetic), so "passed" is a proof that the
// projection of the loop along l is a simple star-shaped polygon around o. Two departures
// from the printed algorithm, both on the safe side: the ray test at a vertex is computed
// once per vertex (s2 of edge i is s1 of edge i+1), and the final answer requires exactly one
// crossing (the printed `return true` would also accept zero, which exact signs never produce).
inline ContourVerdict unprojected_contour_test(const int32_t* loop, int32_t n, const double* V, const Vec3& l) {
    ContourVerdict out;
    // Alg. 1 line 2: kernel point o = mean of the contour vertices. Any o is valid for the
    // test; rounding only moves it.
    Vec3 sum;
    for (int32_t i = 0; i < n; ++i) sum = sum + load(V, loop[i]);
    const double inv = 1.0 / n;
    out.kernel = inv * sum;
    out.ray = ray_direction(l);
    const Vec3& o = out.kernel;
    const Vec3& r = out.ray;
    int s0 = 0;
    Vec3 vi = load(V, loop[0]);
    int s1 = ray_side_sign(vi, o, r, l);  // Alg. 1 line 22
    for (int32_t i = 0; i < n; ++i) {
        const Vec3 vn = load(V, loop[i + 1 == n ? 0 : i + 1]);
        const int s = side_sign(o, vi, vn, l);  // Alg. 1 lines 11 and 18: kernel test
        if (i == 0) s0 = s;
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
        const int s2 = ray_side_sign(vn, o, r, l);  // Alg. 1 line 23
        if (s1 == 0 || s2 == 0) {                   // Alg. 1 line 24
            out.reason = ContourReason::kRayThroughVertex;
            out.edge = s1 == 0 ? i : (i + 1 == n ? 0 : i + 1);
            return out;
        }
        // Alg. 1 line 27: edge crosses the line of the ray, on the ray's side (see README,
        // "verified formulas": sweeping in the kernel sign's sense, a crossing of the ray ends
        // on the ray's s0 side).
        if (s2 == s0 && s1 != s2) {
            if (++out.crossings > 1) {
                out.reason = ContourReason::kMultipleCrossings;
                out.edge = i;
                return out;
            }
        }
        vi = vn;
        s1 = s2;
    }
    if (out.crossings != 1) out.reason = ContourReason::kNoCrossing;
    return out;
}

}  // namespace conecull
