// BVH self-traversal: "aabb" (no cones) and "nc" (Alg. 2, normal cone culling with the
// unprojected contour test). Both emit each candidate triangle pair exactly once: pairs inside
// one child are found by its SelfCollide, pairs across the children by Collide(L, R).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "conecull/bvh/bvh.hpp"
#include "conecull/cone/normal_cone.hpp"
#include "conecull/contour/contour.hpp"
#include "conecull/ccd/contour_test_ccd.hpp"
#include "conecull/contour/contour_test.hpp"
#include "conecull/trace/null_tracer.hpp"
#include "conecull/traversal/stats.hpp"

namespace conecull {

using TrianglePair = std::pair<int32_t, int32_t>;

// The motion a query covers, as a policy of the traversal: one pose (DCD, Alg. 1) or a linear
// step from V0 to V1 (CCD, Alg. 3). Only the contour test depends on it; boxes and cones were
// refit for it beforehand.
struct Discrete {
    const double* V;
    ContourVerdict contour_test(const int32_t* loop, int32_t n, const Vec3& l) const {
        return unprojected_contour_test(loop, n, V, l);
    }
};
struct Continuous {
    const double* V0;
    const double* V1;
    ContourVerdict contour_test(const int32_t* loop, int32_t n, const Vec3& l) const {
        return unprojected_contour_test_ccd(loop, n, V0, V1, l);
    }
};

template <bool kUseCones, class Tracer, class Motion = Discrete>
class SelfCollideTraversal {
   public:
    SelfCollideTraversal(const Bvh& bvh, const Contours& contours, const std::vector<NormalCone>& cones,
                         const Motion& motion, Tracer& tracer, DcdStats& stats, std::vector<TrianglePair>& candidates)
        : bvh_(bvh), contours_(contours), cones_(cones), motion_(motion), tracer_(tracer), stats_(stats), out_(candidates) {}

    void run() {
        if (bvh_.size() > 0) self_collide(0);
    }

   private:
    // Alg. 2 SelfCollide(N).
    void self_collide(int32_t i) {
        const BvhNode& n = bvh_[i];
        if (n.end - n.begin < 2) return;  // Alg. 2 line 1: a single triangle cannot self-collide
        ++stats_.self_tests;
        if constexpr (kUseCones) {
            if (is_self_collision_free(i)) return;  // Alg. 2 lines 5-8
        }
        if (n.is_leaf()) {
            for (int32_t a = n.begin; a < n.end; ++a)
                for (int32_t b = a + 1; b < n.end; ++b) emit(bvh_.order[a], bvh_.order[b]);
            return;
        }
        const int32_t l = Bvh::left(i), r = n.right;
        self_collide(l);      // Alg. 2 line 11
        self_collide(r);      // line 12
        collide(l, r);        // line 13
    }

    // Alg. 2 lines 5-6: normal cone test, then the unprojected contour test (Alg. 1).
    bool is_self_collision_free(int32_t i) {
        const NormalCone& cone = cones_[i];
        ++stats_.cone_tests;
        const bool bounded = cone.bounded();
        if constexpr (kTraceHooks<Tracer>) tracer_.on_cone_test(i, cone, bounded);
        if (!bounded) return false;
        ++stats_.cone_passed;
        if (!contours_.eligible(i)) {
            ++stats_.contour_ineligible;
            if constexpr (kTraceHooks<Tracer>) tracer_.on_contour_ineligible(i, contours_.status[i]);
            return false;
        }
        ++stats_.contour_tests;
        const ContourVerdict v = motion_.contour_test(contours_.loop(i), contours_.loop_size(i), cone.axis);
        stats_.contour_edges += v.edges_visited;
        ++stats_.contour_reasons[static_cast<int>(v.reason)];
        if constexpr (kTraceHooks<Tracer>) tracer_.on_contour_test(i, v);
        if (v.passed()) {
            ++stats_.contour_passed;
            return true;
        }
        ++stats_.contour_failed;
        return false;
    }

    // Collide(A, B): nodes with disjoint triangle sets.
    void collide(int32_t a, int32_t b) {
        ++stats_.bv_tests;
        const BvhNode& na = bvh_[a];
        const BvhNode& nb = bvh_[b];
        const bool overlap = na.box.overlaps(nb.box);
        if constexpr (kTraceHooks<Tracer>) tracer_.on_node_pair(a, b, overlap);
        if (!overlap) return;
        if (na.is_leaf() && nb.is_leaf()) {
            for (int32_t p = na.begin; p < na.end; ++p)
                for (int32_t q = nb.begin; q < nb.end; ++q) emit(bvh_.order[p], bvh_.order[q]);
            return;
        }
        // Descend the larger node (the only one that can be descended, if the other is a leaf).
        if (nb.is_leaf() || (!na.is_leaf() && na.end - na.begin >= nb.end - nb.begin)) {
            collide(Bvh::left(a), b);
            collide(na.right, b);
        } else {
            collide(a, Bvh::left(b));
            collide(a, nb.right);
        }
    }

    void emit(int32_t s, int32_t t) { out_.emplace_back(s < t ? s : t, s < t ? t : s); }

    const Bvh& bvh_;
    const Contours& contours_;
    const std::vector<NormalCone>& cones_;
    Motion motion_;
    Tracer& tracer_;
    DcdStats& stats_;
    std::vector<TrianglePair>& out_;
};

}  // namespace conecull
