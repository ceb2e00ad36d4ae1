#include "conecull/bvh/bvh.hpp"

#include "conecull/ccd/ccd_cone.hpp"
#include "conecull/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <utility>

namespace conecull {

namespace {

inline Aabb box_of(const Vec3& a, const Vec3& b, const Vec3& c) {
    return {{std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}), std::min({a.z, b.z, c.z})},
            {std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y}), std::max({a.z, b.z, c.z})}};
}

Aabb triangle_box(const Topology& topo, const double* V, int32_t f) {
    const int32_t* t = &topo.faces[3 * static_cast<size_t>(f)];
    return box_of(load(V, t[0]), load(V, t[1]), load(V, t[2]));
}

Aabb unite(const Aabb& p, const Aabb& q) {
    return {{std::min(p.lo.x, q.lo.x), std::min(p.lo.y, q.lo.y), std::min(p.lo.z, q.lo.z)},
            {std::max(p.hi.x, q.hi.x), std::max(p.hi.y, q.hi.y), std::max(p.hi.z, q.hi.z)}};
}

// A binary merge tree over triangles (ids 0..m-1) and clusters (ids >= m), laid out later.
struct MergeTree {
    std::vector<int32_t> left, right;  // -1 for triangles
    int32_t add(int32_t l, int32_t r) {
        left.push_back(l);
        right.push_back(r);
        return static_cast<int32_t>(left.size()) - 1;
    }
};

// Joins clusters that share no edge (separate components) top-down by their centroids.
int32_t median_join(std::vector<int32_t>& ids, int32_t begin, int32_t end, const std::vector<Vec3>& center,
                    MergeTree& tree) {
    if (end - begin == 1) return ids[begin];
    Vec3 lo = center[ids[begin]], hi = lo;
    for (int32_t i = begin + 1; i < end; ++i) {
        const Vec3& c = center[ids[i]];
        lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
        hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
    }
    const Vec3 ext = hi - lo;
    const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    const int32_t mid = begin + (end - begin) / 2;
    std::nth_element(ids.begin() + begin, ids.begin() + mid, ids.begin() + end, [&](int32_t p, int32_t q) {
        const double cp = center[p][axis], cq = center[q][axis];
        return cp < cq || (cp == cq && p < q);  // ties by id: independent of the library
    });
    const int32_t l = median_join(ids, begin, mid, center, tree);
    const int32_t r = median_join(ids, mid, end, center, tree);
    return tree.add(l, r);
}

// Stable LSD radix sort of v by key(x) (a uint64_t below 2^bits), 11 bits per pass; a pass whose
// digit is the same for every element is skipped. The clustering's two sorts per level took 40%
// of a build as std::sort; stable on input already in the old comparators' tie-break order, this
// gives the same order in a few linear passes.
template <class T, class Key>
void radix_sort(std::vector<T>& v, std::vector<T>& tmp, const Key& key, int bits = 64) {
    constexpr int kBits = 11;
    constexpr size_t kBuckets = size_t(1) << kBits, kMask = kBuckets - 1;
    const int passes = (bits + kBits - 1) / kBits;
    std::vector<size_t> count(passes * kBuckets, 0);  // every pass's histogram, from one read
    for (const T& x : v) {
        const uint64_t k = key(x);
        for (int p = 0; p < passes; ++p) ++count[p * kBuckets + ((k >> (p * kBits)) & kMask)];
    }
    tmp.resize(v.size());
    for (int p = 0; p < passes && !v.empty(); ++p) {
        size_t* c = &count[p * kBuckets];
        const int shift = p * kBits;
        if (c[(key(v[0]) >> shift) & kMask] == v.size()) continue;
        size_t sum = 0;
        for (size_t d = 0; d < kBuckets; ++d) sum += std::exchange(c[d], sum);
        for (const T& x : v) tmp[c[(key(x) >> shift) & kMask]++] = x;
        v.swap(tmp);
    }
}

// A double's bits as an unsigned key in the order of its value (-0 below +0; no NaN here).
inline uint64_t ordered_bits(double x) {
    uint64_t u;
    std::memcpy(&u, &x, sizeof u);
    return (u >> 63) ? ~u : u | (uint64_t(1) << 63);
}

// Bottom-up clustering that follows the mesh: at every level each cluster is paired with an
// edge-adjacent one, most compact merge first (smallest perimeter^2 / area, with a penalty for
// unequal sizes). Nodes are then connected patches with short, smooth boundaries, which is
// what the normal cone and contour tests need: a top-down median split cuts quads apart and
// leaves saw-tooth boundaries that are not star-shaped from their mean (measured: 32% of the
// internal nodes of a gently bent sheet passed, against > 90% here).
int32_t cluster_bottom_up(const Topology& topo, const double* V, MergeTree& tree, std::vector<Vec3>& center) {
    const int32_t m = topo.n_faces();
    std::vector<double> area(m), perimeter(m, 0.0), size(m, 1.0);
    center.resize(m);
    for (auto* v : {&area, &perimeter, &size}) v->reserve(2 * static_cast<size_t>(m));  // a node per merge
    center.reserve(2 * static_cast<size_t>(m));
    for (int32_t f = 0; f < m; ++f) {
        const int32_t* t = &topo.faces[3 * static_cast<size_t>(f)];
        const Vec3 a = load(V, t[0]), b = load(V, t[1]), c = load(V, t[2]);
        area[f] = 0.5 * norm(cross(b - a, c - a));
        center[f] = {(a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0, (a.z + b.z + c.z) / 3.0};
    }
    struct Cut {
        int32_t fa, fb;
        double length;
    };
    std::vector<Cut> cuts;
    for (int32_t e = 0; e < topo.n_edges(); ++e) {
        const double len = norm(load(V, topo.edges[2 * e + 1]) - load(V, topo.edges[2 * e]));
        const int32_t b = topo.edge_face_offsets[e], end = topo.edge_face_offsets[e + 1];
        // Faces around an edge, linked in a chain: every pair for a manifold edge, and no
        // quadratic blow-up for a fin edge with thousands of faces (adjacency only guides
        // clustering; it never affects correctness).
        for (int32_t i = b; i < end; ++i) {
            perimeter[topo.edge_face_ids[i]] += len;
            if (i + 1 < end) cuts.push_back({topo.edge_face_ids[i], topo.edge_face_ids[i + 1], len});
        }
    }
    tree.left.assign(m, -1);
    tree.right.assign(m, -1);
    tree.left.reserve(2 * static_cast<size_t>(m));
    tree.right.reserve(2 * static_cast<size_t>(m));
    std::vector<int32_t> parent(m);  // union-find over faces; each root knows its cluster
    std::iota(parent.begin(), parent.end(), 0);
    std::vector<int32_t> cluster_of_root(m);
    std::iota(cluster_of_root.begin(), cluster_of_root.end(), 0);
    auto cluster = [&](int32_t f) {
        while (parent[f] != f) f = parent[f] = parent[parent[f]];
        return cluster_of_root[f];
    };
    auto root = [&](int32_t f) {
        while (parent[f] != f) f = parent[f] = parent[parent[f]];
        return f;
    };
    std::vector<int32_t> active(m), representative(m);  // representative: a face of each cluster
    std::iota(active.begin(), active.end(), 0);
    std::iota(representative.begin(), representative.end(), 0);

    struct Candidate {
        int32_t a, b;
        double shared, score;
    };
    std::vector<Candidate> cand, cand_tmp;
    struct Keyed {
        uint64_t key;  // (a, b), a < b, cluster ids packed as a << id_bits | b
        double length;
    };
    std::vector<Keyed> keyed, keyed_tmp;
    std::vector<uint8_t> matched, seen, absorbed;
    std::vector<int32_t> next;
    while (active.size() > 1) {
        int id_bits = 1;  // enough bits for every cluster id so far
        while ((size_t(1) << id_bits) < tree.left.size()) ++id_bits;
        // Cut edges between the current clusters; an edge inside a cluster is dropped for good.
        keyed.clear();
        size_t kept = 0;
        for (const Cut& c : cuts) {
            const uint64_t a = static_cast<uint64_t>(cluster(c.fa)), b = static_cast<uint64_t>(cluster(c.fb));
            if (a == b) continue;
            cuts[kept++] = c;
            keyed.push_back({a < b ? (a << id_bits) | b : (b << id_bits) | a, c.length});
        }
        cuts.resize(kept);
        if (cuts.empty()) break;
        // Grouped by cluster pair, each pair's shared lengths summed shortest first (the order the
        // earlier full sort by (pair, length) summed them in: the tree must not depend on it).
        radix_sort(keyed, keyed_tmp, [](const Keyed& k) { return k.key; }, 2 * id_bits);
        cand.clear();
        const uint64_t low = (uint64_t(1) << id_bits) - 1;
        for (size_t s = 0; s < keyed.size();) {
            size_t e = s + 1;
            while (e < keyed.size() && keyed[e].key == keyed[s].key) ++e;
            if (e - s > 1)
                std::sort(keyed.begin() + s, keyed.begin() + e,
                          [](const Keyed& p, const Keyed& q) { return p.length < q.length; });
            double shared = 0.0;
            for (size_t k = s; k < e; ++k) shared += keyed[k].length;
            const int32_t a = static_cast<int32_t>(keyed[s].key >> id_bits);
            const int32_t b = static_cast<int32_t>(keyed[s].key & low);
            const double P = std::max(0.0, perimeter[a] + perimeter[b] - 2.0 * shared);
            const double S = std::max(area[a] + area[b], 1e-300);
            const double balance = 1.0 + 0.5 * std::fabs(std::log2(size[a] / size[b]));
            cand.push_back({a, b, shared, P * P / S * balance});
            s = e;
        }
        // Most compact first, ties by (a, b): cand is in (a, b) order and the sort is stable.
        // Scores are >= +0 and never NaN (coordinates are bounded, S > 0).
        radix_sort(cand, cand_tmp, [](const Candidate& c) { return ordered_bits(c.score); });
        const size_t n_ids = tree.left.size();
        matched.assign(n_ids, 0);
        next.clear();
        auto merge = [&](int32_t x, int32_t y, double shared) {
            const int32_t id = tree.add(x, y);
            area.push_back(area[x] + area[y]);
            perimeter.push_back(std::max(0.0, perimeter[x] + perimeter[y] - 2.0 * shared));
            size.push_back(size[x] + size[y]);
            center.push_back((size[x] / size[id]) * center[x] + (size[y] / size[id]) * center[y]);
            const int32_t rx = root(representative[x]), ry = root(representative[y]);
            parent[ry] = rx;
            cluster_of_root[rx] = id;
            representative.push_back(rx);
            return id;
        };
        // Most compact merges first (greedy matching).
        for (const Candidate& c : cand) {
            if (matched[c.a] || matched[c.b]) continue;
            matched[c.a] = matched[c.b] = 1;
            merge(c.a, c.b, c.shared);
        }
        // A cluster left without partner joins its most compact neighbour's new cluster right
        // away; left waiting, stragglers end up joining one giant cluster one by one at the top,
        // which made the tree hundreds of levels deep.
        // At most two per cluster and level, so a level adds at most three to the depth.
        absorbed.assign(n_ids, 0);
        for (const Candidate& c : cand) {
            for (const int32_t lone : {c.a, c.b}) {
                const int32_t other = lone == c.a ? c.b : c.a;
                if (matched[lone] || !matched[other] || absorbed[other] >= 2) continue;
                matched[lone] = 1;
                ++absorbed[other];
                merge(cluster(representative[other]), lone, c.shared);
            }
        }
        seen.assign(tree.left.size(), 0);
        for (int32_t a : active) {
            const int32_t now = matched[a] ? cluster(representative[a]) : a;
            if (!seen[now]) next.push_back(now);
            seen[now] = 1;
        }
        // Every level must shrink the cluster count by a quarter, which bounds the number of
        // levels by log_{4/3}(m); otherwise the rest is joined top-down by position.
        const bool stalled = 4 * next.size() > 3 * active.size();
        active.swap(next);
        if (stalled) break;
    }
    if (active.size() == 1) return active[0];
    std::sort(active.begin(), active.end());
    return median_join(active, 0, static_cast<int32_t>(active.size()), center, tree);
}

// Pre-order layout with contiguous triangle ranges; subtrees of at most leaf_size triangles
// become leaves.
struct Layout {
    const MergeTree& tree;
    const std::vector<int32_t>& count;
    Bvh& bvh;

    void collect(int32_t t) {
        if (tree.left[t] < 0) {
            bvh.order.push_back(t);
            return;
        }
        collect(tree.left[t]);
        collect(tree.right[t]);
    }
    void emit(int32_t t, int32_t depth) {
        const int32_t id = bvh.size();
        bvh.nodes.push_back({});
        bvh.nodes[id].depth = depth;
        bvh.nodes[id].begin = static_cast<int32_t>(bvh.order.size());
        if (count[t] <= bvh.leaf_size) {
            collect(t);
        } else {
            emit(tree.left[t], depth + 1);
            const int32_t right = bvh.size();
            emit(tree.right[t], depth + 1);
            bvh.nodes[id].right = right;
        }
        bvh.nodes[id].end = static_cast<int32_t>(bvh.order.size());
    }
};

}  // namespace

Bvh build_bvh(const Topology& topo, const double* V, int32_t leaf_size) {
    Bvh bvh;
    bvh.leaf_size = std::max(1, leaf_size);
    const int32_t m = topo.n_faces();
    if (m == 0) return bvh;
    MergeTree tree;
    std::vector<Vec3> center;
    const int32_t root = cluster_bottom_up(topo, V, tree, center);
    std::vector<int32_t> count(tree.left.size(), 1);
    for (size_t t = m; t < tree.left.size(); ++t) count[t] = count[tree.left[t]] + count[tree.right[t]];
    bvh.nodes.reserve(2 * static_cast<size_t>(m));
    bvh.order.reserve(m);
    Layout{tree, count, bvh}.emit(root, 0);
    refit_boxes(bvh, topo, V);
    return bvh;
}

namespace {

// Bottom-up refit shared by boxes and cones, DCD and CCD: sweep(begin, end) refits the nodes
// [begin, end), children first (a leaf from its triangles in leaf order, an inner node from its
// two children), node(i) the inner node i. Children follow their parent in pre-order, so one
// reverse sweep suffices. With threads, the subtrees below a cut near the root (each a
// contiguous range of the pre-order) are swept in parallel, then the few nodes above the cut
// (inner ones) by node: every node gets the same value from the same children, so the result
// does not depend on the thread count.
template <class Sweep, class Node>
void refit_with(const Bvh& bvh, const Sweep& sweep, const Node& node, int threads) {
    if (threads <= 1 || bvh.size() < 4096) {
        sweep(0, bvh.size());
        return;
    }
    // The cut: split every subtree of >= 64 nodes until there are enough (64 per thread: the
    // subtrees are uneven, and a late helper or a busy core only takes fewer of them).
    std::vector<std::pair<int32_t, int32_t>> cut{{0, bvh.size()}}, next;
    std::vector<int32_t> above;  // in pre-order
    while (cut.size() < 64 * static_cast<size_t>(threads)) {
        next.clear();
        bool split = false;
        for (const auto& [i, end] : cut) {
            const BvhNode& n = bvh.nodes[i];
            if (n.is_leaf() || end - i < 64) {
                next.push_back({i, end});
                continue;
            }
            above.push_back(i);
            next.push_back({Bvh::left(i), n.right});
            next.push_back({n.right, end});
            split = true;
        }
        cut.swap(next);
        if (!split) break;
    }
    parallel_chunks(static_cast<int64_t>(cut.size()), threads, [&](int64_t k, int) { sweep(cut[k].first, cut[k].second); });
    std::sort(above.begin(), above.end());
    for (auto it = above.rbegin(); it != above.rend(); ++it) node(*it);
}

// The plain sweep: node(i) refits any node i.
template <class Node>
void refit(const Bvh& bvh, const Node& node, int threads) {
    refit_with(bvh, [&](int32_t begin, int32_t end) { for (int32_t i = end - 1; i >= begin; --i) node(i); }, node, threads);
}

const int32_t* face(const Topology& topo, int32_t f) { return &topo.faces[3 * static_cast<size_t>(f)]; }

// Boxes only, written in place into the nodes (no copy, no per-query buffer); leaf_box(f) is
// triangle f's box. (With cones: refit_in_blocks, below.)
template <class LeafBox>
void refit_box_nodes(Bvh& bvh, const LeafBox& leaf_box, int threads) {
    BvhNode* nodes = bvh.nodes.data();
    const int32_t* order = bvh.order.data();
    refit(bvh, [&](int32_t i) {
        BvhNode& n = nodes[i];
        if (n.is_leaf()) {
            n.box = leaf_box(order[n.begin]);
            for (int32_t k = n.begin + 1; k < n.end; ++k) n.box = unite(n.box, leaf_box(order[k]));
        } else {
            n.box = unite(nodes[Bvh::left(i)].box, nodes[n.right].box);
        }
    }, threads);
}

}  // namespace

void refit_boxes(Bvh& bvh, const Topology& topo, const double* V, int threads) {
    refit_box_nodes(bvh, [&](int32_t f) { return triangle_box(topo, V, f); }, threads);
}

namespace {

// The triangles of the leaves among a block of nodes [lo, hi) of a refit with cones, computed
// together before the block's nodes: boxes, then the cones batched (cones_around). In pre-order
// the leaves' triangle ranges follow each other, so a block's are the range [k0, k1) of
// Bvh::order. One per thread.
struct LeafTriangles {
    int32_t k0 = 0;
    std::vector<Aabb> box;
    std::vector<double> x, y, z, err;   // rounded normals (CCD: control vectors, three per triangle)
    std::vector<NormalCone> cone, control;

    // The block's triangle count; k0 set, the buffers large enough.
    size_t range(const Bvh& bvh, int32_t lo, int32_t hi) {
        // Node lo's range starts at the first leaf from lo on, node hi's at the first from hi on.
        k0 = bvh.nodes[lo].begin;
        const int32_t k1 = hi < bvh.size() ? bvh.nodes[hi].begin : static_cast<int32_t>(bvh.order.size());
        const size_t m = static_cast<size_t>(k1 - k0);
        if (box.size() < m) {
            box.resize(m), cone.resize(m), control.resize(3 * m);
            x.resize(3 * m), y.resize(3 * m), z.resize(3 * m), err.resize(3 * m);
        }
        return m;
    }
    void put(size_t j, const Vec3& n) { x[j] = n.x, y[j] = n.y, z[j] = n.z; }

    // DCD: each triangle's box and cone (triangle_cone).
    void compute(const Bvh& bvh, const Topology& topo, const double* V, int32_t lo, int32_t hi) {
        const size_t m = range(bvh, lo, hi);
        for (size_t j = 0; j < m; ++j) {
            const int32_t* t = face(topo, bvh.order[k0 + j]);
            const Vec3 p = load(V, t[0]), q = load(V, t[1]), r = load(V, t[2]);
            box[j] = box_of(p, q, r);
            put(j, triangle_normal(p, q, r, err[j]));
        }
        cones_around(x.data(), y.data(), z.data(), err.data(), static_cast<int32_t>(m), cone.data());
    }
    // CCD: each triangle's swept box and CCD cone (triangle_cone_ccd), each triangle's six vertices
    // loaded once for both.
    void compute(const Bvh& bvh, const Topology& topo, const double* V0, const double* V1, int32_t lo, int32_t hi) {
        const size_t m = range(bvh, lo, hi);
        for (size_t j = 0; j < m; ++j) {
            const int32_t* t = face(topo, bvh.order[k0 + j]);
            const Vec3 p0 = load(V0, t[0]), q0 = load(V0, t[1]), r0 = load(V0, t[2]);
            const Vec3 p1 = load(V1, t[0]), q1 = load(V1, t[1]), r1 = load(V1, t[2]);
            box[j] = unite(box_of(p0, q0, r0), box_of(p1, q1, r1));
            Vec3 n[3];
            control_vectors(p0, q0, r0, p1, q1, r1, n, &err[3 * j]);
            put(3 * j, n[0]), put(3 * j + 1, n[1]), put(3 * j + 2, n[2]);
        }
        cones_around(x.data(), y.data(), z.data(), err.data(), static_cast<int32_t>(3 * m), control.data());
        for (size_t j = 0; j < m; ++j) cone[j] = ccd_cone_of(&control[3 * j]);
    }
};

// This thread's (each refit sweep runs on one thread). Not inlined: inlined, GCC recomputed the
// TLS address (a __tls_get_addr call) at each leaf instead of keeping it (~1% of the refit).
[[gnu::noinline]] LeafTriangles& thread_leaf_triangles() {
    static thread_local LeafTriangles t;
    return t;
}

inline constexpr int32_t kRefitBlock = 64;  // nodes per block of a refit with cones

// A refit with cones in blocks of kRefitBlock nodes from the end: compute(leaves, lo, hi) the
// block's leaf triangles first, then its nodes. A leaf's box and cone are built in place, from its
// triangles' in leaf order (a copy from the stack was compiled to 16-byte loads of bytes just
// stored 8 at a time, a store-forwarding stall: 7.5% of the refit's samples in a perf profile).
template <class Compute>
void refit_in_blocks(Bvh& bvh, std::vector<NormalCone>& cones, const Compute& compute, int threads) {
    cones.resize(bvh.nodes.size());
    BvhNode* nodes = bvh.nodes.data();
    NormalCone* cone = cones.data();
    const auto inner = [&](int32_t i) {
        BvhNode& n = nodes[i];
        n.box = unite(nodes[Bvh::left(i)].box, nodes[n.right].box);
        cone[i] = merge(cone[Bvh::left(i)], cone[n.right]);
    };
    const auto sweep = [&](int32_t begin, int32_t end) {
        LeafTriangles& leaves = thread_leaf_triangles();  // once per sweep: a TLS lookup
        for (int32_t hi = end; hi > begin;) {
            const int32_t lo = std::max(begin, hi - kRefitBlock);
            compute(leaves, lo, hi);
            for (int32_t i = hi - 1; i >= lo; --i) {
                BvhNode& n = nodes[i];
                if (!n.is_leaf()) {
                    inner(i);
                    continue;
                }
                const int32_t j = n.begin - leaves.k0;
                n.box = leaves.box[j];
                NormalCone& c = cone[i];
                c = leaves.cone[j];
                for (int32_t k = j + 1; k < n.end - leaves.k0; ++k) {
                    n.box = unite(n.box, leaves.box[k]);
                    c = merge(c, leaves.cone[k]);
                }
            }
            hi = lo;
        }
    };
    refit_with(bvh, sweep, inner, threads);
}

}  // namespace

void refit_boxes_and_cones(Bvh& bvh, const Topology& topo, const double* V, std::vector<NormalCone>& cones,
                           int threads) {
    refit_in_blocks(bvh, cones, [&](LeafTriangles& t, int32_t lo, int32_t hi) { t.compute(bvh, topo, V, lo, hi); },
                    threads);
}

void refit_boxes_ccd(Bvh& bvh, const Topology& topo, const double* V0, const double* V1, int threads) {
    refit_box_nodes(bvh, [&](int32_t f) { return unite(triangle_box(topo, V0, f), triangle_box(topo, V1, f)); }, threads);
}

void refit_boxes_and_cones_ccd(Bvh& bvh, const Topology& topo, const double* V0, const double* V1,
                               std::vector<NormalCone>& cones, int threads) {
    refit_in_blocks(
        bvh, cones, [&](LeafTriangles& t, int32_t lo, int32_t hi) { t.compute(bvh, topo, V0, V1, lo, hi); }, threads);
}

}  // namespace conecull
