#include "conecull/contour/contour.hpp"

#include <algorithm>
#include <numeric>

namespace conecull {

namespace {

struct HalfEdge {
    int32_t from, to, tri;
    int64_t key() const {
        const int64_t lo = std::min(from, to), hi = std::max(from, to);
        return (hi << 32) | lo;
    }
};

struct UnionFind {
    std::vector<int32_t> parent;
    explicit UnionFind(int32_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    int32_t find(int32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    bool unite(int32_t a, int32_t b) {
        a = find(a);
        b = find(b);
        if (a == b) return false;
        parent[std::max(a, b)] = std::min(a, b);
        return true;
    }
};

bool by_key(const HalfEdge& p, const HalfEdge& q) { return p.key() < q.key(); }

// Cancels opposite half-edge pairs (interior edges) of `hes`, sorted by key; returns false when
// an edge is used twice in the same direction or more than twice. `unions` counts patches
// joined. What is left stays sorted by key, so a parent merges its children's boundaries
// instead of sorting them (the build was 40% sorts before).
bool cancel_interior(std::vector<HalfEdge>& hes, UnionFind& uf, int32_t& unions) {
    size_t out = 0;
    for (size_t s = 0; s < hes.size();) {
        size_t e = s + 1;
        while (e < hes.size() && hes[e].key() == hes[s].key()) ++e;
        if (e - s == 1) {
            hes[out++] = hes[s];
        } else if (e - s == 2 && hes[s].from == hes[s + 1].to) {
            unions += uf.unite(hes[s].tri, hes[s + 1].tri);
        } else {
            return false;
        }
        s = e;
    }
    hes.resize(out);
    return true;
}

// Orders a boundary (a union of cycles) into one loop starting at its smallest vertex id, or says
// why it is not one simple cycle. next_of / stamp_of: one slot per mesh vertex, stamp_of never
// equal to `stamp` on entry (the node's id), so no clearing between nodes.
ContourStatus order_loop(const std::vector<HalfEdge>& boundary, int32_t stamp, std::vector<int32_t>& next_of,
                         std::vector<int32_t>& stamp_of, std::vector<int32_t>& loop) {
    if (boundary.empty()) return ContourStatus::kNoBoundary;
    int32_t start = boundary[0].from;
    for (const HalfEdge& h : boundary) {
        if (stamp_of[h.from] == stamp) return ContourStatus::kNonSimpleLoop;  // two edges leave h.from
        stamp_of[h.from] = stamp;
        next_of[h.from] = h.to;
        start = std::min(start, h.from);
    }
    loop.clear();
    int32_t v = start;
    for (size_t steps = 0; steps < boundary.size(); ++steps) {
        loop.push_back(v);
        // A chain boundary has in-degree == out-degree everywhere, so this always finds one.
        if (stamp_of[v] != stamp) return ContourStatus::kMultipleLoops;
        v = next_of[v];
        if (v == loop.front()) break;
    }
    if (loop.size() != boundary.size()) return ContourStatus::kMultipleLoops;
    return ContourStatus::kSimpleLoop;
}

}  // namespace

Contours build_contours(const Bvh& bvh, const Topology& topo) {
    const int32_t n = bvh.size();
    Contours c;
    c.status.assign(n, 0);
    c.components.assign(n, 0);
    // Boundaries wait on a stack until the parent consumes them: in reverse pre-order a node's
    // right subtree is done, then its left, then the node, so its children's boundaries are the
    // top two segments (the left child's on top). No per-node allocation.
    std::vector<HalfEdge> stack, hes;
    std::vector<size_t> segment;  // where each waiting boundary starts on the stack
    std::vector<int32_t> flat, loop_at(n, 0), loop_size(n, 0);  // the loops, in the order found
    UnionFind uf(topo.n_faces());
    std::vector<int32_t> loop, next_of(topo.n_vertices), stamp_of(topo.n_vertices, -1);
    for (int32_t i = n - 1; i >= 0; --i) {
        const BvhNode& node = bvh[i];
        hes.clear();
        ContourStatus status = ContourStatus::kSimpleLoop;
        int32_t components = 0, unions = 0;
        if (node.is_leaf()) {
            for (int32_t k = node.begin; k < node.end; ++k) {
                const int32_t f = bvh.order[k];
                if (topo.face_touches_nonmanifold[f]) status = ContourStatus::kNonManifold;
                const int32_t* t = &topo.faces[3 * static_cast<size_t>(f)];
                for (int j = 0; j < 3; ++j) hes.push_back({t[j], t[(j + 1) % 3], f});
            }
            std::sort(hes.begin(), hes.end(), by_key);
            components = node.end - node.begin;
        } else {
            const int32_t l = Bvh::left(i), r = node.right;
            const size_t left_begin = segment.back();
            segment.pop_back();
            const size_t right_begin = segment.back();
            segment.pop_back();
            // A child that is non-manifold or inconsistent makes every ancestor so too.
            const auto poisoned = [&](ContourStatus s) {
                return c.status[l] == static_cast<uint8_t>(s) || c.status[r] == static_cast<uint8_t>(s);
            };
            if (poisoned(ContourStatus::kNonManifold)) {
                status = ContourStatus::kNonManifold;
            } else if (poisoned(ContourStatus::kInconsistentEdge)) {
                status = ContourStatus::kInconsistentEdge;
            } else {
                // Both children's boundaries are sorted by key (cancel_interior keeps them so).
                hes.resize(stack.size() - right_begin);
                std::merge(stack.begin() + left_begin, stack.end(), stack.begin() + right_begin,
                           stack.begin() + left_begin, hes.begin(), by_key);
                components = c.components[l] + c.components[r];
            }
            stack.resize(right_begin);
        }
        if (status == ContourStatus::kSimpleLoop) {
            if (!cancel_interior(hes, uf, unions)) {
                status = ContourStatus::kInconsistentEdge;
            } else {
                components -= unions;
                c.components[i] = components;
                if (components != 1) {
                    status = ContourStatus::kDisconnected;
                } else {
                    status = order_loop(hes, i, next_of, stamp_of, loop);
                    if (status == ContourStatus::kSimpleLoop) {
                        loop_at[i] = static_cast<int32_t>(flat.size());
                        loop_size[i] = static_cast<int32_t>(loop.size());
                        flat.insert(flat.end(), loop.begin(), loop.end());
                    }
                }
            }
        }
        // Keep the boundary for the parent even when this node is not eligible for other reasons
        // (disconnected, holes): the parent may still be a disk.
        segment.push_back(stack.size());
        if (status != ContourStatus::kNonManifold && status != ContourStatus::kInconsistentEdge)
            stack.insert(stack.end(), hes.begin(), hes.end());
        c.status[i] = static_cast<uint8_t>(status);
    }
    c.offsets.assign(static_cast<size_t>(n) + 1, 0);
    for (int32_t i = 0; i < n; ++i) c.offsets[i + 1] = c.offsets[i] + loop_size[i];
    c.vertices.resize(c.offsets[n]);
    for (int32_t i = 0; i < n; ++i)
        std::copy_n(flat.begin() + loop_at[i], loop_size[i], c.vertices.begin() + c.offsets[i]);
    return c;
}

}  // namespace conecull
