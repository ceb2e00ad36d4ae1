// Mesh topology, built once from the faces: topology never changes between frames.
// Accepts any triangle soup (non-manifold edges and vertices, several components, holes);
// what is not a manifold, consistently oriented surface is flagged so that normal-cone
// culling can skip it (Sec. 3.1 assumes 2-manifold meshes).
#pragma once

#include <cstdint>
#include <vector>

namespace conecull {

struct Topology {
    int32_t n_vertices = 0;
    std::vector<int32_t> faces;          // (m, 3) row-major
    std::vector<int32_t> edges;          // (E, 2), each row i < j, rows sorted lexicographically
    std::vector<int32_t> face_edges;     // (m, 3): edge id of (f0,f1), (f1,f2), (f2,f0)
    std::vector<int32_t> edge_face_offsets, edge_face_ids;      // CSR edge -> faces
    std::vector<int32_t> vertex_face_offsets, vertex_face_ids;  // CSR vertex -> faces
    std::vector<int32_t> boundary_edges;     // edge ids with exactly one face
    std::vector<uint8_t> edge_nonmanifold;   // > 2 faces, or 2 faces that traverse it the same way
    std::vector<uint8_t> vertex_nonmanifold; // incident faces are not one fan, or on a bad edge
    std::vector<uint8_t> face_touches_nonmanifold;
    std::vector<int32_t> face_component;     // connected components through shared vertices
    int32_t n_components = 0;

    int32_t n_faces() const { return static_cast<int32_t>(faces.size() / 3); }
    int32_t n_edges() const { return static_cast<int32_t>(edges.size() / 2); }
};

// faces: m rows of 3 distinct vertex ids in [0, n_vertices); validated by the caller.
Topology build_topology(const int32_t* faces, int32_t m, int32_t n_vertices);

}  // namespace conecull
