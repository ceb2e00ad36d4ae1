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

// A loop's positions copied in loop order, one buffer per pose, and the ids 0 .. n-1 that index
// them. The tests of "nc" read each contour vertex several times (Alg. 1's mean, its star test,
// the kernel clipping, the simplicity fallback): gathered once, those passes read contiguous
// memory instead of V at random. The tests see the same positions, so the same verdicts.
struct GatheredLoop {
    std::vector<double> P[2];
    std::vector<int32_t> ids;

    const double* gather(int pose, const int32_t* loop, int32_t n, const double* V) {
        std::vector<double>& out = P[pose];
        out.resize(3 * static_cast<size_t>(n));
        for (int32_t i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) out[3 * static_cast<size_t>(i) + k] = V[3 * static_cast<size_t>(loop[i]) + k];
        return out.data();
    }
    const int32_t* identity(int32_t n) {
        for (int32_t i = static_cast<int32_t>(ids.size()); i < n; ++i) ids.push_back(i);
        return ids.data();
    }
};

}  // namespace conecull
