// AABB BVH over the triangles (Sec. 5.1: "We use AABBs as the underlying bounding volume"),
// built once from the first pose by bottom-up clustering along the mesh (the paper builds it
// top-down; see build_bvh) and refit bottom-up for every query.
#pragma once

#include <cstdint>
#include <vector>

#include "conecull/cone/normal_cone.hpp"
#include "conecull/mesh/topology.hpp"
#include "conecull/vec3.hpp"

namespace conecull {

struct Aabb {
    Vec3 lo, hi;
    // Closed boxes: boxes that only touch still overlap, as touching triangles collide.
    bool overlaps(const Aabb& o) const {
        return lo.x <= o.hi.x && o.lo.x <= hi.x && lo.y <= o.hi.y && o.lo.y <= hi.y &&
               lo.z <= o.hi.z && o.lo.z <= hi.z;
    }
    // The same test with no early exit: all six comparisons, then one branch on the result
    // (FrontTracking's walk over its entries, self_collide.hpp, says why it uses it).
    bool overlaps_flat(const Aabb& o) const {
        return (lo.x <= o.hi.x) & (o.lo.x <= hi.x) & (lo.y <= o.hi.y) & (o.lo.y <= hi.y) &
               (lo.z <= o.hi.z) & (o.lo.z <= hi.z);
    }
};

// Nodes in pre-order: the left child of node i is i + 1, so children always follow their
// parent and a reverse sweep refits bottom-up.
struct BvhNode {
    Aabb box;           // 48 B
    int32_t right = -1; // right child, -1 for a leaf
    int32_t begin = 0;  // triangle range [begin, end) in Bvh::order
    int32_t end = 0;
    int32_t depth = 0;
    bool is_leaf() const { return right < 0; }
};
// 64 B, but the vector's storage is only 16-byte aligned, so a node's four ints share a cache
// line with the next node's box. alignas(64) (one node, one line) measured no faster here: an
// A/B of 4 runs on three steps and four methods moved traversal times by -25% to +43% either
// way, the noise of this VM.
static_assert(sizeof(BvhNode) == 64, "BvhNode: box 48 B + 4 int32 = 64 B");

struct Bvh {
    std::vector<BvhNode> nodes;
    std::vector<int32_t> order;  // triangle ids in leaf order; node ranges index into it
    int32_t leaf_size = 1;

    static int32_t left(int32_t i) { return i + 1; }
    int32_t size() const { return static_cast<int32_t>(nodes.size()); }
    const BvhNode& operator[](int32_t i) const { return nodes[i]; }
};

// Bottom-up clustering along mesh adjacency (compact connected patches); components are joined
// by a median split of their centroids.
Bvh build_bvh(const Topology& topo, const double* V, int32_t leaf_size);

// Refit boxes from positions V (n, 3); O(nodes). The refits give the same values for any
// number of threads.
void refit_boxes(Bvh& bvh, const Topology& topo, const double* V, int threads = 1);

// Boxes and normal cones for every node from positions V, in one sweep: leaves merge their
// triangles' cones, inner nodes their children's.
void refit_boxes_and_cones(Bvh& bvh, const Topology& topo, const double* V, std::vector<NormalCone>& cones,
                           int threads = 1);

// CCD: swept boxes (the box of both poses holds every linear motion between them) and cones
// holding every triangle's normal for all t in [0, 1].
void refit_boxes_ccd(Bvh& bvh, const Topology& topo, const double* V0, const double* V1, int threads = 1);
void refit_boxes_and_cones_ccd(Bvh& bvh, const Topology& topo, const double* V0, const double* V1,
                               std::vector<NormalCone>& cones, int threads = 1);

}  // namespace conecull
