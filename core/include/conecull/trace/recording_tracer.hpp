// RecordingTracer: appends the events of one query to pre-reserved struct-of-arrays buffers,
// handed to Python as NumPy arrays after the query (never one call into Python per event).
// Event kinds and fields are documented once, in conecull/trace.py (the Python schema).
#pragma once

#include <cstdint>
#include <vector>

#include "conecull/bvh/bvh.hpp"
#include "conecull/cone/normal_cone.hpp"
#include "conecull/contour/contour_test.hpp"
#include "conecull/traversal/bvtt_front.hpp"

namespace conecull {

// Contour events carry an Alg. 1 ContourReason (0..5), or, when Alg. 1 did not run because the
// node has no single simple contour, kIneligibleBase + the node's ContourStatus.
inline constexpr uint8_t kIneligibleBase = 16;

struct RecordingTracer {
    static constexpr bool enabled = true;

    // cone_test: one per ApexAngle(C_N) < pi check (Alg. 2 line 5)
    std::vector<int32_t> cone_node;
    std::vector<double> cone_axis;        // 3 per event
    std::vector<double> cone_apex_angle;  // radians; 2 pi for a full cone
    std::vector<uint8_t> cone_bounded;
    // contour_test: one per node whose cone passed (Alg. 2 line 6)
    std::vector<int32_t> contour_node;
    std::vector<uint8_t> contour_reason;
    std::vector<int32_t> contour_edge;
    std::vector<int32_t> contour_crossings;
    std::vector<double> contour_kernel;   // 3 per event
    std::vector<double> contour_kernel_end;  // 3 per event (CCD: o at t = 1; DCD: = kernel)
    std::vector<double> contour_ray;      // 3 per event
    std::vector<uint8_t> contour_simple;  // passed by the simplicity fallback (ContourVerdict::by_simplicity)
    // node pairs of Collide(A, B), aggregated by BVH level (the deeper node's depth)
    std::vector<int64_t> level_pairs, level_overlaps;
    // front: one per FrontTracking(Front_N) (Alg. 4 line 13), front methods only
    std::vector<int32_t> front_node;
    std::vector<uint8_t> front_mode;  // FrontMode
    std::vector<int32_t> front_before, front_after;  // |Front_N| at the query's start (0: none kept), and kept
    std::vector<int64_t> front_box_tests;
    // elementary tests
    std::vector<int32_t> elementary_pair;  // 2 per event
    std::vector<uint8_t> elementary_result;
    // CCD elementary tests: vertex-face (vertex, face) and edge-edge (edge a, edge b)
    std::vector<int32_t> vf_pair, ee_pair;  // 2 per event
    std::vector<uint8_t> vf_result, ee_result;

    const Bvh* bvh = nullptr;

    void reserve(const Bvh& tree) {
        bvh = &tree;
        const size_t n = tree.nodes.size();
        cone_node.reserve(n);
        cone_axis.reserve(3 * n);
        cone_apex_angle.reserve(n);
        cone_bounded.reserve(n);
        contour_node.reserve(n);
        contour_reason.reserve(n);
        contour_edge.reserve(n);
        contour_crossings.reserve(n);
        contour_kernel.reserve(3 * n);
        contour_kernel_end.reserve(3 * n);
        contour_ray.reserve(3 * n);
        contour_simple.reserve(n);
        int32_t depth = 0;
        for (const BvhNode& node : tree.nodes) depth = std::max(depth, node.depth);
        level_pairs.assign(depth + 1, 0);
        level_overlaps.assign(depth + 1, 0);
    }

    void on_cone_test(int32_t node, const NormalCone& cone, bool bounded) {
        cone_node.push_back(node);
        for (int k = 0; k < 3; ++k) cone_axis.push_back(cone.axis[k]);
        cone_apex_angle.push_back(cone.apex_angle());
        cone_bounded.push_back(bounded);
    }
    void on_contour_ineligible(int32_t node, uint8_t status) {
        push_contour(node, static_cast<uint8_t>(kIneligibleBase + status), -1, 0, Vec3{}, Vec3{}, Vec3{}, false);
    }
    void on_contour_test(int32_t node, const ContourVerdict& v) {
        push_contour(node, static_cast<uint8_t>(v.reason), v.edge, v.crossings, v.kernel, v.kernel_end, v.ray,
                     v.by_simplicity);
    }
    void on_node_pair(int32_t a, int32_t b, bool overlap) {
        const int32_t d = std::max(bvh->nodes[a].depth, bvh->nodes[b].depth);
        ++level_pairs[d];
        level_overlaps[d] += overlap;
    }
    void on_front(int32_t node, FrontMode mode, int32_t before, int32_t after, int64_t box_tests) {
        front_node.push_back(node);
        front_mode.push_back(static_cast<uint8_t>(mode));
        front_before.push_back(before);
        front_after.push_back(after);
        front_box_tests.push_back(box_tests);
    }
    void on_vf(int32_t v, int32_t f, bool result) {
        vf_pair.push_back(v);
        vf_pair.push_back(f);
        vf_result.push_back(result);
    }
    void on_ee(int32_t a, int32_t b, bool result) {
        ee_pair.push_back(a);
        ee_pair.push_back(b);
        ee_result.push_back(result);
    }
    void on_elementary(int32_t i, int32_t j, bool result) {
        elementary_pair.push_back(i);
        elementary_pair.push_back(j);
        elementary_result.push_back(result);
    }

   private:
    void push_contour(int32_t node, uint8_t reason, int32_t edge, int32_t crossings, const Vec3& o, const Vec3& o1,
                      const Vec3& r, bool simple) {
        contour_simple.push_back(simple);
        contour_node.push_back(node);
        contour_reason.push_back(reason);
        contour_edge.push_back(edge);
        contour_crossings.push_back(crossings);
        for (int k = 0; k < 3; ++k) contour_kernel.push_back(o[k]);
        for (int k = 0; k < 3; ++k) contour_kernel_end.push_back(o1[k]);
        for (int k = 0; k < 3; ++k) contour_ray.push_back(r[k]);
    }
};

}  // namespace conecull
