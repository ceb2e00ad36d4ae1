#include "conecull/collider.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <type_traits>

#include "conecull/elementary/triangles_apart.hpp"
#include "conecull/interrupt.hpp"
#include "conecull/parallel.hpp"
#include "conecull/trace/null_tracer.hpp"

namespace conecull {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// What DCD's first-hit traversal keeps per task besides the hit: nothing.
struct NoTaskOut {};

// Runs `body` with the query's tracer variant, chosen once per query: the recording tracer if
// one is given (and the build has hooks), else the NullTracer whose hooks compile away.
template <class Body>
void with_tracer(RecordingTracer* tracer, const Bvh& bvh, Body body) {
#ifdef CONECULL_NO_TRACE_HOOKS
    tracer = nullptr;
#endif
    if (tracer) {
        tracer->reserve(bvh);
        body(*tracer);
    } else {
        NullTracer null;
        body(null);
    }
}

}  // namespace

Method parse_method(const std::string& name) {
    if (name == "aabb") return Method::kAabb;
    if (name == "nc") return Method::kNc;
    if (name == "aabb+front") return Method::kAabbFront;
    if (name == "nc+front") return Method::kNcFront;
    if (name == "sct") return Method::kSct;
    if (name == "cbc") return Method::kCbc;
    throw std::invalid_argument("method: unknown method '" + name +
                                "'; expected one of 'aabb', 'nc', 'aabb+front', 'nc+front', 'sct', 'cbc'");
}

const char* method_name(Method m) {
    switch (m) {
        case Method::kAabb: return "aabb";
        case Method::kNc: return "nc";
        case Method::kAabbFront: return "aabb+front";
        case Method::kNcFront: return "nc+front";
        case Method::kSct: return "sct";
        case Method::kCbc: return "cbc";
    }
    return "unknown";
}

SelfCollider::SelfCollider(std::shared_ptr<const Topology> topo, Method method, int32_t leaf_size, int threads)
    : topo_(std::move(topo)), method_(method), leaf_size_(leaf_size), threads_(threads) {
    bvh_.leaf_size = leaf_size;  // reported by the debug views even before the first query
}

double SelfCollider::build(const double* V) {
    const auto t0 = Clock::now();
    bvh_ = build_bvh(*topo_, V, leaf_size_);
    contours_ = build_contours(bvh_, *topo_);
    dcd_front_.reset();
    ccd_front_.reset();
    dcd_first_.assign(bvh_.nodes.size(), FirstTest::kStar);
    ccd_first_.assign(bvh_.nodes.size(), FirstTest::kStar);
    built_ = true;
    return seconds_since(t0);
}

// Stage (2) of Sec. 4.1 with the collider's method; candidates_ receives the triangle pairs.
template <class Tracer, class Motion>
void SelfCollider::traverse(const Motion& motion, Tracer& tracer, DcdStats& st) {
    BvttFront& front = Motion::kContinuous ? ccd_front_ : dcd_front_;
    candidates_.clear();
    candidate_list_.set(candidates_);  // unless the parallel traversal lists its own
    // aabb / nc, without or with a front (the template arguments per method).
    auto run = [&](auto cones, auto track) {
        constexpr bool kCones = decltype(cones)::value, kFront = decltype(track)::value;
        BvttFront* f = kFront ? &front : nullptr;
        if constexpr (!kTraceHooks<Tracer>) {
            // Several threads: the same candidates in the same order, and the same front
            // (parallel_self_collide.hpp). A traced query stays serial (events in order).
            if (query_threads_ > 1) {
                const auto make = [&](DcdStats& s, std::vector<TrianglePair>& out, FrontPart* part) {
                    return SelfCollideTraversal<kCones, Tracer, Motion, kFront>(bvh_, contours_, cones_, motion, tracer,
                                                                               s, out, interrupt_, f, kFront ? part : nullptr);
                };
                parallel_self_collide(bvh_, query_threads_, make, f, st, candidate_list_, parallel_);
                return;
            }
        }
        SelfCollideTraversal<kCones, Tracer, Motion, kFront>(bvh_, contours_, cones_, motion, tracer, st, candidates_,
                                                             interrupt_, f)
            .run();
    };
    switch (method_) {
        case Method::kAabb:
            run(std::false_type{}, std::false_type{});
            break;
        case Method::kNc:
            run(std::true_type{}, std::false_type{});
            break;
        case Method::kAabbFront:
            run(std::false_type{}, std::true_type{});
            break;
        case Method::kNcFront:
            run(std::true_type{}, std::true_type{});
            break;
        case Method::kSct:
            if constexpr (!Motion::kContinuous) {
                const DiscreteProjected m{motion.V, &projection_};
                SelfCollideTraversal<true, Tracer, DiscreteProjected>(bvh_, contours_, cones_, m, tracer, st,
                                                                      candidates_, interrupt_).run();
            }  // CCD: rejected by ccd()
            break;
        case Method::kCbc:
            if constexpr (Motion::kContinuous) {
                const ContinuousQuadratic m{motion.V0, motion.V1};
                SelfCollideTraversal<true, Tracer, ContinuousQuadratic>(bvh_, contours_, cones_, m, tracer, st,
                                                                        candidates_, interrupt_).run();
            } else {
                const DiscreteQuadratic m{motion.V};
                SelfCollideTraversal<true, Tracer, DiscreteQuadratic>(bvh_, contours_, cones_, m, tracer, st,
                                                                      candidates_, interrupt_).run();
            }
            break;
    }
}

template <class Tracer>
void SelfCollider::traverse_and_test(const double* V, Tracer& tracer, DcdResult& res, bool stop_at_first) {
    DcdStats& st = res.stats;
    const int32_t* F = topo_->faces.data();
    const auto collide = [&](const TrianglePair& c) {
        const bool hit = triangles_collide_rows(V, F, c);
        if constexpr (kTraceHooks<Tracer>) tracer.on_elementary(c.first, c.second, hit);
        return hit;
    };
    // Prefetch: a test's loads (two faces' ids, then their six corners) depend on each other
    // and miss the L1; fetched 16 and 8 pairs ahead, they overlap with the tests before.
    const auto ahead = [&](const TrianglePair& c, int d) {
        const int32_t* fp = F + 3 * static_cast<size_t>(c.first);
        const int32_t* fq = F + 3 * static_cast<size_t>(c.second);
        if (d == 16) {
            __builtin_prefetch(fp);
            __builtin_prefetch(fq);
            return;
        }
        for (int i = 0; i < 3; ++i) {
            __builtin_prefetch(V + 3 * static_cast<size_t>(fp[i]));
            __builtin_prefetch(V + 3 * static_cast<size_t>(fq[i]));
        }
    };
    // The candidates p[0, n) in order, four at a time: triangles_collide4's certified plane
    // rejection settles most (85-88% on the real steps; each costs a third of a full test), and
    // the signs it proved decide most others in the same lanes; what is left goes to the exact
    // test. on_hit(k) for the k-th if it collides; true stops the scan there: returns k, or n at
    // the end. A traced query gets each pair's event in order.
    const auto scan = [&](const TrianglePair* p, int64_t n, const auto& on_hit) -> int64_t {
        int64_t k = 0;
        for (; k + 4 <= n; k += 4) {
            if ((k & (kDcdInterruptStride - 1)) == 0 && interrupt_requested(interrupt_)) throw Interrupted{};
            for (int l = 0; l < 4; ++l) {
                if (k + 16 + l < n) ahead(p[k + 16 + l], 16);
                if (k + 8 + l < n) ahead(p[k + 8 + l], 8);
            }
            const uint32_t hits = triangles_collide4(V, F, p + k);
            if constexpr (kTraceHooks<Tracer>) {
                for (int l = 0; l < 4; ++l) {
                    const bool hit = hits >> l & 1;
                    tracer.on_elementary(p[k + l].first, p[k + l].second, hit);
                    if (hit && on_hit(k + l)) return k + l;
                }
            } else {
                for (uint32_t rest = hits; rest != 0; rest &= rest - 1) {  // in lane order
                    const int l = __builtin_ctz(rest);
                    if (on_hit(k + l)) return k + l;
                }
            }
        }
        for (; k < n; ++k)
            if (collide(p[k]) && on_hit(k)) return k;
        return n;
    };
    const auto stop = [](int64_t) { return true; };
    if constexpr (!kTraceHooks<Tracer>) {
        if (stop_at_first && (method_ == Method::kAabb || method_ == Method::kNc)) {
            // Without a front to keep complete, the traversal itself stops at the first hit in
            // first-hit order (parallel_self_collide.hpp). A traced query keeps the full traversal
            // (its events are those of the full query up to the hit), as do the front methods
            // (their front must stay whole) and the sct / cbc baselines (one thread, the full
            // traversal).
            const auto t0 = Clock::now();
            const auto run = [&](auto cones) {
                constexpr bool kCones = decltype(cones)::value;
                const Discrete motion{V, dcd_first_.data(), false};  // first hit: no learning (see Discrete)
                const auto make = [&](DcdStats& s, std::vector<TrianglePair>& out, FrontPart*) {
                    return SelfCollideTraversal<kCones, Tracer, Discrete, false>(bvh_, contours_, cones_, motion, tracer,
                                                                                s, out, interrupt_);
                };
                const auto find_hit = [&](const std::vector<TrianglePair>& c, NoTaskOut&) {
                    return scan(c.data(), static_cast<int64_t>(c.size()), stop);
                };
                std::vector<NoTaskOut> outs;
                return self_collide_until_first_hit(bvh_, query_threads_, make, find_hit, outs, st, parallel_);
            };
            const FirstHit hit = method_ == Method::kNc ? run(std::true_type{}) : run(std::false_type{});
            candidates_.clear();
            candidate_list_.set(candidates_);
            if (hit.found) res.pairs.push_back(hit.pair);
            st.elementary_tests = hit.tests;
            st.colliding_pairs = static_cast<int64_t>(res.pairs.size());
            st.seconds_traversal = seconds_since(t0);  // the tests run inside it
            st.seconds_elementary = 0.0;
            return;
        }
    }
    auto t0 = Clock::now();
    traverse(Discrete{V, dcd_first_.data()}, tracer, st);
    st.seconds_traversal = seconds_since(t0);

    t0 = Clock::now();
    // The candidates in chunks, each chunk's hits in its own list, concatenated in order.
    const CandidateList& candidates = candidate_list_;
    const Chunks ch(candidates.size(), query_threads_, 512);
    if (stop_at_first) {
        // The first colliding candidate in traversal order (FirstHitChunk: the answer and the
        // count of tests up to it do not depend on the threads).
        FirstHitChunk first(ch.count);
        std::vector<std::pair<int64_t, TrianglePair>> hit_of(ch.count, {-1, {}});
        parallel_chunks(ch.count, query_threads_, [&](int64_t k, int) {
            if (first.skip(k)) return;
            const int64_t i = candidates.scan_runs(ch.begin(k), ch.end(k), [&](const TrianglePair* p, int64_t n) {
                const int64_t j = scan(p, n, stop);
                if (j < n) hit_of[k].second = p[j];
                return j;
            });
            if (i == ch.end(k)) return;
            hit_of[k].first = i;
            first.found(k);
        });
        const int64_t k = first.get();
        if (k < ch.count) res.pairs.push_back(hit_of[k].second);
        st.elementary_tests = k < ch.count ? hit_of[k].first + 1 : candidates.size();
        st.colliding_pairs = static_cast<int64_t>(res.pairs.size());
        st.seconds_elementary = seconds_since(t0);
        return;
    }
    std::vector<Padded<std::vector<TrianglePair>>> hits(ch.count);
    parallel_chunks(ch.count, query_threads_, [&](int64_t k, int) {
        candidates.scan_runs(ch.begin(k), ch.end(k), [&](const TrianglePair* p, int64_t n) {
            return scan(p, n, [&](int64_t j) {
                hits[k].value.push_back(p[j]);
                return false;
            });
        });
    });
    concat_in_order(hits, hits.size(), 1, res.pairs);
    st.elementary_tests = candidates.size();
    parallel_sort(res.pairs, query_threads_, interrupt_);
    st.colliding_pairs = static_cast<int64_t>(res.pairs.size());
    st.seconds_elementary = seconds_since(t0);
}

// A query that throws (Ctrl-C, or memory running out) may stop inside the traversal, the front
// half rebuilt: the nodes reached hold sub-segments of a front never finished (with several
// threads, offsets into parts never joined), which a later query would resume (found: wrong
// pairs, or a crash). Its kind's front and learnt test order start over, as a fresh collider's;
// the next query rebuilds the front from the top, and its counters do not depend on where the
// query stopped.
void SelfCollider::forget(BvttFront& front, std::vector<FirstTest>& first) {
    front.reset();
    std::fill(first.begin(), first.end(), FirstTest::kStar);
}

DcdResult SelfCollider::dcd(const double* V, RecordingTracer* tracer, int threads, bool stop_at_first) {
    DcdResult res;
    query_threads_ = tracer ? 1 : resolve_threads(threads > 0 ? threads : threads_);
    const bool fresh = !built_;
    if (fresh) res.stats.seconds_build = build(V);  // boxes fit to V
    const auto t0 = Clock::now();
    // Boxes and cones in one sweep (bvh.cpp); refitting a fresh BVH's boxes gives them again.
    if (uses_cones(method_)) refit_boxes_and_cones(bvh_, *topo_, V, cones_, query_threads_);
    else if (!fresh) refit_boxes(bvh_, *topo_, V, query_threads_);
    res.stats.seconds_refit = seconds_since(t0);
    try {
        with_tracer(tracer, bvh_, [&](auto& t) { traverse_and_test(V, t, res, stop_at_first); });
    } catch (...) {
        forget(dcd_front_, dcd_first_);  // Ctrl-C, or memory running out, perhaps inside the traversal
        throw;
    }
    return res;
}

}  // namespace conecull

// ---- CCD ---------------------------------------------------------------------------------
#include "conecull/ccd/non_penetration.hpp"

namespace conecull {

CcdResult SelfCollider::ccd(const double* V0, const double* V1, Arithmetic arithmetic, RecordingTracer* tracer,
                            bool want_toi, int threads, bool stop_at_first) {
    // [SPO10]'s star-contour test is a DCD test; Sec. 3.2: "It is not clear whether the linear
    // time algorithm for contour test in [SPO10] extends to CCD". The CCD baseline is "cbc".
    if (method_ == Method::kSct)
        throw std::invalid_argument("method: 'sct' is a discrete (DCD) method [SPO10]; for CCD use 'nc', "
                                    "'nc+front' or the CCD baseline 'cbc'");
    CcdResult res;
    query_threads_ = tracer ? 1 : resolve_threads(threads > 0 ? threads : threads_);
    if (!built_) res.stats.seconds_build = build(V0);
    const auto t0 = Clock::now();
    if (uses_cones(method_)) refit_boxes_and_cones_ccd(bvh_, *topo_, V0, V1, cones_, query_threads_);
    else refit_boxes_ccd(bvh_, *topo_, V0, V1, query_threads_);
    res.stats.seconds_refit = seconds_since(t0);
    try {
        with_tracer(tracer, bvh_, [&](auto& t) { ccd_traverse_and_test(V0, V1, arithmetic, t, res, stop_at_first); });
    } catch (...) {
        forget(ccd_front_, ccd_first_);  // as dcd
        throw;
    }
    if (want_toi) {
        const int32_t* F = topo_->faces.data();
        const int32_t* E = topo_->edges.data();
        const int64_t n_vf = static_cast<int64_t>(res.vf.size());
        res.toi.resize(res.vf.size() + res.ee.size());
        // Each bound is a search over the step (hundreds of exact tests where the pair stays
        // close): a look at the interrupt flag before each one (a step with every pair in
        // contact ran 70 s past Ctrl-C without it).
        parallel_for(static_cast<int64_t>(res.toi.size()), query_threads_, 16, [&](int64_t i) {
            if (interrupt_requested(interrupt_)) return;
            if (i < n_vf) {
                const auto [v, f] = res.vf[i];
                const int32_t* t = F + 3 * static_cast<size_t>(f);
                res.toi[i] = vertex_face_toi_lower_bound(load(V0, v), load(V0, t[0]), load(V0, t[1]), load(V0, t[2]),
                                                         load(V1, v), load(V1, t[0]), load(V1, t[1]), load(V1, t[2]));
            } else {
                const auto [ea, eb] = res.ee[i - n_vf];
                const int32_t a = E[2 * ea], b = E[2 * ea + 1], c = E[2 * eb], d = E[2 * eb + 1];
                res.toi[i] = edge_edge_toi_lower_bound(load(V0, a), load(V0, b), load(V0, c), load(V0, d), load(V1, a),
                                                       load(V1, b), load(V1, c), load(V1, d));
            }
        });
        if (interrupt_requested(interrupt_)) throw Interrupted{};
    }
    return res;
}

namespace {

// The VF / EE tests of a run of them (a chunk of keys, a chunk of candidates or a first-hit
// task): contacts and counters, summed in order afterwards.
struct alignas(64) CcdTally {  // own cache lines: runs side by side run on different threads
    std::vector<std::pair<int32_t, int32_t>> vf, ee;
    int64_t vf_candidates = 0, ee_candidates = 0, npf_culled = 0, vf_tests = 0, ee_tests = 0;
    ExactPathCounts exact;
};

// A candidate's VF (at most 6) or EE (at most 9) keys, for the first-hit tests.
struct KeyBuffer {
    uint64_t key[9];
    int32_t size = 0;
    void push_back(uint64_t k) { key[size++] = k; }
};

}  // namespace

template <class Tracer>
void SelfCollider::ccd_traverse_and_test(const double* V0, const double* V1, Arithmetic arithmetic, Tracer& tracer,
                                         CcdResult& res, bool stop_at_first) {
    CcdStats& st = res.stats;
    const int threads = query_threads_;
    // Low-level culling (Sec. 5.1): every VF / EE pair of the candidate triangle pairs whose
    // primitives' swept boxes overlap, each once. The boxes first: a first-hit query makes the
    // pairs of a candidate as soon as the traversal finds it.
    auto t0 = Clock::now();
    const int32_t* F = topo_->faces.data();
    const int32_t* FE = topo_->face_edges.data();
    const int32_t* Ed = topo_->edges.data();
    auto swept = [&](std::initializer_list<int32_t> ids) {
        Aabb b{load(V0, *ids.begin()), load(V0, *ids.begin())};
        for (int32_t v : ids)
            for (const double* V : {V0, V1}) {
                const Vec3 x = load(V, v);
                b.lo = {std::min(b.lo.x, x.x), std::min(b.lo.y, x.y), std::min(b.lo.z, x.z)};
                b.hi = {std::max(b.hi.x, x.x), std::max(b.hi.y, x.y), std::max(b.hi.z, x.z)};
            }
        return b;
    };
    // The vertices', edges' and faces' boxes as one range: one parallel region.
    const int64_t n_v = topo_->n_vertices, n_e = topo_->n_edges(), n_f = topo_->n_faces();
    vertex_boxes_.resize(n_v);
    edge_boxes_.resize(n_e);
    face_boxes_.resize(n_f);
    parallel_for(n_v + n_e + n_f, threads, 4096, [&](int64_t i) {
        if (i < n_v) {
            vertex_boxes_[i] = swept({static_cast<int32_t>(i)});
        } else if (i < n_v + n_e) {
            const int64_t e = i - n_v;
            edge_boxes_[e] = swept({Ed[2 * e], Ed[2 * e + 1]});
        } else {
            const int64_t f = i - n_v - n_e;
            face_boxes_[f] = swept({F[3 * f], F[3 * f + 1], F[3 * f + 2]});
        }
    });
    // Each vertex and each edge is owned by one of its faces; a VF pair (v, f) is produced only
    // by the candidate pair (owner(v), f), an EE pair only by (owner(ea), owner(eb)). Every pair
    // is then produced at most once with no sorting, and none is lost: if v touches f, the
    // boxes of owner(v) and f overlap, so that pair is a candidate (or lies in a culled node,
    // which has no contact at any t).
    // Each face's share as a 6-bit mask, so that making a candidate's pairs reads two bytes
    // instead of the owners of its six corners and six edges, scattered over two arrays (with
    // those, making the pairs took longer than the elementary tests on the rod-twist step).
    if (face_owns_.size() != static_cast<size_t>(n_f)) {
        std::vector<int32_t> vertex_owner(n_v, -1);
        for (int32_t f = static_cast<int32_t>(n_f) - 1; f >= 0; --f)
            for (int k = 0; k < 3; ++k) vertex_owner[F[3 * f + k]] = f;
        face_owns_.assign(n_f, 0);
        for (int32_t f = 0; f < n_f; ++f)
            for (int k = 0; k < 3; ++k) {
                if (vertex_owner[F[3 * f + k]] == f) face_owns_[f] |= static_cast<uint8_t>(1u << k);
                const int32_t e = FE[3 * f + k];
                if (topo_->edge_face_ids[topo_->edge_face_offsets[e]] == f)
                    face_owns_[f] |= static_cast<uint8_t>(8u << k);
            }
    }
    const double seconds_boxes = seconds_since(t0);
    // A candidate's VF and EE pairs whose swept boxes overlap. A primitive's swept box lies in
    // its face's, so two faces whose swept boxes are apart have none: one test skips them (a
    // leaf pair's four triangle pairs share the leaves' overlap, not each its own). Flat box
    // tests: whether a pair overlaps is as hard to predict here as in FrontTracking's walk.
    auto pairs_of = [&](const TrianglePair& c, auto& vf_keys, auto& ee_keys) {
        const Aabb bp = face_boxes_[c.first], bq = face_boxes_[c.second];
        if (!bp.overlaps_flat(bq)) return;
        const int32_t* fp = F + 3 * static_cast<size_t>(c.first);
        const int32_t* fq = F + 3 * static_cast<size_t>(c.second);
        const uint32_t op = face_owns_[c.first], oq = face_owns_[c.second];
        auto in = [](const int32_t* f, int32_t v) { return f[0] == v || f[1] == v || f[2] == v; };
        for (int k = 0; k < 3; ++k) {
            if ((op >> k & 1u) && !in(fq, fp[k]) && vertex_boxes_[fp[k]].overlaps_flat(bq))
                vf_keys.push_back(static_cast<uint64_t>(fp[k]) << 32 | static_cast<uint32_t>(c.second));
            if ((oq >> k & 1u) && !in(fp, fq[k]) && vertex_boxes_[fq[k]].overlaps_flat(bp))
                vf_keys.push_back(static_cast<uint64_t>(fq[k]) << 32 | static_cast<uint32_t>(c.first));
        }
        if (!(op & 0x38u) || !(oq & 0x38u)) return;
        for (int i = 0; i < 3; ++i) {
            if (!(op >> (3 + i) & 1u)) continue;
            const int32_t ea = FE[3 * c.first + i];
            const int32_t a0 = fp[i], a1 = fp[(i + 1) % 3];
            const Aabb ba = edge_boxes_[ea];
            for (int j = 0; j < 3; ++j) {
                if (!(oq >> (3 + j) & 1u)) continue;
                const int32_t eb = FE[3 * c.second + j];
                const int32_t b0 = fq[j], b1 = fq[(j + 1) % 3];
                if (a0 == b0 || a0 == b1 || a1 == b0 || a1 == b1) continue;
                if (!ba.overlaps_flat(edge_boxes_[eb])) continue;
                ee_keys.push_back(static_cast<uint64_t>(std::min(ea, eb)) << 32 | static_cast<uint32_t>(std::max(ea, eb)));
            }
        }
    };
    const int32_t* E = topo_->edges.data();
    // filter = false: the pair is known to pass the non-penetration filter (test_keys).
    auto test_vf = [&](uint64_t key, CcdTally& out, bool filter = true) {
        const int32_t v = static_cast<int32_t>(key >> 32), f = static_cast<int32_t>(key & 0xffffffffu);
        const int32_t* t = F + 3 * static_cast<size_t>(f);
        if (filter && vf_never_coplanar(load(V0, v), load(V0, t[0]), load(V0, t[1]), load(V0, t[2]), load(V1, v),
                                        load(V1, t[0]), load(V1, t[1]), load(V1, t[2]))) {
            ++out.npf_culled;
            return;
        }
        ++out.vf_tests;
        const bool hit = vertex_face_ccd(load(V0, v), load(V0, t[0]), load(V0, t[1]), load(V0, t[2]), load(V1, v),
                                         load(V1, t[0]), load(V1, t[1]), load(V1, t[2]), arithmetic);
        if constexpr (kTraceHooks<Tracer>) tracer.on_vf(v, f, hit);
        if (hit) out.vf.emplace_back(v, f);
    };
    auto test_ee = [&](uint64_t key, CcdTally& out, bool filter = true) {
        const int32_t ea = static_cast<int32_t>(key >> 32), eb = static_cast<int32_t>(key & 0xffffffffu);
        const int32_t a = E[2 * ea], b = E[2 * ea + 1], c = E[2 * eb], d = E[2 * eb + 1];
        if (filter && ee_never_coplanar(load(V0, a), load(V0, b), load(V0, c), load(V0, d), load(V1, a), load(V1, b),
                                        load(V1, c), load(V1, d))) {
            ++out.npf_culled;
            return;
        }
        ++out.ee_tests;
        const bool hit = edge_edge_ccd(load(V0, a), load(V0, b), load(V0, c), load(V0, d), load(V1, a), load(V1, b),
                                       load(V1, c), load(V1, d), arithmetic);
        if constexpr (kTraceHooks<Tracer>) tracer.on_ee(ea, eb, hit);
        if (hit) out.ee.emplace_back(ea, eb);
    };
    // A run of tests into `out`; the exact-path counters are per thread: reset and read around it.
    auto run_tests = [](CcdTally& out, const auto& body) {
        exact_path_counts() = {};
        body();
        out.exact = exact_path_counts();
    };
    // The results of runs of tests, in order: contacts and counters (the first-hit query passes
    // only the runs up to the one with the contact; the full query counts its pairs itself).
    auto gather = [&](const CcdTally* outs, size_t n) {
        st.exact_paths = {};
        for (size_t k = 0; k < n; ++k) {
            const CcdTally& out = outs[k];
            res.vf.insert(res.vf.end(), out.vf.begin(), out.vf.end());
            res.ee.insert(res.ee.end(), out.ee.begin(), out.ee.end());
            st.vf_candidates += out.vf_candidates;
            st.ee_candidates += out.ee_candidates;
            st.npf_culled += out.npf_culled;
            st.vf_tests += out.vf_tests;
            st.ee_tests += out.ee_tests;
            ExactPathCounts& e = st.exact_paths;
            e.filtered += out.exact.filtered;
            e.static_contact += out.exact.static_contact;
            e.proven_contact += out.exact.proven_contact;
            e.interval_filtered += out.exact.interval_filtered;
            e.exact_engine += out.exact.exact_engine;
        }
        parallel_sort(res.vf, threads);  // distinct pairs: std::sort's order (parallel.hpp)
        parallel_sort(res.ee, threads);
        st.elementary_tests = st.vf_tests + st.ee_tests;
        st.vf_contacts = static_cast<int64_t>(res.vf.size());
        st.ee_contacts = static_cast<int64_t>(res.ee.size());
        st.colliding_pairs = st.vf_contacts + st.ee_contacts;
    };

    if (stop_at_first) {
        // "Is this step collision-free?": a candidate's VF then EE pairs are made and tested as
        // soon as it is reached, up to the first contact; the pairs of the candidates after it
        // are never made. Test order: the candidates in traversal order (aabb / nc: the tasks in
        // first-hit order, as dcd), each candidate's VF pairs, then its EE pairs.
        auto first_contact = [&](const TrianglePair& c, CcdTally& out) {
            KeyBuffer vf, ee;
            pairs_of(c, vf, ee);
            out.vf_candidates += vf.size;
            out.ee_candidates += ee.size;
            for (int32_t i = 0; i < vf.size; ++i) {
                test_vf(vf.key[i], out);
                if (!out.vf.empty()) return true;
            }
            for (int32_t i = 0; i < ee.size; ++i) {
                test_ee(ee.key[i], out);
                if (!out.ee.empty()) return true;
            }
            return false;
        };
        const auto no_prefetch = [](const TrianglePair&, int) {};
        // A look at the interrupt flag (interrupt.hpp) before each candidate's tests (a dozen or
        // so VF/EE pairs, each costlier than the look): once it is set, every scan stops as if at
        // a contact, ending the query's blocks and chunks at once, and the query throws below.
        const auto contact_or_interrupt = [&](const TrianglePair& c, CcdTally& out) {
            return interrupt_requested(interrupt_) || first_contact(c, out);
        };
        std::vector<CcdTally> outs;
        size_t counted = 0;
        bool done = false;
        if constexpr (!kTraceHooks<Tracer>) {
            if (method_ == Method::kAabb || method_ == Method::kNc) {
                // Without a front to keep complete, the traversal stops at the hit too.
                t0 = Clock::now();
                const Continuous motion{V0, V1, ccd_first_.data(), false};  // first hit: no learning
                const auto run = [&](auto cones) {
                    constexpr bool kCones = decltype(cones)::value;
                    const auto make = [&](DcdStats& s, std::vector<TrianglePair>& out, FrontPart*) {
                        return SelfCollideTraversal<kCones, Tracer, Continuous, false>(bvh_, contours_, cones_, motion,
                                                                                      tracer, s, out, interrupt_);
                    };
                    const auto find_hit = [&](const std::vector<TrianglePair>& c, CcdTally& out) {
                        CandidateList list;
                        list.set(c);
                        int64_t i = 0;
                        run_tests(out, [&] {
                            i = list.find_in_range(
                                0, list.size(), [&](const TrianglePair& p) { return contact_or_interrupt(p, out); },
                                no_prefetch);
                        });
                        return i;
                    };
                    return self_collide_until_first_hit(bvh_, threads, make, find_hit, outs, st, parallel_);
                };
                const FirstHit hit = method_ == Method::kNc ? run(std::true_type{}) : run(std::false_type{});
                candidates_.clear();
                candidate_list_.set(candidates_);
                if (interrupt_requested(interrupt_)) throw Interrupted{};
                std::vector<CcdTally> ordered(hit.tasks);
                for (size_t i = 0; i < hit.tasks; ++i) ordered[i] = std::move(outs[parallel_.run_order[i]]);
                outs.swap(ordered);
                counted = outs.size();
                st.seconds_traversal = seconds_since(t0);  // the pairs and tests run inside it
                done = true;
            }
        }
        if (!done) {
            // The front methods (their front must stay complete), cbc and traced queries
            // traverse fully, then go through the candidates in chunks; each chunk stops at its
            // first contact (FirstHitChunk), so the chunks up to the first with a contact hold
            // exactly the tests up to the first contact in candidate order, whatever the chunking.
            t0 = Clock::now();
            traverse(Continuous{V0, V1, ccd_first_.data()}, tracer, st);
            st.seconds_traversal = seconds_since(t0);
            t0 = Clock::now();
            const CandidateList& candidates = candidate_list_;
            const Chunks ch(candidates.size(), threads, 1024);
            outs.resize(ch.count);
            FirstHitChunk first_hit(ch.count);
            parallel_chunks(ch.count, threads, [&](int64_t k, int) {
                if (first_hit.skip(k)) return;
                CcdTally& out = outs[k];
                int64_t i = 0;
                run_tests(out, [&] {
                    i = candidates.find_in_range(
                        ch.begin(k), ch.end(k), [&](const TrianglePair& c) { return contact_or_interrupt(c, out); },
                        no_prefetch);
                });
                if (i < ch.end(k)) first_hit.found(k);
            });
            if (interrupt_requested(interrupt_)) throw Interrupted{};
            counted = static_cast<size_t>(std::min(first_hit.get() + 1, ch.count));
            st.seconds_elementary = seconds_since(t0);
        }
        gather(outs.data(), counted);
        st.seconds_pairs = seconds_boxes;
        return;
    }

    t0 = Clock::now();
    traverse(Continuous{V0, V1, ccd_first_.data()}, tracer, st);
    st.seconds_traversal = seconds_since(t0);

    t0 = Clock::now();
    // In chunks of candidates, each chunk's keys in its own lists, concatenated in chunk order:
    // the serial order.
    const Chunks cand(candidate_list_.size(), threads, 1024);
    std::vector<Padded<std::vector<uint64_t>>> vf_parts(cand.count), ee_parts(cand.count);
    parallel_chunks(cand.count, threads, [&](int64_t k, int) {
        candidate_list_.for_range(cand.begin(k), cand.end(k),
                                  [&](const TrianglePair& c) { pairs_of(c, vf_parts[k].value, ee_parts[k].value); });
    });
    std::vector<uint64_t>& vf_keys = vf_keys_;
    std::vector<uint64_t>& ee_keys = ee_keys_;
    concat_in_order(vf_parts, vf_parts.size(), threads, vf_keys);
    concat_in_order(ee_parts, ee_parts.size(), threads, ee_keys);
    st.vf_candidates = static_cast<int64_t>(vf_keys.size());
    st.ee_candidates = static_cast<int64_t>(ee_keys.size());
    st.seconds_pairs = seconds_boxes + seconds_since(t0);

    // keys[b, e): four at a time through the floating-point filter first (ccd/non_penetration.hpp),
    // for a fraction of a scalar filter's cost. It culls most of the pairs the filter culls (which
    // are 61% of armadillo's, 93% of rod-twist's, 31-36% of the generated folds'), and proves most
    // of the others kept (two coefficients of opposite signs): those go straight to the
    // elementary test. The rest, and the last few keys, go through test (the full filter, exact
    // where it must be, then the elementary test). In key order: the same contacts and counters
    // as test on each key.
    auto test_keys = [&](const uint64_t* keys, int64_t b, int64_t e, const auto& test, auto filter4,
                         const int32_t* prims, CcdTally& out) {
        int64_t i = b;
        for (; i + 4 <= e; i += 4) {
            const uint32_t bits = filter4(V0, V1, prims, keys + i);
            if ((bits & 0xfu) == 0xfu) {
                out.npf_culled += 4;
                continue;
            }
            for (int l = 0; l < 4; ++l) {
                if (bits >> l & 1u) ++out.npf_culled;
                else test(keys[i + l], out, !(bits >> (4 + l) & 1u));  // kept: no filter to rerun
            }
        }
        for (; i < e; ++i) test(keys[i], out);
    };
    t0 = Clock::now();
    // The VF then the EE keys as one range, in chunks; each chunk keeps its own contacts and
    // counters.
    const int64_t n_vf = static_cast<int64_t>(vf_keys.size());
    const Chunks keys(n_vf + static_cast<int64_t>(ee_keys.size()), threads, 64);
    std::vector<CcdTally> outs(keys.count);
    parallel_chunks(keys.count, threads, [&](int64_t k, int) {
        CcdTally& out = outs[k];
        run_tests(out, [&] {
            // In blocks, each after a look at the interrupt flag (interrupt.hpp), the first at the
            // chunk's start: chunks begun after the flag stop at once (with i % stride instead,
            // each ran up to 63 tests first: 0.8-1.0 s late on two threads).
            const int64_t end = keys.end(k);
            for (int64_t b = keys.begin(k); b < end; b += kInterruptStride) {
                if (interrupt_requested(interrupt_)) return;
                const int64_t e = std::min(end, b + kInterruptStride);
                test_keys(vf_keys.data(), std::min(b, n_vf), std::min(e, n_vf), test_vf, vf_never_coplanar4, F, out);
                test_keys(ee_keys.data(), std::max(b, n_vf) - n_vf, std::max(e, n_vf) - n_vf, test_ee,
                          ee_never_coplanar4, E, out);
            }
        });
    });
    if (interrupt_requested(interrupt_)) throw Interrupted{};
    gather(outs.data(), outs.size());
    st.seconds_elementary = seconds_since(t0);
}

}  // namespace conecull
