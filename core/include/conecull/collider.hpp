// SelfCollider: the per-mesh state kept between queries (topology, BVH, contours) and the DCD
// query (Sec. 4.1's three stages: update BVs and normal cones; traverse with normal cone
// culling; elementary tests).
#pragma once

#include <atomic>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "conecull/bvh/bvh.hpp"
#include "conecull/ccd/elementary_ccd.hpp"
#include "conecull/contour/contour.hpp"
#include "conecull/mesh/topology.hpp"
#include "conecull/trace/recording_tracer.hpp"
#include "conecull/traversal/parallel_self_collide.hpp"
#include "conecull/traversal/self_collide.hpp"
#include "conecull/traversal/stats.hpp"

namespace conecull {

// "aabb", "nc" (Alg. 2), and with a BVTT front kept between queries: "aabb+front" (a
// conventional front, [TMLT11]) and "nc+front" (Alg. 4). All four give the same candidates as
// their method without a front, hence the same results. The baselines of Sec. 6.1 are Alg. 2
// with another contour test: "sct" (the projected star-contour test of [SPO10]; DCD only, as
// [SPO10]: Sec. 3.2 notes it is not known to extend to CCD) and "cbc" (the O(n^2) edge-pair
// test of [TCYM09]; on a DCD query, the same test at the one pose). Every contour test is
// certified, so all methods give the same results.
enum class Method { kAabb, kNc, kAabbFront, kNcFront, kSct, kCbc };
inline bool uses_cones(Method m) { return m != Method::kAabb && m != Method::kAabbFront; }
inline bool tracks_front(Method m) { return m == Method::kAabbFront || m == Method::kNcFront; }

Method parse_method(const std::string& name);  // throws std::invalid_argument
const char* method_name(Method m);

struct DcdResult {
    std::vector<TrianglePair> pairs;  // i < j, sorted lexicographically
    DcdStats stats;
};

struct CcdStats : DcdStats {
    int64_t vf_candidates = 0, ee_candidates = 0;  // unique pairs from the candidate triangle pairs
    int64_t npf_culled = 0;                        // dropped by the non-penetration filter
    int64_t vf_tests = 0, ee_tests = 0;            // elementary tests run
    int64_t vf_contacts = 0, ee_contacts = 0;
    double seconds_pairs = 0;                      // building the unique VF / EE pairs
    ExactPathCounts exact_paths;                   // arithmetic "exact": how each pair was decided
};

struct CcdResult {
    std::vector<std::pair<int32_t, int32_t>> vf;  // (vertex, face), sorted
    std::vector<std::pair<int32_t, int32_t>> ee;  // (edge a, edge b), a < b, sorted
    std::vector<double> toi;                       // if asked: per vf row then ee row, a lower bound
                                                   // on the earliest contact time
    CcdStats stats;
};

class SelfCollider {
   public:
    // threads: the queries' default thread count, <= 0 for all cores.
    SelfCollider(std::shared_ptr<const Topology> topo, Method method, int32_t leaf_size, int threads = 0);

    // V: (n_vertices, 3) float64, row-major, validated by the caller. The BVH and contours are
    // built from the first pose given. With a tracer, the query's events are appended to it.
    // threads: this query's thread count, <= 0 for the collider's default. Results and counters
    // are the same for any thread count; a traced query runs on one thread (events in order).
    // stop_at_first: the query stops at a colliding candidate ("is this pose
    // intersection-free?"): res.pairs holds it, or nothing, and stats.elementary_tests counts the
    // tests up to it (the same for any thread count). aabb and nc stop traversing there too and
    // visit the top of the BVTT in first_hit_order (parallel_self_collide.hpp); the others
    // traverse fully and stop at the first colliding candidate in traversal order.
    DcdResult dcd(const double* V, RecordingTracer* tracer = nullptr, int threads = 0, bool stop_at_first = false);

    // Continuous query over one linear step V0 -> V1 (Sec. 3.6). stop_at_first ("is this step
    // collision-free?"): each candidate's VF then EE pairs are made and tested as soon as it is
    // reached, up to the first contact: res holds it, or nothing, and the counters count the
    // pairs and tests up to it (the same for any thread count). aabb and nc stop traversing there
    // too (tasks in first_hit_order, as dcd); the others traverse fully (a front method's front
    // stays complete) and take the candidates in traversal order.
    CcdResult ccd(const double* V0, const double* V1, Arithmetic arithmetic, RecordingTracer* tracer = nullptr,
                  bool want_toi = false, int threads = 0, bool stop_at_first = false);

    // A flag that, once set, makes the running query stop and throw Interrupted (interrupt.hpp);
    // null: never. Set between queries by the caller.
    void set_interrupt(const std::atomic<bool>* flag) { interrupt_ = flag; }

    bool built() const { return built_; }
    Method method() const { return method_; }
    int threads() const { return resolve_threads(threads_); }
    const Topology& topology() const { return *topo_; }
    const Bvh& bvh() const { return bvh_; }
    const Contours& contours() const { return contours_; }
    const std::vector<NormalCone>& cones() const { return cones_; }
    // The BVTT front kept for DCD or CCD queries (front methods; empty before their first query).
    const BvttFront& front(bool continuous) const { return continuous ? ccd_front_ : dcd_front_; }

   private:
    double build(const double* V);  // the BVH and contours from pose V; returns the seconds taken
    template <class Tracer, class Motion>
    void traverse(const Motion& motion, Tracer& tracer, DcdStats& stats);
    template <class Tracer>
    void traverse_and_test(const double* V, Tracer& tracer, DcdResult& res, bool stop_at_first);
    template <class Tracer>
    void ccd_traverse_and_test(const double* V0, const double* V1, Arithmetic arithmetic, Tracer& tracer, CcdResult& res,
                               bool stop_at_first);

    std::shared_ptr<const Topology> topo_;
    Method method_;
    int32_t leaf_size_;
    int threads_;            // default, <= 0: all cores
    int query_threads_ = 1;  // the current query's, resolved
    const std::atomic<bool>* interrupt_ = nullptr;
    ParallelTraversalScratch parallel_;
    bool built_ = false;
    Bvh bvh_;
    Contours contours_;
    std::vector<NormalCone> cones_;
    // The BVTT fronts of the front methods, one per query kind (DCD, CCD): a CCD query's swept
    // boxes overlap more, so alternating queries sharing one front would keep regrowing it.
    // (Sharing would still be exact: any cut is; see bvtt_front.hpp.)
    BvttFront dcd_front_, ccd_front_;
    // "nc" / "nc+front": per node, the contour test to run first (FirstTest: the one that proved
    // the node when a query of the kind last tested it; contour_test_simple.hpp). Only the order, and so the
    // edges visited, depends on it: the culled nodes do not.
    std::vector<FirstTest> dcd_first_, ccd_first_;
    void forget(BvttFront& front, std::vector<FirstTest>& first);
    std::vector<TrianglePair> candidates_;  // reused between queries
    CandidateList candidate_list_;          // the query's candidates: candidates_ or the parallel traversal's
    std::vector<Aabb> vertex_boxes_, edge_boxes_, face_boxes_;  // CCD: swept boxes of primitives
    std::vector<uint64_t> vf_keys_, ee_keys_;
    // CCD: per face, which of its corners (bits 0-2) and edges (bits 3-5) it owns, i.e. produces
    // the VF / EE pairs of (collider.cpp, ccd_traverse_and_test).
    std::vector<uint8_t> face_owns_;
    ProjectionScratch projection_;                     // "sct": projected contour coordinates
};

}  // namespace conecull
