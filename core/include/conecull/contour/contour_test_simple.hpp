// The simplicity fallback of "nc" (ours; DCD and CCD): when Alg. 1 (Alg. 3) fails, the node is
// still free of self-collision if its contour projected along l is a simple polygon
// (contour.hpp: with the cone bounded, a simple projected loop covers every point at most once),
// whether or not that polygon is star-shaped. Alg. 1 proves "simple" through "star-shaped around
// o", a sufficient condition; this test decides simplicity itself, with [TCYM09]'s certified
// edge-pair predicates (contour_test_cbc.hpp), but only on the pairs that can meet: the edges'
// extents along one direction of the projection plane are sorted and swept, and a pair whose
// extents are apart by more than the projections' error bound cannot meet (a separating axis),
// so it is skipped unexamined. O(n log n + k) for the k pairs whose extents overlap, where
// [TCYM09]'s test is O(n^2); k is capped at kSimplicityPairsPerEdge n (then the test gives up).
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

// Loops longer than this are not tried (the sort and the sweep's pairs grow with n), and the
// sweep gives up (not culled) after examining this many pairs per edge: a contour whose edges
// crowd one stretch of the sweep's axis would otherwise cost O(n^2).
inline constexpr int32_t kMaxSimplicityEdges = 4096;
inline constexpr int64_t kSimplicityPairsPerEdge = 64;

struct SimplicityScratch {
    std::vector<double> x, lo, hi;  // the vertices' X; the edges' extents
    std::vector<int32_t> order;
};

// The test over `poses` positions of the loop (DCD: V; CCD: V0 and V1, the loop moving linearly
// between them), with Signs deciding each pair for the whole motion (contour_test_cbc.hpp).
// Certified: "passed" only if every pair of edges is proven apart in projection (adjacent ones:
// meeting only at their shared vertex). Fails with kEdgesMayOverlap (edge, other_edge) at the
// first pair not proven apart. edges_visited counts 2 per pair examined, as [TCYM09]'s test.
template <class Signs>
ContourVerdict simplicity_test(int32_t n, const Signs& signs, const double* const* poses, int n_poses, const Vec3& l,
                               const int32_t* loop, SimplicityScratch& s, ContourVerdict out) {
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
    // Extents along g = u + phi w, a direction of the projection plane that no grid-aligned
    // contour side is perpendicular to (along u alone, a contour side parallel to w has all its
    // edges at one X, and the sweep would examine all their pairs). Z = fl(X + phi Y) with X, Y
    // the frame coordinates of project (kernel_point.hpp): each within 9 eps D1 scale of the
    // exact ones, D1 the largest |p - c|_1 and |X|, |Y| <= D1 scale, so Z is within
    // (9 (1 + phi) + 3) eps D1 scale < 18 eps D1 scale of the exact Z* = (p - c) . g, and a
    // difference of two Z within a further 4 eps D1 scale. c is one fixed point (the first vertex
    // in the first pose), so for a loop moving linearly every exact Z* is linear in t: an edge's
    // extent over the motion lies within the hull of its ends' Z in the poses. Pairs whose
    // rounded extents are apart by more than `gap` are apart exactly (a separating axis), at
    // every t.
    constexpr double phi = 0.6180339887498949;
    const ProjectionFrame f = projection_frame(l);
    const Vec3 c = load(poses[0], loop[0]);
    s.x.resize(static_cast<size_t>(n) * n_poses);
    double d1 = 0.0;
    for (int k = 0; k < n_poses; ++k)
        for (int32_t i = 0; i < n; ++i) {
            double x, y;
            d1 = std::fmax(d1, project(load(poses[k], loop[i]), c, f, x, y));
            s.x[static_cast<size_t>(k) * n + i] = x + phi * y;
        }
    const double gap = 64.0 * kEps * d1 * f.scale;  // > 2 x 18 + 4 eps D1 scale, with room
    if (!std::isfinite(gap)) return fail(0, 0);
    s.lo.resize(n);
    s.hi.resize(n);
    for (int32_t i = 0; i < n; ++i) {
        const int32_t i1 = i + 1 == n ? 0 : i + 1;
        double lo = s.x[i], hi = s.x[i];
        for (int k = 0; k < n_poses; ++k)
            for (const int32_t v : {i, i1}) {
                const double x = s.x[static_cast<size_t>(k) * n + v];
                lo = std::fmin(lo, x);
                hi = std::fmax(hi, x);
            }
        s.lo[i] = lo;
        s.hi[i] = hi;
    }
    s.order.resize(n);
    for (int32_t i = 0; i < n; ++i) s.order[i] = i;
    std::sort(s.order.begin(), s.order.end(),
              [&](int32_t a, int32_t b) { return s.lo[a] < s.lo[b] || (s.lo[a] == s.lo[b] && a < b); });
    int64_t budget = kSimplicityPairsPerEdge * n;
    for (int32_t a = 0; a < n; ++a) {
        const int32_t i = s.order[a];
        for (int32_t b = a + 1; b < n; ++b) {
            const int32_t j = s.order[b];
            if (s.lo[j] - s.hi[i] > gap) break;  // this one and every later one start beyond edge i
            const int32_t i1 = i + 1 == n ? 0 : i + 1, j1 = j + 1 == n ? 0 : j + 1;
            if (j == i1 || j1 == i) continue;  // adjacent: checked above
            const int32_t p = std::min(i, j), q = std::max(i, j);
            if (--budget < 0) return fail(p, q);  // gave up: not proven
            out.edges_visited += 2;
            if (!edges_apart(signs, p, p + 1 == n ? 0 : p + 1, q, q + 1 == n ? 0 : q + 1)) return fail(p, q);
        }
    }
    return out;
}

// DCD: the loop at V.
inline ContourVerdict simplicity_test(const int32_t* loop, int32_t n, const double* V, const Vec3& l,
                                      SimplicityScratch& s) {
    ContourVerdict out;
    out.kernel = kernel_point(loop, n, V);  // reported only (the test has no kernel point)
    out.kernel_end = out.kernel;
    const double* poses[1] = {V};
    return simplicity_test(n, QuadraticSignsDiscrete{loop, V, l}, poses, 1, l, loop, s, out);
}

// CCD: the loop moving linearly from V0 to V1, l fixed (the CCD cone's axis): simple at every t.
inline ContourVerdict simplicity_test_ccd(const int32_t* loop, int32_t n, const double* V0, const double* V1,
                                          const Vec3& l, SimplicityScratch& s) {
    ContourVerdict out;
    out.kernel = kernel_point(loop, n, V0);  // reported only, as the means at both ends
    out.kernel_end = kernel_point(loop, n, V1);
    const double* poses[2] = {V0, V1};
    return simplicity_test(n, QuadraticSignsContinuous{loop, V0, V1, l}, poses, 2, l, loop, s, out);
}

// The fallback after Alg. 1 (Alg. 3): `v` is that test's verdict on a loop of n edges; where it
// failed, simple(scratch) runs the simplicity test, and a pass turns v into a pass marked
// by_simplicity. A failure keeps v (its reason, kernel point and ray) for the debugger; the edges
// visited add up.
template <class Simple>
ContourVerdict with_simplicity_fallback(ContourVerdict v, int32_t n, Simple simple) {
    if (v.passed() || n > kMaxSimplicityEdges) return v;
    thread_local SimplicityScratch scratch;  // per thread: traversal tasks run on several
    const ContourVerdict s = simple(scratch);
    v.edges_visited += s.edges_visited;
    if (s.passed()) {
        v.reason = ContourReason::kPassed;
        v.by_simplicity = true;
    }
    return v;
}

}  // namespace conecull
