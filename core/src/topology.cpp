#include "conecull/mesh/topology.hpp"

#include <algorithm>
#include <numeric>

namespace conecull {

namespace {

struct UnionFind {
    std::vector<int32_t> parent;
    explicit UnionFind(int32_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    int32_t find(int32_t x) {
        while (parent[x] != x) {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        return x;
    }
    bool unite(int32_t a, int32_t b) {
        a = find(a);
        b = find(b);
        if (a == b) return false;
        if (a < b) std::swap(a, b);
        parent[a] = b;
        return true;
    }
};

}  // namespace

Topology build_topology(const int32_t* faces, int32_t m, int32_t n_vertices) {
    Topology t;
    t.n_vertices = n_vertices;
    t.faces.assign(faces, faces + 3 * static_cast<size_t>(m));

    // Unique undirected edges, sorted by (i, j): sort the 3m face corners' edges.
    struct HalfEdge {
        int32_t lo, hi, face, corner;
    };
    // Bucketed by lo (a counting sort), then each bucket, a vertex's few edges, sorted by
    // (hi, face): the order of one full sort by (lo, hi, face), in about half its time.
    const auto lo_of = [&](int32_t f, int k) { return std::min(faces[3 * f + k], faces[3 * f + (k + 1) % 3]); };
    std::vector<int32_t> start(static_cast<size_t>(n_vertices) + 1, 0);
    for (int32_t f = 0; f < m; ++f)
        for (int k = 0; k < 3; ++k) ++start[lo_of(f, k) + 1];
    for (int32_t v = 0; v < n_vertices; ++v) start[v + 1] += start[v];
    std::vector<HalfEdge> he(3 * static_cast<size_t>(m));
    {
        std::vector<int32_t> cursor(start.begin(), start.end() - 1);
        for (int32_t f = 0; f < m; ++f) {
            for (int k = 0; k < 3; ++k) {
                const int32_t a = faces[3 * f + k], b = faces[3 * f + (k + 1) % 3];
                he[cursor[std::min(a, b)]++] = {std::min(a, b), std::max(a, b), f, k};
            }
        }
    }
    for (int32_t v = 0; v < n_vertices; ++v)
        std::sort(he.begin() + start[v], he.begin() + start[v + 1], [](const HalfEdge& p, const HalfEdge& q) {
            return p.hi != q.hi ? p.hi < q.hi : p.face < q.face;
        });
    t.face_edges.assign(3 * static_cast<size_t>(m), -1);
    t.edge_face_offsets.push_back(0);
    for (size_t s = 0; s < he.size();) {
        size_t e = s;
        while (e < he.size() && he[e].lo == he[s].lo && he[e].hi == he[s].hi) ++e;
        const int32_t id = t.n_edges();
        t.edges.push_back(he[s].lo);
        t.edges.push_back(he[s].hi);
        int forward = 0;
        for (size_t k = s; k < e; ++k) {
            t.face_edges[3 * he[k].face + he[k].corner] = id;
            t.edge_face_ids.push_back(he[k].face);
            forward += faces[3 * he[k].face + he[k].corner] == he[k].lo;
        }
        t.edge_face_offsets.push_back(static_cast<int32_t>(t.edge_face_ids.size()));
        const size_t count = e - s;
        if (count == 1) t.boundary_edges.push_back(id);
        // Two faces must traverse a shared edge in opposite directions (consistent orientation).
        t.edge_nonmanifold.push_back(count > 2 || (count == 2 && forward != 1));
        s = e;
    }

    // vertex -> faces (CSR)
    t.vertex_face_offsets.assign(static_cast<size_t>(n_vertices) + 1, 0);
    for (size_t i = 0; i < t.faces.size(); ++i) ++t.vertex_face_offsets[t.faces[i] + 1];
    for (int32_t v = 0; v < n_vertices; ++v) t.vertex_face_offsets[v + 1] += t.vertex_face_offsets[v];
    t.vertex_face_ids.resize(t.faces.size());
    {
        std::vector<int32_t> cursor(t.vertex_face_offsets.begin(), t.vertex_face_offsets.end() - 1);
        for (int32_t f = 0; f < m; ++f)
            for (int k = 0; k < 3; ++k) t.vertex_face_ids[cursor[faces[3 * f + k]]++] = f;
    }

    // A vertex is manifold when its faces form one fan: connected through the manifold edges
    // incident to it, and none of its edges is non-manifold.
    t.vertex_nonmanifold.assign(n_vertices, 0);
    for (int32_t e = 0; e < t.n_edges(); ++e) {
        if (t.edge_nonmanifold[e]) {
            t.vertex_nonmanifold[t.edges[2 * e]] = 1;
            t.vertex_nonmanifold[t.edges[2 * e + 1]] = 1;
        }
    }
    {
        // Faces around v form one fan iff they are connected through the manifold edges (v, w)
        // incident to v: a small union-find per vertex.
        std::vector<int32_t> local;
        for (int32_t v = 0; v < n_vertices; ++v) {
            if (t.vertex_nonmanifold[v]) continue;
            const int32_t b = t.vertex_face_offsets[v], e = t.vertex_face_offsets[v + 1];
            if (e - b <= 1) continue;
            local.assign(t.vertex_face_ids.begin() + b, t.vertex_face_ids.begin() + e);
            UnionFind luf(e - b);
            int32_t classes = e - b;
            for (int32_t i = 0; i < e - b; ++i) {
                const int32_t f = local[i];
                for (int k = 0; k < 3; ++k) {
                    const int32_t a = faces[3 * f + k], c = faces[3 * f + (k + 1) % 3];
                    if (a != v && c != v) continue;
                    const int32_t eid = t.face_edges[3 * f + k];
                    const int32_t eb = t.edge_face_offsets[eid];
                    if (t.edge_face_offsets[eid + 1] - eb != 2) continue;
                    const int32_t g = t.edge_face_ids[eb] == f ? t.edge_face_ids[eb + 1] : t.edge_face_ids[eb];
                    // vertex_face_ids lists each vertex's faces in increasing order
                    const int32_t j = static_cast<int32_t>(std::lower_bound(local.begin(), local.end(), g) - local.begin());
                    if (luf.unite(i, j)) --classes;
                }
            }
            if (classes != 1) t.vertex_nonmanifold[v] = 1;
        }
    }
    t.face_touches_nonmanifold.assign(m, 0);
    for (int32_t f = 0; f < m; ++f) {
        for (int k = 0; k < 3; ++k) {
            if (t.vertex_nonmanifold[faces[3 * f + k]] || t.edge_nonmanifold[t.face_edges[3 * f + k]])
                t.face_touches_nonmanifold[f] = 1;
        }
    }

    // Components through shared vertices.
    UnionFind uf(m);
    for (int32_t v = 0; v < n_vertices; ++v) {
        const int32_t b = t.vertex_face_offsets[v], e = t.vertex_face_offsets[v + 1];
        for (int32_t k = b + 1; k < e; ++k) uf.unite(t.vertex_face_ids[b], t.vertex_face_ids[k]);
    }
    t.face_component.assign(m, -1);
    std::vector<int32_t> label(m, -1);
    for (int32_t f = 0; f < m; ++f) {
        const int32_t r = uf.find(f);
        if (label[r] < 0) label[r] = t.n_components++;
        t.face_component[f] = label[r];
    }
    return t;
}

}  // namespace conecull
