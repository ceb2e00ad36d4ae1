#include "conecull/bvh/bvh.hpp"

#include <algorithm>
#include <cmath>

namespace conecull {

namespace {

Aabb triangle_box(const Topology& topo, const double* V, int32_t f) {
    const int32_t* t = &topo.faces[3 * static_cast<size_t>(f)];
    const Vec3 a = load(V, t[0]), b = load(V, t[1]), c = load(V, t[2]);
    return {{std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}), std::min({a.z, b.z, c.z})},
            {std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y}), std::max({a.z, b.z, c.z})}};
}

Aabb unite(const Aabb& p, const Aabb& q) {
    return {{std::min(p.lo.x, q.lo.x), std::min(p.lo.y, q.lo.y), std::min(p.lo.z, q.lo.z)},
            {std::max(p.hi.x, q.hi.x), std::max(p.hi.y, q.hi.y), std::max(p.hi.z, q.hi.z)}};
}

struct Builder {
    const std::vector<Vec3>& centroid;
    Bvh& bvh;

    void build(int32_t begin, int32_t end, int32_t depth) {
        const int32_t id = bvh.size();
        bvh.nodes.push_back({});
        bvh.nodes[id].begin = begin;
        bvh.nodes[id].end = end;
        bvh.nodes[id].depth = depth;
        if (end - begin <= bvh.leaf_size) return;
        Vec3 lo = centroid[bvh.order[begin]], hi = lo;
        for (int32_t i = begin + 1; i < end; ++i) {
            const Vec3& c = centroid[bvh.order[i]];
            lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
            hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
        }
        const Vec3 ext = hi - lo;
        const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
        const int32_t mid = begin + (end - begin) / 2;
        // Ties broken by triangle id so the tree does not depend on the sort implementation.
        std::nth_element(bvh.order.begin() + begin, bvh.order.begin() + mid, bvh.order.begin() + end,
                         [&](int32_t p, int32_t q) {
                             const double cp = centroid[p][axis], cq = centroid[q][axis];
                             return cp < cq || (cp == cq && p < q);
                         });
        build(begin, mid, depth + 1);
        const int32_t right = bvh.size();
        build(mid, end, depth + 1);
        bvh.nodes[id].right = right;
    }
};

}  // namespace

Bvh build_bvh(const Topology& topo, const double* V, int32_t leaf_size) {
    Bvh bvh;
    bvh.leaf_size = std::max(1, leaf_size);
    const int32_t m = topo.n_faces();
    if (m == 0) return bvh;
    std::vector<Vec3> centroid(m);
    for (int32_t f = 0; f < m; ++f) {
        const int32_t* t = &topo.faces[3 * static_cast<size_t>(f)];
        const Vec3 a = load(V, t[0]), b = load(V, t[1]), c = load(V, t[2]);
        // NaN-free by validation; centroids only steer the split, never correctness.
        centroid[f] = {(a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0, (a.z + b.z + c.z) / 3.0};
    }
    bvh.order.resize(m);
    for (int32_t f = 0; f < m; ++f) bvh.order[f] = f;
    bvh.nodes.reserve(2 * static_cast<size_t>(m));
    Builder{centroid, bvh}.build(0, m, 0);
    refit_boxes(bvh, topo, V);
    return bvh;
}

void refit_boxes(Bvh& bvh, const Topology& topo, const double* V) {
    for (int32_t i = bvh.size() - 1; i >= 0; --i) {
        BvhNode& n = bvh.nodes[i];
        if (n.is_leaf()) {
            n.box = triangle_box(topo, V, bvh.order[n.begin]);
            for (int32_t k = n.begin + 1; k < n.end; ++k) n.box = unite(n.box, triangle_box(topo, V, bvh.order[k]));
        } else {
            n.box = unite(bvh.nodes[Bvh::left(i)].box, bvh.nodes[n.right].box);
        }
    }
}

void refit_cones(const Bvh& bvh, const Topology& topo, const double* V, std::vector<NormalCone>& cones) {
    cones.resize(bvh.nodes.size());
    for (int32_t i = bvh.size() - 1; i >= 0; --i) {
        const BvhNode& n = bvh.nodes[i];
        if (n.is_leaf()) {
            NormalCone c;
            for (int32_t k = n.begin; k < n.end; ++k) {
                const int32_t* t = &topo.faces[3 * static_cast<size_t>(bvh.order[k])];
                const NormalCone tc = triangle_cone(load(V, t[0]), load(V, t[1]), load(V, t[2]));
                c = k == n.begin ? tc : merge(c, tc);
            }
            cones[i] = c;
        } else {
            cones[i] = merge(cones[Bvh::left(i)], cones[n.right]);
        }
    }
}

}  // namespace conecull
