// Counters of one query. Kept in the traversal object (locals of the query), returned once.
#pragma once

#include <array>
#include <cstdint>

namespace conecull {

struct DcdStats {
    int64_t bv_tests = 0;            // box-box overlap tests of Collide(A, B)
    int64_t self_tests = 0;          // SelfCollide(N) calls on internal nodes (or multi-triangle leaves)
    int64_t cone_tests = 0;          // ApexAngle(C_N) < pi checks (Alg. 2 line 5)
    int64_t cone_passed = 0;
    int64_t contour_ineligible = 0;  // cone passed, but the node has no single simple contour
    int64_t contour_tests = 0;       // Alg. 1 runs
    int64_t contour_passed = 0;      // nodes culled
    int64_t contour_passed_simple = 0;  // of which by the simplicity fallback ("nc": Alg. 1 or 3 failed)
    int64_t contour_failed = 0;
    std::array<int64_t, 8> contour_reasons{};  // by ContourReason (kContourReasons)
    int64_t contour_edges = 0;       // contour edges visited by the contour test (cbc: 2 per edge pair)
    // BVTT front (methods "aabb+front", "nc+front"; 0 for the others), after the query:
    int64_t front_entries = 0;       // entries kept for the next query (over all sub-segments)
    int64_t front_segments = 0;      // records kept: one per node the query visited (bvtt_front.hpp)
    int64_t front_bytes = 0;         // all kept: entries (8 bytes), records (24), one slot per BVH node (4)
    int64_t front_added = 0;         // entries made this query (descents, merges, rebuilt sub-segments)
    int64_t front_removed = 0;       // entries of the previous front not kept (descended, merged, culled, churned)
    int64_t front_rested = 0;        // sub-segments not tracked this query: resting after churn
    int64_t elementary_tests = 0;
    int64_t colliding_pairs = 0;
    double seconds_build = 0;        // building the BVH and contours (the collider's first query only)
    double seconds_refit = 0, seconds_traversal = 0, seconds_elementary = 0;
    double seconds_contour = 0;      // inside the contour tests (steady clock around each call; part of traversal)

    // Sums the traversal counters of the parallel traversal's workers (integers: any order).
    void add_traversal_counters(const DcdStats& s) {
        bv_tests += s.bv_tests;
        self_tests += s.self_tests;
        cone_tests += s.cone_tests;
        cone_passed += s.cone_passed;
        contour_ineligible += s.contour_ineligible;
        contour_tests += s.contour_tests;
        contour_passed += s.contour_passed;
        contour_passed_simple += s.contour_passed_simple;
        contour_failed += s.contour_failed;
        for (size_t r = 0; r < contour_reasons.size(); ++r) contour_reasons[r] += s.contour_reasons[r];
        contour_edges += s.contour_edges;
        front_added += s.front_added;
        front_rested += s.front_rested;
        seconds_contour += s.seconds_contour;  // time: summed over the threads
    }
};

}  // namespace conecull
