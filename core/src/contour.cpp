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

// Cancels opposite half-edge pairs (interior edges); returns false when an edge is used
// twice in the same direction or more than twice. `unions` counts patches joined.
bool cancel_interior(std::vector<HalfEdge>& hes, UnionFind& uf, int32_t& unions) {
    std::sort(hes.begin(), hes.end(), [](const HalfEdge& p, const HalfEdge& q) { return p.key() < q.key(); });
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

// Orders a boundary (a union of cycles) into one loop, or says why it is not one simple cycle.
ContourStatus order_loop(const std::vector<HalfEdge>& boundary, std::vector<int32_t>& loop) {
    if (boundary.empty()) return ContourStatus::kNoBoundary;
    std::vector<HalfEdge> by_from = boundary;
    std::sort(by_from.begin(), by_from.end(), [](const HalfEdge& p, const HalfEdge& q) { return p.from < q.from; });
    for (size_t i = 1; i < by_from.size(); ++i)
        if (by_from[i].from == by_from[i - 1].from) return ContourStatus::kNonSimpleLoop;
    loop.clear();
    int32_t v = by_from[0].from;
    for (size_t steps = 0; steps < by_from.size(); ++steps) {
        loop.push_back(v);
        const auto it = std::lower_bound(by_from.begin(), by_from.end(), v,
                                         [](const HalfEdge& h, int32_t x) { return h.from < x; });
        // A chain boundary has in-degree == out-degree everywhere, so this always finds one.
        if (it == by_from.end() || it->from != v) return ContourStatus::kMultipleLoops;
        v = it->to;
        if (v == loop.front()) break;
    }
    if (loop.size() != by_from.size()) return ContourStatus::kMultipleLoops;
    return ContourStatus::kSimpleLoop;
}

}  // namespace

Contours build_contours(const Bvh& bvh, const Topology& topo) {
    const int32_t n = bvh.size();
    Contours c;
    c.status.assign(n, 0);
    c.components.assign(n, 0);
    std::vector<std::vector<int32_t>> loops(n);
    std::vector<std::vector<HalfEdge>> boundary(n);  // live only until the parent consumes it
    UnionFind uf(topo.n_faces());
    std::vector<int32_t> loop;
    for (int32_t i = n - 1; i >= 0; --i) {
        const BvhNode& node = bvh[i];
        std::vector<HalfEdge> hes;
        ContourStatus status = ContourStatus::kSimpleLoop;
        int32_t components = 0, unions = 0;
        if (node.is_leaf()) {
            for (int32_t k = node.begin; k < node.end; ++k) {
                const int32_t f = bvh.order[k];
                if (topo.face_touches_nonmanifold[f]) status = ContourStatus::kNonManifold;
                const int32_t* t = &topo.faces[3 * static_cast<size_t>(f)];
                for (int j = 0; j < 3; ++j) hes.push_back({t[j], t[(j + 1) % 3], f});
            }
            components = node.end - node.begin;
        } else {
            const int32_t l = Bvh::left(i), r = node.right;
            // A child that is non-manifold or inconsistent makes every ancestor so too.
            const auto poisoned = [&](ContourStatus s) {
                return c.status[l] == static_cast<uint8_t>(s) || c.status[r] == static_cast<uint8_t>(s);
            };
            if (poisoned(ContourStatus::kNonManifold)) {
                status = ContourStatus::kNonManifold;
            } else if (poisoned(ContourStatus::kInconsistentEdge)) {
                status = ContourStatus::kInconsistentEdge;
            } else {
                hes = std::move(boundary[l]);
                hes.insert(hes.end(), boundary[r].begin(), boundary[r].end());
                components = c.components[l] + c.components[r];
            }
            std::vector<HalfEdge>().swap(boundary[l]);
            std::vector<HalfEdge>().swap(boundary[r]);
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
                    status = order_loop(hes, loop);
                    if (status == ContourStatus::kSimpleLoop) loops[i] = loop;
                }
            }
        }
        // Keep the boundary for the parent even when this node is not eligible for other reasons
        // (disconnected, holes): the parent may still be a disk.
        if (status != ContourStatus::kNonManifold && status != ContourStatus::kInconsistentEdge) boundary[i] = std::move(hes);
        c.status[i] = static_cast<uint8_t>(status);
    }
    c.offsets.assign(static_cast<size_t>(n) + 1, 0);
    for (int32_t i = 0; i < n; ++i) c.offsets[i + 1] = c.offsets[i] + static_cast<int32_t>(loops[i].size());
    c.vertices.reserve(c.offsets[n]);
    for (int32_t i = 0; i < n; ++i) c.vertices.insert(c.vertices.end(), loops[i].begin(), loops[i].end());
    return c;
}

}  // namespace conecull
