// Per-node boundary contours (Sec. 3.2, Fig. 2: "its contour edges are defined by an ordered
// list of vertices"), precomputed once at build: topology never changes.
//
// A node is eligible for the contour test only if its triangles form one connected,
// consistently oriented, edge-manifold patch whose boundary is exactly one simple cycle, and
// none of them touches a non-manifold edge or vertex of the mesh. Its contour is that cycle,
// oriented like the triangles (the boundary of the chain sum of its triangles). Soundness of
// the culling rests on it: with every projected triangle positively oriented, the winding
// number of this cycle around a point counts the triangles covering it, so a simple
// (star-shaped) projected cycle means every point is covered at most once: interiors are
// disjoint. Touching is excluded too: near a projected vertex only that vertex's fan covers
// the plane (so two distinct vertices never project to one point), near a projected edge only
// that edge's two triangles, and the projection is one-to-one on each triangle; so two
// triangles of the patch meet only in the vertices or edge they share. No disk topology is
// assumed.
#pragma once

#include <cstdint>
#include <vector>

#include "conecull/bvh/bvh.hpp"
#include "conecull/mesh/topology.hpp"

namespace conecull {

enum class ContourStatus : uint8_t {
    kSimpleLoop = 0,        // eligible
    kNonManifold = 1,       // a triangle touches a non-manifold edge or vertex of the mesh
    kInconsistentEdge = 2,  // an edge used twice in the same direction (or > 2 times) inside
    kDisconnected = 3,      // triangles form more than one edge-connected patch
    kNoBoundary = 4,        // closed patch: no boundary loop
    kNonSimpleLoop = 5,     // the boundary passes a vertex twice
    kMultipleLoops = 6,     // more than one boundary loop (a patch with holes)
};

struct Contours {
    std::vector<uint8_t> status;     // per node, a ContourStatus
    std::vector<int32_t> offsets;    // per node + 1: loop vertices are vertices[offsets[i], offsets[i+1])
    std::vector<int32_t> vertices;   // loops of eligible nodes, in boundary order; empty otherwise
    std::vector<int32_t> components; // per node: number of edge-connected patches (0 if unknown)

    bool eligible(int32_t node) const { return status[node] == static_cast<uint8_t>(ContourStatus::kSimpleLoop); }
    int32_t loop_size(int32_t node) const { return offsets[node + 1] - offsets[node]; }
    const int32_t* loop(int32_t node) const { return vertices.data() + offsets[node]; }
};

Contours build_contours(const Bvh& bvh, const Topology& topo);

}  // namespace conecull
