// The simplicity fallback of "nc" (ours; DCD and CCD): when Alg. 1 (Alg. 3) fails, the node is
// still free of self-collision if its contour projected along l is a simple polygon
// (contour.hpp: with the cone bounded, a simple projected loop covers every point at most once),
// whether or not that polygon is star-shaped. Alg. 1 proves "simple" through "star-shaped around
// o", a sufficient condition; this test decides simplicity itself, with [TCYM09]'s certified
// edge-pair predicates (contour_test_cbc.hpp), but only on the pairs that can meet: a pair whose
// extents along one direction g of the projection plane, or along the perpendicular h, are apart
// by more than the projections' error bound cannot meet (a separating axis), so it is skipped
// unexamined. The loop is cut into runs monotone along g, whose own non-adjacent pairs are all
// apart that way; the runs are sorted and swept, and two runs whose boxes meet are walked in step
// along g. Adjacent edges are mostly settled from the same coordinates (turn_margin).
// O(n + r log r + k) for r runs and the k pairs scanned, where [TCYM09]'s test is O(n^2); k is
// capped at kSimplicityPairsPerEdge n (then the test gives up).
// Why: a contour can be simple without being star-shaped (a C-shaped or long bent patch; the
// clipped kernel is empty), and then Alg. 1 traverses the whole subtree below.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "conecull/contour/contour_test_cbc.hpp"
#include "conecull/contour/kernel_point.hpp"

namespace conecull {

// Loops longer than this are not tried (the sweep's pairs grow with n), and the sweep gives up
// (not culled) after scanning this many pairs (of runs, and of edges in the walks) per edge: a
// contour whose edges crowd one stretch of the sweep's axis would otherwise cost O(n^2).
inline constexpr int32_t kMaxSimplicityEdges = 4096;
inline constexpr int64_t kSimplicityPairsPerEdge = 64;
// The sweep directions g = u + phi w, h = w - phi u (simplicity_test).
inline constexpr double kSimplicityPhi = 0.6180339887498949;

// An edge's extents along g ([lo, hi]) and h ([hlo, hhi]).
struct SweepEdge {
    double lo, hi, hlo, hhi;
};

// A run of the loop: its edges first, ..., first + count - 1 (loop order, not wrapping), each
// step along g of one strict sign dir (+1 increasing, -1 decreasing; 0: an edge alone), and the
// box of their extents.
struct SweepRun {
    double lo, hi, hlo, hhi;
    int32_t first, count, dir;
};

struct SimplicityScratch {
    std::vector<double> zg, zh;            // one pose: Z_g, Z_h of the loop's vertices, two wrapped
    std::vector<SweepEdge> edges;          // in loop order
    std::vector<SweepRun> runs;            // in loop order, then in sweep order
    bool gave_up = false;                  // the last test failed unproven (its budget, or not finite)
};

// A vertex's rounded coordinates along g and h (simplicity_test), in each pose.
template <int n_poses>
struct ZPoint {
    double g[n_poses], h[n_poses];
};

// Adjacent edges (a, b), (b, c) meet only at b when the projected vectors A = a - b and C = c - b
// are proven not to point one way: (g, h) is an invertible linear image of the projection plane
// (g = u + phi w, h = w - phi u with u, w the exact frame, kernel_point.hpp), so A, C are parallel
// with a positive ratio there iff they are in the plane; a negative dot product of their (g, h)
// images, or a cross product of one strict sign, rules that out (and a zero-length edge, whose
// products are 0). Over a linear motion A(t), C(t) are linear in t and each product quadratic,
// with Bernstein coefficients k0 = P(A0, C0), k2 = P(A1, C1), k1 = (P(A0, C1) + P(A1, C0)) / 2:
// all of one strict sign prove it for every t. Error: each Z within 18 eps D1 scale of the exact
// Z* and |Z*| <= (1 + phi) D1 scale (see simplicity_test), so a difference of two Z is within
// delta = 39.3 eps D1 scale of the exact one, R = 3.24 D1 scale bounding it; a sum of two rounded
// products within 4 R delta + 4 eps R^2 (1 + O(eps)) < 552 eps (D1 scale)^2 of the exact value:
// `bound` = 1024 eps (D1 scale)^2 covers k0 and k2, and 2 bound the four products of 2 k1
// (8 R delta + 16 eps R^2 < 1188 eps (D1 scale)^2). The turn is proven iff turn_margin > bound:
// the margin is the largest of -dot and |cross| (one pose), or, over a step, of the least
// coefficient of -dot, of cross and of -cross, the middle one halved (exact: a middle coefficient
// beyond 2 bound is a normal double). A margin, not a verdict, so that one pass can keep the least
// over the loop and compare it with the bound once D1 is known.
template <int n_poses>
double turn_margin(const ZPoint<n_poses>& a, const ZPoint<n_poses>& b, const ZPoint<n_poses>& c) {
    double ag[n_poses], ah[n_poses], cg[n_poses], ch[n_poses];
    for (int k = 0; k < n_poses; ++k) {
        ag[k] = a.g[k] - b.g[k], ah[k] = a.h[k] - b.h[k];
        cg[k] = c.g[k] - b.g[k], ch[k] = c.h[k] - b.h[k];
    }
    if constexpr (n_poses == 1) {  // one pose: k0 alone
        const double dot = ag[0] * cg[0] + ah[0] * ch[0], cr = ag[0] * ch[0] - ah[0] * cg[0];
        return max_into(-dot, max_into(cr, -cr));
    }
    const int m = n_poses - 1;
    const double dot0 = ag[0] * cg[0] + ah[0] * ch[0], dot2 = ag[m] * cg[m] + ah[m] * ch[m];
    const double dot1 = ag[0] * cg[m] + ah[0] * ch[m] + ag[m] * cg[0] + ah[m] * ch[0];
    const double cr0 = ag[0] * ch[0] - ah[0] * cg[0], cr2 = ag[m] * ch[m] - ah[m] * cg[m];
    const double cr1 = ag[0] * ch[m] - ah[0] * cg[m] + ag[m] * ch[0] - ah[m] * cg[0];
    const double back = min_into(min_into(-dot0, -dot2), -0.5 * dot1);
    const double left = min_into(min_into(cr0, cr2), 0.5 * cr1), right = min_into(min_into(-cr0, -cr2), -0.5 * cr1);
    return max_into(back, max_into(left, right));
}

// One pose, the pass's first half over the whole loop at once: Z_g = fl(X + phi Y) and
// Z_h = fl(Y - phi X) of every vertex into zg[0, n), zh[0, n) (the numbers of simplicity_test's
// z_of, bit for bit), zg[n], zg[n + 1] (zh too) repeating vertices 0 and 1; returns the largest
// |p - c|_1. Why apart from the pass: as a loop of its own, without the runs' branches, the
// projections of several vertices overlap, and run four at a time with AVX2
// (contour_test_simple.cpp). On the folding sheet of `bench contour`, contour time per DCD query
// 0.91x in this portable form, 0.86x with AVX2 (four alternations of the builds).
// Vertices [from, to), d1 the largest |p - c|_1 so far.
inline double project_loop_gh_range(const int32_t* loop, const double* V, int32_t from, int32_t to, const Vec3& c,
                                    const ProjectionFrame& f, double* zg, double* zh, double d1) {
    for (int32_t i = from; i < to; ++i) {
        double x, y;
        d1 = max_into(d1, project(load(V, loop[i]), c, f, x, y));
        zg[i] = x + kSimplicityPhi * y;
        zh[i] = y - kSimplicityPhi * x;
    }
    return d1;
}
inline void wrap_loop_gh(double* zg, double* zh, int32_t n) {
    zg[n] = zg[0], zg[n + 1] = zg[1], zh[n] = zh[0], zh[n + 1] = zh[1];
}
inline double project_loop_gh_portable(const int32_t* loop, const double* V, int32_t n, const Vec3& c,
                                       const ProjectionFrame& f, double* zg, double* zh) {
    const double d1 = project_loop_gh_range(loop, V, 0, n, c, f, zg, zh, 0.0);
    wrap_loop_gh(zg, zh, n);
    return d1;
}

// One pose: the least turn_margin over the loop's vertices, from project_loop_gh's arrays
// (vertex b in [from, to), 1 <= b <= n; n is vertex 0), `margin` the least so far.
inline double least_turn_margin_range(const double* zg, const double* zh, int32_t from, int32_t to, double margin) {
    using Z1 = ZPoint<1>;
    for (int32_t b = from; b < to; ++b)
        margin = min_into(margin, turn_margin(Z1{{zg[b - 1]}, {zh[b - 1]}}, Z1{{zg[b]}, {zh[b]}},
                                              Z1{{zg[b + 1]}, {zh[b + 1]}}));
    return margin;
}
// The least over all n, + 0.0: a zero margin is +0 whichever of +0 (a turn straight back) and -0
// (a zero-length edge) came first, so that the AVX2 path, which takes the least in another order,
// returns the same bits (only `margin > bound` reads it).
inline double least_turn_margin_portable(const double* zg, const double* zh, int32_t n) {
    return least_turn_margin_range(zg, zh, 1, n + 1, std::numeric_limits<double>::infinity()) + 0.0;
}

// The same two, on AVX2 where the CPU has it (the same operations in the same order per vertex, so
// the same numbers: no FMA).
double project_loop_gh(const int32_t* loop, const double* V, int32_t n, const Vec3& c, const ProjectionFrame& f,
                       double* zg, double* zh);
double least_turn_margin(const double* zg, const double* zh, int32_t n);
bool simplicity_pass_vectorised();

// The test on the loop of vertex ids `loop` over `n_poses` positions P[k] (DCD: one; CCD: two, the
// loop moving linearly between them); `signs` decides each pair for the whole motion
// (contour_test_cbc.hpp). Certified: "passed" only if every pair of edges is proven apart in
// projection (adjacent ones: meeting only at their shared vertex). Fails with
// kEdgesMayOverlap (edge, other_edge) at the first pair not proven apart. edges_visited counts 2
// per pair examined with the predicates, as [TCYM09]'s test.
template <int n_poses, class Signs>
ContourVerdict simplicity_test(const int32_t* loop, const double* const* P, int32_t n, const Vec3& l,
                               SimplicityScratch& s, const Signs& signs) {
    ContourVerdict out;
    s.gave_up = false;
    const auto fail = [&](int32_t i, int32_t j) {
        out.reason = ContourReason::kEdgesMayOverlap;
        out.edge = i;
        out.other_edge = j;
        return out;
    };
    // Extents along g = u + phi w and h = w - phi u, two directions of the projection plane
    // (perpendicular for a unit l) that no grid-aligned contour side is perpendicular to (along u alone, a
    // contour side parallel to w has all its edges at one X, and the sweep would scan all their
    // pairs). Z_g = fl(X + phi Y), Z_h = fl(Y - phi X) with X, Y the frame coordinates of project
    // (kernel_point.hpp): each within 9 eps D1 scale of the exact ones, D1 the largest
    // |p - c|_1 and |X|, |Y| <= D1 scale, so Z is within (9 (1 + phi) + 3) eps D1 scale
    // < 18 eps D1 scale of the exact Z* = (p - c) . g (or h), and a difference of two Z within a
    // further 4 eps D1 scale. c is one fixed point (the first vertex in the first pose), so for a
    // loop moving linearly every exact Z* is linear in t: an edge's extent over the motion lies
    // within the hull of its ends' Z in the poses. Pairs whose rounded extents along g or along h
    // are apart by more than `gap` are apart exactly (a separating axis), at every t.
    constexpr double phi = kSimplicityPhi;
    const ProjectionFrame f = projection_frame(l);
    const Vec3 c = load(P[0], loop[0]);
    const size_t nn = static_cast<size_t>(n);
    using Z = ZPoint<n_poses>;
    double d1 = 0.0;
    // Vertex i's Z in every pose; `dmax` keeps the largest |p - c|_1 (the pass: the loop's D1).
    const auto z_of = [&](int32_t i, double& dmax) {
        Z z;
        for (int k = 0; k < n_poses; ++k) {
            double x, y;
            dmax = max_into(dmax, project(load(P[k], loop[i]), c, f, x, y));
            z.g[k] = x + phi * y;
            z.h[k] = y - phi * x;
        }
        return z;
    };
    // An edge's extents: the hull of its ends' Z over the poses.
    const auto extent = [](const Z& a, const Z& b) {
        SweepEdge e{a.g[0], a.g[0], a.h[0], a.h[0]};
        for (int k = 0; k < n_poses; ++k)
            for (const Z* v : {&a, &b}) {
                e.lo = min_into(e.lo, v->g[k]), e.hi = max_into(e.hi, v->g[k]);
                e.hlo = min_into(e.hlo, v->h[k]), e.hhi = max_into(e.hhi, v->h[k]);
            }
        return e;
    };
    // An edge's step along g from vertex a to b: b's least Z_g minus a's largest when positive
    // (b lies beyond a in every pose: dir +1), else a's least minus b's largest (dir -1 when
    // positive, 0 when neither).
    const auto step_of = [](const Z& a, const Z& b, double& step) {
        if constexpr (n_poses == 1) {  // a's least minus b's largest is -(b - a), exactly
            const double up = b.g[0] - a.g[0];
            step = std::fabs(up);
            return static_cast<int32_t>(up > 0.0) - static_cast<int32_t>(up < 0.0);
        }
        double amin = a.g[0], amax = a.g[0], bmin = b.g[0], bmax = b.g[0];
        for (int k = 1; k < n_poses; ++k) {
            amin = min_into(amin, a.g[k]), amax = max_into(amax, a.g[k]);
            bmin = min_into(bmin, b.g[k]), bmax = max_into(bmax, b.g[k]);
        }
        const double up = bmin - amax, down = amin - bmax;
        step = up > 0.0 ? up : down;
        return static_cast<int32_t>(up > 0.0) - static_cast<int32_t>(down > 0.0);
    };
    // The loop cut into runs monotone along g, in the same pass. Within a run, edges k and k + m
    // (m >= 2) are apart along g by at least the step of edge k + 1 (lo of edge k + 2 is the least
    // Z_g of its first vertex, hi of edge k the largest of its last, and lo increases along the
    // run): once every interior step (not a run's first or last edge) is beyond the gap, the skip
    // test would pass all of them, so they are not examined at all. Why: the sweep then orders a
    // few runs instead of n edges, and scans pairs of edges only where two runs' boxes meet
    // (the 235 fallback tests of bench contour's sheet: runs of 16 edges on average; by a model in
    // numpy, 1.1 pairs of edges and 0.2 of runs scanned per edge, against 3.0 pairs of edges by
    // the sweep over edges it replaces, the same 24 pairs reaching the predicates).
    SweepEdge* const ed = scratch_buffer(s.edges, nn);
    SweepRun* const runs = scratch_buffer(s.runs, nn);
    int32_t n_runs = 0;
    SweepRun run{};  // the open run, stored when the next one opens
    double interior_step = std::numeric_limits<double>::infinity(), last_step = 0.0;
    const auto add_edge = [&](int32_t i, const Z& a, const Z& b) {
        const SweepEdge e = extent(a, b);
        // Field by field: a copy of the whole struct was compiled as two 8-byte stores and a
        // 16-byte load of the same bytes, which stalls store forwarding (a fifth of the test's
        // time in a perf profile).
        ed[i].lo = e.lo, ed[i].hi = e.hi, ed[i].hlo = e.hlo, ed[i].hhi = e.hhi;
        double step;
        const int32_t dir = step_of(a, b, step);
        if (dir != 0 && dir == run.dir && i > 0) {
            interior_step = min_into(interior_step, last_step);  // the run's last edge becomes interior
            ++run.count;
            run.lo = min_into(run.lo, e.lo), run.hi = max_into(run.hi, e.hi);
            run.hlo = min_into(run.hlo, e.hlo), run.hhi = max_into(run.hhi, e.hhi);
        } else {
            if (i > 0) runs[n_runs++] = run;
            run = SweepRun{e.lo, e.hi, e.hlo, e.hhi, i, 1, dir};
        }
        last_step = step;
    };
    // One pass over the loop (n >= 3): each vertex projected once, in every pose; the extents and
    // run of the edge it ends; the turn at the vertex before (adjacent edges share a vertex, so no
    // extent separates them: turn_margin settles most of them, the predicates the rest), kept as
    // the least margin, compared with the bound once D1 is known (the projections' bound needs all
    // of them).
    double margin = std::numeric_limits<double>::infinity();
    if constexpr (n_poses == 1) {
        double* const zg = scratch_buffer(s.zg, nn + 2);
        double* const zh = scratch_buffer(s.zh, nn + 2);
        d1 = project_loop_gh(loop, P[0], n, c, f, zg, zh);
        margin = least_turn_margin(zg, zh, n);
        for (int32_t i = 0; i < n; ++i) add_edge(i, Z{{zg[i]}, {zh[i]}}, Z{{zg[i + 1]}, {zh[i + 1]}});
    } else {
        const Z z0 = z_of(0, d1), z1 = z_of(1, d1);
        add_edge(0, z0, z1);
        Z za = z0, zb = z1;
        for (int32_t i = 2; i < n; ++i) {
            const Z zc = z_of(i, d1);
            margin = min_into(margin, turn_margin(za, zb, zc));  // at vertex i - 1
            add_edge(i - 1, zb, zc);
            za = zb, zb = zc;
        }
        margin = min_into(margin, turn_margin(za, zb, z0));  // at vertex n - 1
        margin = min_into(margin, turn_margin(zb, z0, z1));  // at vertex 0
        add_edge(n - 1, zb, z0);
    }
    runs[n_runs++] = run;
    const double gap = 64.0 * kEps * d1 * f.scale;  // > 2 x 18 + 4 eps D1 scale, with room
    // Positions are finite (the bindings check), and so is every Z and difference of two, within
    // 2 (1 + phi) D1 scale, unless that overflows: then not proven (the runs' sort needs no NaN).
    if (!std::isfinite(4.0 * d1 * f.scale)) return s.gave_up = true, fail(0, 0);
    const double ds = d1 * f.scale, bound = 1024.0 * kEps * ds * ds;
    if (!(margin > bound)) {
        // Some turn is not proven from the coordinates: in loop order, each such one by the
        // predicates (the first not proven apart fails; the counts as if each pair was examined).
        double unused = 0.0;
        const auto again = [&](int32_t i) { return z_of(i, unused); };  // the same numbers as the pass's
        for (int32_t i = 0; i < n; ++i) {
            const int32_t i1 = i + 1 == n ? 0 : i + 1, i2 = i1 + 1 == n ? 0 : i1 + 1;
            out.edges_visited += 2;
            if (!(turn_margin(again(i), again(i1), again(i2)) > bound) && !adjacent_edges_apart(signs, i, i1, i2))
                return fail(i, i1);
        }
    } else {
        out.edges_visited += 2 * n;
    }
    // The runs' sweep: runs sorted by lo (exactly: few of them); a pair of runs whose boxes are
    // apart along g or h is skipped whole (each edge's extents lie inside its run's box, and
    // rounding is monotone, so its edges' pairs are as far apart); otherwise the two are walked.
    if (!(interior_step > gap)) {
        // A run's interior step is not beyond the gap (an edge nearly perpendicular to g, within
        // rounding): its non-adjacent pairs are not proven apart by their order. Every edge its
        // own run: the plain sweep over edges.
        for (int32_t i = 0; i < n; ++i) runs[i] = SweepRun{ed[i].lo, ed[i].hi, ed[i].hlo, ed[i].hhi, i, 1, 0};
        n_runs = n;
    }
    std::sort(runs, runs + n_runs, [](const SweepRun& a, const SweepRun& b) { return a.lo < b.lo; });
    int64_t budget = kSimplicityPairsPerEdge * n;
    const auto next = [n](int32_t i) { return i + 1 == n ? 0 : i + 1; };
    for (int32_t a = 0; a < n_runs; ++a) {
        const SweepRun ra = runs[a];
        // Run a's edges in increasing g (a decreasing run backwards): along them lo and hi increase.
        const int32_t da = ra.dir >= 0 ? 1 : -1, sa = ra.dir >= 0 ? ra.first : ra.first + ra.count - 1;
        for (int32_t b = a + 1; b < n_runs; ++b) {
            const SweepRun& rb = runs[b];
            if (rb.lo - ra.hi > gap) break;  // every run from b on starts beyond run a
            if (--budget < 0) return s.gave_up = true, fail(std::min(ra.first, rb.first), std::max(ra.first, rb.first));
            if ((rb.hlo - ra.hhi > gap) | (ra.hlo - rb.hhi > gap)) continue;
            const int32_t db = rb.dir >= 0 ? 1 : -1, sb = rb.dir >= 0 ? rb.first : rb.first + rb.count - 1;
            const int32_t end_b = sb + db * rb.count;
            // The walk: run a's edges from the first not below run b (runs are sorted by lo, so run
            // a starts first), each against the edges of run b not apart from it along g: a window
            // that only moves forward.
            int32_t ka = 0;  // a binary search: hi increases along run a
            for (int32_t len = ra.count; len > 0;) {
                const int32_t half = len / 2;
                if (rb.lo - ed[sa + da * (ka + half)].hi > gap) ka += half + 1, len -= half + 1;
                else len = half;
            }
            int32_t i = sa + da * ka;
            int32_t from = sb;
            for (; ka < ra.count; ++ka, i += da) {
                const SweepEdge ea = ed[i];
                if (ea.lo - rb.hi > gap) break;  // this edge and the rest of run a lie beyond run b
                // Apart along h from run b's box, so from each of its edges (rounding is monotone):
                // no pair to scan. Why: two runs whose boxes meet mostly do so at a few edges (a
                // loop's two halves span the same g and h), and the scan below costs a branch per
                // pair (on `bench contour`'s sheet, by a numpy model, 4859 pairs scanned per query
                // without this test, 904 with it). The window moves on at the next edge scanned:
                // lo only increases along run a.
                if ((rb.hlo - ea.hhi > gap) | (ea.hlo - rb.hhi > gap)) continue;
                while (from != end_b && ea.lo - ed[from].hi > gap) from += db;
                const int32_t after = next(i), before = i == 0 ? n - 1 : i - 1;  // edge i's neighbours
                for (int32_t j = from; j != end_b; j += db) {
                    const SweepEdge& eb = ed[j];
                    if (eb.lo - ea.hi > gap) break;  // the rest of run b starts beyond edge i
                    if (--budget < 0) return s.gave_up = true, fail(std::min(i, j), std::max(i, j));
                    // Skipped: adjacent (checked above), or apart along h. One branch, nearly
                    // always taken.
                    if ((j == after) | (j == before) | (eb.hlo - ea.hhi > gap) | (ea.hlo - eb.hhi > gap)) continue;
                    const int32_t p = std::min(i, j), q = std::max(i, j);
                    out.edges_visited += 2;
                    if (!edges_apart(signs, p, next(p), q, next(q))) return fail(p, q);
                }
            }
        }
    }
    return out;
}

// DCD: the loop of vertex ids `loop` at V. (No kernel point: the test has none; the fallback
// keeps Alg. 1's.)
inline ContourVerdict simplicity_test(const int32_t* loop, int32_t n, const double* V, const Vec3& l,
                                      SimplicityScratch& s) {
    const double* poses[1] = {V};
    return simplicity_test<1>(loop, poses, n, l, s, QuadraticSignsDiscrete{loop, V, l});
}

// CCD: the loop moving linearly from V0 to V1, l fixed (the CCD cone's axis): simple at every t.
inline ContourVerdict simplicity_test_ccd(const int32_t* loop, int32_t n, const double* V0, const double* V1,
                                          const Vec3& l, SimplicityScratch& s) {
    const double* poses[2] = {V0, V1};
    return simplicity_test<2>(loop, poses, n, l, s, QuadraticSignsContinuous{loop, V0, V1, l});
}

// Which of "nc"'s tests a node's contour test runs first: the one that proved the node when it was
// last tested (the collider keeps one per node; with_simplicity_fallback). Why: nodes keep
// their shape from frame to frame, and so which test proves them (measured: 98-100% of the nodes
// tested in two consecutive frames of our scenes); where Alg. 1 with the mean fails, it costs a
// pass over the loop for nothing (on the 64K folding sheet, 218 of its 235 tests in 7 frames).
enum class FirstTest : uint8_t { kStar = 0, kSimplicity = 1 };

// The contour test of "nc" on a loop of n edges, from three tests: star() is Alg. 1's (Alg. 3's)
// verdict with the mean as the kernel point; simple(scratch) the simplicity test; retry(v) the
// kernel-point search after a failed star() (retry_kernel_point: the clipped kernel). The culled
// nodes are those any of the three passes, in either order.
//   - FirstTest::kStar: star(); where it fails, the simplicity test, and a pass turns v into a
//     pass marked by_simplicity (its kernel point and ray: the mean's failed attempt); where that
//     fails too, the search.
//   - FirstTest::kSimplicity: the simplicity test; a pass is marked by_simplicity, with no kernel
//     point (kernel, kernel_end and ray NaN). Where it fails, star(), then the search.
// The search runs only where the simplicity test gave up (budget, length) or, over a step
// (`exact_pairs` false), could not prove a pair apart that Alg. 3 might still prove. In one pose
// its pair predicates are exact, so its failure there proves the projected loop not simple: no
// kernel point can exist, and star() fails too. A failure is reported with star()'s verdict (its
// reason, kernel point and ray, for the debugger) in either order, run for that purpose if the
// simplicity test ran first. The edges visited add up over the tests run.
template <class Star, class Simple, class Retry>
ContourVerdict with_simplicity_fallback(int32_t n, bool exact_pairs, FirstTest first, Star star, Simple simple,
                                        Retry retry) {
    thread_local SimplicityScratch scratch;  // per thread: traversal tasks run on several
    const bool sweep = n <= kMaxSimplicityEdges;
    int32_t swept = 0;
    bool swept_first = false;
    if (first == FirstTest::kSimplicity && sweep) {
        ContourVerdict s = simple(scratch);
        if (s.passed()) {
            constexpr double nan = std::numeric_limits<double>::quiet_NaN();
            s.by_simplicity = true;
            s.kernel = s.kernel_end = s.ray = Vec3{nan, nan, nan};
            return s;
        }
        swept = s.edges_visited;
        swept_first = true;
    }
    ContourVerdict v = star();
    v.edges_visited += swept;
    if (v.passed()) return v;
    if (sweep && !swept_first) {
        const ContourVerdict s = simple(scratch);
        v.edges_visited += s.edges_visited;
        if (s.passed()) {
            v.reason = ContourReason::kPassed;
            v.by_simplicity = true;
            return v;
        }
    }
    if (sweep && exact_pairs && !scratch.gave_up) return v;
    return retry(v);
}

// The order for the next query from a verdict of with_simplicity_fallback: a node passed by the
// simplicity test tries it first next time, one passed by Alg. 1 (with the mean or a searched
// kernel point) Alg. 1; a failure keeps the order.
inline FirstTest next_first_test(const ContourVerdict& v, FirstTest first) {
    if (!v.passed()) return first;
    return v.by_simplicity ? FirstTest::kSimplicity : FirstTest::kStar;
}

}  // namespace conecull
