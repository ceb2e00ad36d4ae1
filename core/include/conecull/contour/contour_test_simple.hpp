// The simplicity fallback of "nc" (ours; DCD): when Alg. 1 fails, the node is still free of
// self-collision if its contour projected along l is a simple polygon (contour.hpp: with the
// cone bounded, a simple projected loop covers every point at most once), whether or not that
// polygon is star-shaped. Alg. 1 proves "simple" through "star-shaped around o", a sufficient
// condition; this test decides simplicity itself, with [TCYM09]'s certified edge-pair
// predicates (contour_test_cbc.hpp), but only on the pairs that can meet: the edges' extents
// along the frame axis u are sorted and swept, and a pair whose extents are apart by more than
// the projections' error bound cannot meet (a separating axis), so it is skipped unexamined.
// O(n log n + k) for the k pairs whose extents overlap, where [TCYM09]'s test is O(n^2).
// Why: a contour can be simple without being star-shaped (a C-shaped or long bent patch; the
// clipped kernel is empty), and then Alg. 1 traverses the whole subtree below.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "conecull/contour/contour_test_cbc.hpp"
#include "conecull/contour/kernel_point.hpp"

namespace conecull {

// Loops longer than this are not tried (the sort and the sweep's pairs grow with n).
inline constexpr int32_t kMaxSimplicityEdges = 4096;

struct SimplicityScratch {
    std::vector<double> x, lo, hi;  // the vertices' X; the edges' extents
    std::vector<int32_t> order;
};

// Certified: "passed" only if every pair of edges is proven apart in projection (adjacent ones:
// meeting only at their shared vertex). Fails with kEdgesMayOverlap (edge, other_edge) at the
// first pair not proven apart. edges_visited counts 2 per pair examined, as [TCYM09]'s test.
inline ContourVerdict simplicity_test(const int32_t* loop, int32_t n, const double* V, const Vec3& l,
                                      SimplicityScratch& s) {
    ContourVerdict out;
    out.kernel = kernel_point(loop, n, V);  // reported only (the test has no kernel point)
    out.kernel_end = out.kernel;
    const QuadraticSignsDiscrete signs{loop, V, l};
    const auto fail = [&](int32_t i, int32_t j) {
        out.reason = ContourReason::kEdgesMayOverlap;
        out.edge = i;
        out.other_edge = j;
        return out;
    };
    // Adjacent edges first (every one of them shares a vertex, so no extent separates them).
    for (int32_t i = 0; i < n; ++i) {
        const int32_t i1 = i + 1 == n ? 0 : i + 1, i2 = i1 + 1 == n ? 0 : i1 + 1;
        out.edges_visited += 2;
        if (!adjacent_edges_apart(signs, i, i1, i2)) return fail(i, i1);
    }
    // Extents along u: X = fl(fl(p - c) . u) is within 9 eps D1 max|u_j| of the exact
    // projection (kernel_point.hpp, project), D1 the largest |p - c|_1; |X| <= D1 max|u_j|, so
    // a difference of two X is within a further 2 eps D1 max|u_j|. Pairs whose rounded extents
    // are apart by more than `gap` are apart exactly.
    const ProjectionFrame f = projection_frame(l);
    const Vec3 c = load(V, loop[0]);
    s.x.resize(n);
    double d1 = 0.0;
    for (int32_t i = 0; i < n; ++i) {
        double y;
        d1 = std::fmax(d1, project(load(V, loop[i]), c, f, s.x[i], y));
    }
    const double umax = std::fmax(std::fabs(f.u.x), std::fmax(std::fabs(f.u.y), std::fabs(f.u.z)));
    const double gap = 32.0 * kEps * d1 * umax;  // each X within ~4.02 eps D1 max|u_j|: ample room
    if (!std::isfinite(gap)) return fail(0, 0);
    s.lo.resize(n);
    s.hi.resize(n);
    for (int32_t i = 0; i < n; ++i) {
        const double a = s.x[i], b = s.x[i + 1 == n ? 0 : i + 1];
        s.lo[i] = std::fmin(a, b);
        s.hi[i] = std::fmax(a, b);
    }
    s.order.resize(n);
    for (int32_t i = 0; i < n; ++i) s.order[i] = i;
    std::sort(s.order.begin(), s.order.end(), [&](int32_t a, int32_t b) { return s.lo[a] < s.lo[b] || (s.lo[a] == s.lo[b] && a < b); });
    for (int32_t a = 0; a < n; ++a) {
        const int32_t i = s.order[a];
        for (int32_t b = a + 1; b < n; ++b) {
            const int32_t j = s.order[b];
            if (s.lo[j] - s.hi[i] > gap) break;  // this one and every later one start beyond edge i
            const int32_t i1 = i + 1 == n ? 0 : i + 1, j1 = j + 1 == n ? 0 : j + 1;
            if (j == i1 || j1 == i) continue;  // adjacent: checked above
            out.edges_visited += 2;
            if (!edges_apart(signs, std::min(i, j), std::min(i, j) + 1 == n ? 0 : std::min(i, j) + 1, std::max(i, j),
                             std::max(i, j) + 1 == n ? 0 : std::max(i, j) + 1))
                return fail(std::min(i, j), std::max(i, j));
        }
    }
    return out;
}

}  // namespace conecull
