#include "conecull/collider.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "conecull/elementary/triangle_triangle.hpp"
#include "conecull/trace/null_tracer.hpp"

namespace conecull {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

Method parse_method(const std::string& name) {
    if (name == "aabb") return Method::kAabb;
    if (name == "nc") return Method::kNc;
    throw std::invalid_argument("method: unknown method '" + name + "'; expected one of 'aabb', 'nc'");
}

const char* method_name(Method m) { return m == Method::kAabb ? "aabb" : "nc"; }

SelfCollider::SelfCollider(std::shared_ptr<const Topology> topo, Method method, int32_t leaf_size)
    : topo_(std::move(topo)), method_(method), leaf_size_(leaf_size) {
    bvh_.leaf_size = leaf_size;  // reported by the debug views even before the first query
}

void SelfCollider::build(const double* V) {
    bvh_ = build_bvh(*topo_, V, leaf_size_);
    contours_ = build_contours(bvh_, *topo_);
    built_ = true;
}

template <class Tracer>
void SelfCollider::traverse_and_test(const double* V, Tracer& tracer, DcdResult& res) {
    DcdStats& st = res.stats;
    auto t0 = Clock::now();
    candidates_.clear();
    if (method_ == Method::kNc) {
        SelfCollideTraversal<true, Tracer>(bvh_, contours_, cones_, V, tracer, st, candidates_).run();
    } else {
        SelfCollideTraversal<false, Tracer>(bvh_, contours_, cones_, V, tracer, st, candidates_).run();
    }
    st.seconds_traversal = seconds_since(t0);

    t0 = Clock::now();
    const int32_t* F = topo_->faces.data();
    for (const TrianglePair& c : candidates_) {
        const int32_t* fp = F + 3 * static_cast<size_t>(c.first);
        const int32_t* fq = F + 3 * static_cast<size_t>(c.second);
        const Vec3 P[3] = {load(V, fp[0]), load(V, fp[1]), load(V, fp[2])};
        const Vec3 Q[3] = {load(V, fq[0]), load(V, fq[1]), load(V, fq[2])};
        const bool hit = triangles_collide(fp, P, fq, Q);
        if constexpr (kTraceHooks<Tracer>) tracer.on_elementary(c.first, c.second, hit);
        if (hit) res.pairs.push_back(c);
    }
    st.elementary_tests = static_cast<int64_t>(candidates_.size());
    std::sort(res.pairs.begin(), res.pairs.end());
    st.colliding_pairs = static_cast<int64_t>(res.pairs.size());
    st.seconds_elementary = seconds_since(t0);
}

DcdResult SelfCollider::dcd(const double* V, RecordingTracer* tracer) {
    DcdResult res;
    auto t0 = Clock::now();
    if (!built_) build(V);
    else refit_boxes(bvh_, *topo_, V);
    if (method_ == Method::kNc) refit_cones(bvh_, *topo_, V, cones_);
    res.stats.seconds_refit = seconds_since(t0);
    // The tracer variant is chosen once per query; the traversal itself has no branches on it.
#ifdef CONECULL_NO_TRACE_HOOKS
    tracer = nullptr;
#endif
    if (tracer) {
        tracer->reserve(bvh_);
        traverse_and_test(V, *tracer, res);
    } else {
        NullTracer null;
        traverse_and_test(V, null, res);
    }
    return res;
}

}  // namespace conecull
