// BVH self-traversal: "aabb" (no cones) and "nc" (Alg. 2, normal cone culling with the
// unprojected contour test), and their front-tracking variants "aabb+front" (a conventional BVTT
// front, [TMLT11]) and "nc+front" (Alg. 4, the normal cone guided BVTT front); the baselines
// "sct" and "cbc" are Alg. 2 with another contour test (Sec. 6.1). All emit each
// candidate triangle pair exactly once: pairs inside one child are found by its SelfCollide,
// pairs across the children by Collide(L, R) or, with a front, by FrontTracking(Front_N).
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <utility>
#include <vector>

#include "conecull/bvh/bvh.hpp"
#include "conecull/cone/normal_cone.hpp"
#include "conecull/contour/contour.hpp"
#include "conecull/ccd/contour_test_ccd.hpp"
#include "conecull/contour/contour_test.hpp"
#include "conecull/contour/contour_test_cbc.hpp"
#include "conecull/contour/contour_test_sct.hpp"
#include "conecull/contour/contour_test_simple.hpp"
#include "conecull/interrupt.hpp"
#include "conecull/trace/null_tracer.hpp"
#include "conecull/traversal/bvtt_front.hpp"
#include "conecull/traversal/stats.hpp"

namespace conecull {

using TrianglePair = std::pair<int32_t, int32_t>;

// A task of the parallel traversal: SelfCollide(a) if b == kSelfTask, FrontTracking(Front_a)
// if b == kFrontTask (front methods), else Collide(a, b).
struct BvttTask {
    static constexpr int32_t kSelfTask = -1, kFrontTask = -2;
    int32_t a, b;
};

// The motion a query covers and its contour test, as a policy of the traversal (chosen at
// compile time per method: no virtual call in the loop): one pose (DCD) or a linear step from V0
// to V1 (CCD). Only the contour test depends on it; boxes and cones were refit beforehand.
// Ours, the unprojected test: Alg. 1 (DCD), Alg. 3 (CCD), with the simplicity fallback and the
// kernel-point search (with_simplicity_fallback, contour_test_simple.hpp): the star test proves
// most contours simple cheaply, the fallback decides simplicity on those it cannot. `first`, if
// given, holds per node the test to run first (FirstTest: the one that proved the node when it was
// last tested; the collider keeps one array per query kind), and is updated if `learn`; without
// it, Alg. 1 runs first. Each node's entry is read and written only by its own contour test, which
// runs at most once per query, so parallel tasks never share one. A query that stops at its first
// hit does not learn: on several threads, which tasks past the hit run depends on timing, and the
// order must not (the counters of later queries depend on it). A failure reports Alg. 1's verdict
// (its reason, kernel point and ray).
// test(order) with node's order from `first` (Alg. 1 first without one); learns the next order.
template <class Test>
ContourVerdict in_first_test_order(FirstTest* first, bool learn, int32_t node, Test test) {
    const FirstTest order = first ? first[node] : FirstTest::kStar;
    const ContourVerdict v = test(order);
    if (first && learn) first[node] = next_first_test(v, order);
    return v;
}
// DCD: one pose.
struct Discrete {
    static constexpr bool kContinuous = false;
    const double* V;
    FirstTest* first = nullptr;
    bool learn = true;
    ContourVerdict contour_test(int32_t node, const int32_t* loop, int32_t n, const Vec3& l) const {
        return in_first_test_order(first, learn, node, [&](FirstTest order) {
            return with_simplicity_fallback(
                n, true, order, [&] { return unprojected_contour_test_at_mean(loop, n, V, l); },
                [&](SimplicityScratch& s) { return simplicity_test(loop, n, V, l, s); },
                [&](const ContourVerdict& v) { return retry_kernel_point(v, loop, n, V, l); });
        });
    }
};
// CCD: Alg. 3 with the means, the simplicity fallback over the step (simple at every t) and the
// kernel-point search.
struct Continuous {
    static constexpr bool kContinuous = true;
    const double* V0;
    const double* V1;
    FirstTest* first = nullptr;
    bool learn = true;
    ContourVerdict contour_test(int32_t node, const int32_t* loop, int32_t n, const Vec3& l) const {
        return in_first_test_order(first, learn, node, [&](FirstTest order) {
            return with_simplicity_fallback(
                n, false, order, [&] { return unprojected_contour_test_ccd_at_mean(loop, n, V0, V1, l); },
                [&](SimplicityScratch& s) { return simplicity_test_ccd(loop, n, V0, V1, l, s); },
                [&](const ContourVerdict& v) { return retry_kernel_point_ccd(v, loop, n, V0, V1, l); });
        });
    }
};
// Baselines (Sec. 6.1). "sct": the projected star-contour test of [SPO10] (DCD only).
struct DiscreteProjected {
    static constexpr bool kContinuous = false;
    const double* V;
    ProjectionScratch* scratch;
    ContourVerdict contour_test(int32_t, const int32_t* loop, int32_t n, const Vec3& l) const {
        return projected_contour_test(loop, n, V, l, *scratch);
    }
};
// "cbc": the O(n^2) edge-pair test of [TCYM09]; for DCD the same test at the one pose.
struct DiscreteQuadratic {
    static constexpr bool kContinuous = false;
    const double* V;
    ContourVerdict contour_test(int32_t, const int32_t* loop, int32_t n, const Vec3& l) const {
        return quadratic_contour_test(loop, n, V, l);
    }
};
struct ContinuousQuadratic {
    static constexpr bool kContinuous = true;
    const double* V0;
    const double* V1;
    ContourVerdict contour_test(int32_t, const int32_t* loop, int32_t n, const Vec3& l) const {
        return quadratic_contour_test_ccd(loop, n, V0, V1, l);
    }
};

// kTrackFront: Collide(L, R) of every node is resumed from the node's BVTT front sub-segment
// (Alg. 4), kept in `front` between queries. The new sub-segments go to `part` (a task's own,
// parallel traversal) or else to front->next.
template <bool kUseCones, class Tracer, class Motion = Discrete, bool kTrackFront = false>
class SelfCollideTraversal {
   public:
    // interrupt: the query's Ctrl-C flag (interrupt.hpp), or null.
    SelfCollideTraversal(const Bvh& bvh, const Contours& contours, const std::vector<NormalCone>& cones,
                         const Motion& motion, Tracer& tracer, DcdStats& stats, std::vector<TrianglePair>& candidates,
                         const std::atomic<bool>* interrupt, BvttFront* front = nullptr, FrontPart* part = nullptr)
        : bvh_(bvh), contours_(contours), cones_(cones), motion_(motion), tracer_(tracer), stats_(stats), out_(candidates),
          interrupt_(interrupt), front_(front), part_(part ? part : front ? &front->next : nullptr),
          rebase_(part != nullptr) {}

    void run() {
        if constexpr (kTrackFront) front_->prepare(bvh_);
        if (bvh_.size() > 0) self_collide(0);
        flush();
        if constexpr (kTrackFront) front_->finish_query(stats_);
    }

    // Parallel traversal (parallel_self_collide.hpp): the top of the BVTT becomes an ordered
    // list of independent tasks. expand does a task's first step (the counters and tests
    // SelfCollide / Collide would do there) and appends its subtasks in the order they would
    // run: concatenated in that order, their candidates (and front sub-segments) are the task's.
    // Tasks at the leaves, and FrontTracking tasks, are kept whole (false: nothing done).
    bool expand(BvttTask t, std::vector<BvttTask>& out) {
        if (t.b == BvttTask::kFrontTask) {
            out.push_back(t);
            return false;
        }
        if (t.b == BvttTask::kSelfTask) {
            const BvhNode& n = bvh_[t.a];
            if (n.end - n.begin < 2) return true;
            if (n.is_leaf()) {
                out.push_back(t);
                return false;
            }
            ++stats_.self_tests;
            if constexpr (kUseCones) {
                if (is_self_collision_free(t.a)) return true;
            }
            const int32_t l = Bvh::left(t.a), r = n.right;
            // Alg. 2 lines 11-13 / Alg. 4 lines 11-13, as self_collide.
            if constexpr (kTrackFront) {
                out.insert(out.end(), {{l, BvttTask::kSelfTask}, {r, BvttTask::kSelfTask}, {t.a, BvttTask::kFrontTask}});
            } else {
                out.insert(out.end(), {{l, BvttTask::kSelfTask}, {r, BvttTask::kSelfTask}, {l, r}});
            }
            return true;
        }
        const BvhNode& na = bvh_[t.a];
        const BvhNode& nb = bvh_[t.b];
        if (na.is_leaf() && nb.is_leaf()) {
            out.push_back(t);
            return false;
        }
        ++stats_.bv_tests;
        const bool overlap = na.box.overlaps(nb.box);
        if constexpr (kTraceHooks<Tracer>) tracer_.on_node_pair(t.a, t.b, overlap);
        if (!overlap) return true;
        if (nb.is_leaf() || (!na.is_leaf() && na.end - na.begin >= nb.end - nb.begin)) {  // as descend
            out.insert(out.end(), {{Bvh::left(t.a), t.b}, {na.right, t.b}});
        } else {
            out.insert(out.end(), {{t.a, Bvh::left(t.b)}, {t.a, nb.right}});
        }
        return true;
    }
    void run_task(BvttTask t) {
        if (t.b == BvttTask::kSelfTask) {
            self_collide(t.a);
        } else if (t.b == BvttTask::kFrontTask) {
            if constexpr (kTrackFront) front_tracking(t.a);
        } else {
            collide<false>(t.a, t.b);
        }
        flush();
    }

   private:
    static constexpr int32_t kPrefetchAhead = 8;

    // Alg. 2 SelfCollide(N); with a front, Alg. 4 SelfCollideWithGuidedFrontTracking(N).
    void self_collide(int32_t i) {
        const BvhNode& n = bvh_[i];
        if (n.end - n.begin < 2) return;  // Alg. 2 / 4 line 1: a single triangle cannot self-collide
        ++stats_.self_tests;
        if constexpr (kUseCones) {
            // Alg. 2 / 4 lines 5-8. With a front, Front_N and those below are not tracked, so
            // not kept (bvtt_front.hpp): rebuilt from the top if N fails the tests again.
            if (is_self_collision_free(i)) return;
        }
        if (n.is_leaf()) {
            for (int32_t a = n.begin; a < n.end; ++a)
                for (int32_t b = a + 1; b < n.end; ++b) emit(bvh_.order[a], bvh_.order[b]);
            return;
        }
        const int32_t l = Bvh::left(i), r = n.right;
        self_collide(l);  // Alg. 2 / 4 line 11
        self_collide(r);  // line 12
        if constexpr (kTrackFront) {
            front_tracking(i);  // Alg. 4 line 13
        } else {
            collide<false>(l, r);  // Alg. 2 line 13
        }
    }

    // Alg. 2 lines 5-6: normal cone test, then the unprojected contour test (Alg. 1).
    bool is_self_collision_free(int32_t i) {
        const NormalCone& cone = cones_[i];
        ++stats_.cone_tests;
        const bool bounded = cone.bounded();
        if constexpr (kTraceHooks<Tracer>) tracer_.on_cone_test(i, cone, bounded);
        if (!bounded) return false;
        ++stats_.cone_passed;
        if (!contours_.eligible(i)) {
            ++stats_.contour_ineligible;
            if constexpr (kTraceHooks<Tracer>) tracer_.on_contour_ineligible(i, contours_.status[i]);
            return false;
        }
        ++stats_.contour_tests;
        // Fig. 9's measure: time inside the contour tests, a steady clock around each call
        // (two clock reads, ~2 x 20 ns, included; cheap next to the test on large nodes).
        const auto t0 = std::chrono::steady_clock::now();
        const ContourVerdict v = motion_.contour_test(i, contours_.loop(i), contours_.loop_size(i), cone.axis);
        stats_.seconds_contour += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        stats_.contour_edges += v.edges_visited;
        ++stats_.contour_reasons[static_cast<int>(v.reason)];
        if constexpr (kTraceHooks<Tracer>) tracer_.on_contour_test(i, v);
        if (v.passed()) {
            ++stats_.contour_passed;
            stats_.contour_passed_simple += v.by_simplicity;
            return true;
        }
        ++stats_.contour_failed;
        return false;
    }

    // Collide(A, B): nodes with disjoint triangle sets. With kRecord, the BVTT nodes where it
    // stops (boxes apart, or two leaves) are appended to the front sub-segment being rebuilt.
    template <bool kRecord>
    void collide(int32_t a, int32_t b) {
        ++stats_.bv_tests;
        const bool overlap = bvh_[a].box.overlaps(bvh_[b].box);
        if constexpr (kTraceHooks<Tracer>) tracer_.on_node_pair(a, b, overlap);
        collide_tested<kRecord>(a, b, overlap);
    }

    // Collide(A, B) once A's and B's boxes are tested: apart, the pair is a front entry (with
    // kRecord); overlapping, two leaves emit their pairs, else the larger node is descended.
    template <bool kRecord>
    void collide_tested(int32_t a, int32_t b, bool overlap) {
        if (!overlap) {
            if constexpr (kRecord) push_front({a, b}, false);  // its parent overlaps: nothing to merge
            return;
        }
        const BvhNode& na = bvh_[a];
        const BvhNode& nb = bvh_[b];
        if (na.is_leaf() && nb.is_leaf()) {
            emit_leaves(na, nb);
            if constexpr (kRecord) push_front({a, b}, false);
            return;
        }
        descend<kRecord>(a, b);
    }

    // Descend the larger node (the only one that can be descended, if the other is a leaf).
    // Both children pairs are box-tested before either is entered, so only overlapping pairs
    // cost a call, and the two tests' loads overlap: the same tests, candidates and front entries
    // in the same order as Collide on each pair in turn. A traced query keeps that form, so that
    // its node-pair events come in the recursion's order.
    template <bool kRecord>
    void descend(int32_t a, int32_t b) {
        const BvhNode& na = bvh_[a];
        const BvhNode& nb = bvh_[b];
        int32_t a1 = a, a2 = a, b1 = b, b2 = b;
        if (nb.is_leaf() || (!na.is_leaf() && na.end - na.begin >= nb.end - nb.begin)) {
            a1 = Bvh::left(a);
            a2 = na.right;
        } else {
            b1 = Bvh::left(b);
            b2 = nb.right;
        }
        if constexpr (kTraceHooks<Tracer>) {
            collide<kRecord>(a1, b1);
            collide<kRecord>(a2, b2);
        } else {
            stats_.bv_tests += 2;
            const bool first = bvh_[a1].box.overlaps(bvh_[b1].box);
            const bool second = bvh_[a2].box.overlaps(bvh_[b2].box);
            collide_tested<kRecord>(a1, b1, first);
            collide_tested<kRecord>(a2, b2, second);
        }
    }

    void emit_leaves(const BvhNode& na, const BvhNode& nb) {
        for (int32_t p = na.begin; p < na.end; ++p)
            for (int32_t q = nb.begin; q < nb.end; ++q) emit(bvh_.order[p], bvh_.order[q]);
    }

    // Alg. 4 line 13, FrontTracking(Front_N): Collide(L, R) resumed from the cut the previous
    // query left (see bvtt_front.hpp for why any cut gives exactly Collide's candidates). The
    // front grows where an entry's boxes now overlap (it is descended as Collide would) and
    // shrinks where two sibling entries and their parent are apart (they merge into the parent).
    // Where the front churns, N rests instead (BvttFront::churned): Collide(L, R) from the top,
    // nothing kept, so the front never costs much more than Alg. 2.
    void front_tracking(int32_t n) {
        BvttFront& f = *front_;
        FrontPart& next = *part_;
        const size_t start = next.entries.size();
        // N's record from the last query (its sub-segment and churn state), if it visited N.
        const FrontSegment* last = f.record(n);
        const bool resumable = last && last->tracked;
        FrontSegment rec{static_cast<int64_t>(start), n, 0, 0, last ? last->rest : uint8_t{0},
                         last ? last->backoff : uint8_t{0}};
        // The front event of Front_N (how it was updated, its size before and after, the box
        // tests spent), at each way out; nothing of it is computed with tracing off.
        [[maybe_unused]] const int64_t tests_at_start = kTraceHooks<Tracer> ? stats_.bv_tests : 0;
        [[maybe_unused]] const int32_t had = kTraceHooks<Tracer> && resumable ? last->count : 0;
        const auto traced = [&]([[maybe_unused]] FrontMode mode) {
            if constexpr (kTraceHooks<Tracer>)
                tracer_.on_front(n, mode, had, mode == FrontMode::kResting || mode == FrontMode::kChurned
                                                   ? 0 : static_cast<int32_t>(next.entries.size() - start),
                                 stats_.bv_tests - tests_at_start);
        };
        mergeable_run_ = 0;  // a new sub-segment: nothing before it may merge
        if (rec.rest > 0) {  // resting after churn (bvtt_front.hpp): Alg. 2 line 13, unrecorded
            --rec.rest;
            ++stats_.front_rested;
            collide<false>(Bvh::left(n), bvh_[n].right);
            keep_record(rec);
            traced(FrontMode::kResting);
            return;
        }
        const FrontMode mode = resumable ? FrontMode::kResumed : FrontMode::kFromTop;
        if (mode == FrontMode::kFromTop) {
            collide<true>(Bvh::left(n), bvh_[n].right);  // no front kept: from the top, L * R
        } else {
            const int64_t tests_before = stats_.bv_tests;
            const FrontEntry* seg = f.entries.data() + last->begin;
            const int32_t count = last->count;
            const BvhNode* nodes = bvh_.nodes.data();  // in a register across the loop
            for (int32_t k = 0; k < count; ++k) {
                // A front is a flat list of independent box tests, known ahead: unlike a
                // top-down descent it can fetch the boxes of later entries while testing this one.
                if (k + kPrefetchAhead < count) {
                    __builtin_prefetch(&nodes[seg[k + kPrefetchAhead].a]);
                    __builtin_prefetch(&nodes[seg[k + kPrefetchAhead].b]);
                }
                const FrontEntry e = seg[k];
                ++stats_.bv_tests;
                const BvhNode& na = nodes[e.a];
                const BvhNode& nb = nodes[e.b];
                // Branch-free: which comparison fails first varies from entry to entry, and the
                // early exits were mispredicted (13% of this loop on flamenco). The recursion
                // keeps them: flat there, nc got slower (README, BVTT fronts).
                const bool overlap = na.box.overlaps_flat(nb.box);
                if constexpr (kTraceHooks<Tracer>) tracer_.on_node_pair(e.a, e.b, overlap);
                if (!overlap) {
                    next.entries.push_back(e);
                    ++mergeable_run_;
                    if (mergeable_run_ >= 2) merge_apart_siblings();
                } else if (na.is_leaf() && nb.is_leaf()) {
                    emit_leaves(na, nb);
                    next.entries.push_back(e);
                    mergeable_run_ = 0;
                } else {
                    descend<true>(e.a, e.b);  // the front grows below e
                }
            }
            if (BvttFront::churned(rec, stats_.bv_tests - tests_before, static_cast<int64_t>(next.entries.size() - start))) {
                next.entries.resize(start);  // N rests from the next query: nothing kept
                keep_record(rec);
                traced(FrontMode::kChurned);
                return;
            }
        }
        rec.count = static_cast<int32_t>(next.entries.size() - start);
        rec.tracked = 1;
        keep_record(rec);
        traced(mode);
    }

    // N's record for the next query. A task's records are numbered when the parts are joined
    // (parallel_self_collide.hpp); a whole query numbers them here.
    void keep_record(const FrontSegment& rec) {
        FrontPart& next = *part_;
        if (!rebase_) front_->slot[rec.node] = static_cast<int32_t>(next.segments.size());
        next.segments.push_back(rec);
    }

    void push_front(FrontEntry e, bool mergeable) {
        part_->entries.push_back(e);
        mergeable_run_ = mergeable ? mergeable_run_ + 1 : 0;
        ++stats_.front_added;
    }

    // The front shrinks: while the last two entries of the sub-segment are apart siblings that
    // may merge and their parent's boxes are apart too, replace them by the parent (which may
    // merge again, with its own sibling).
    void merge_apart_siblings() {
        FrontEntries& next = part_->entries;
        while (mergeable_run_ >= 2) {
            FrontEntry p;
            if (!BvttFront::parent_of(bvh_, next[next.size() - 2], next.back(), p)) return;
            ++stats_.bv_tests;
            const bool overlap = bvh_[p.a].box.overlaps(bvh_[p.b].box);
            if constexpr (kTraceHooks<Tracer>) tracer_.on_node_pair(p.a, p.b, overlap);
            if (overlap) return;
            next.resize(next.size() - 2);
            mergeable_run_ -= 2;
            push_front(p, true);
        }
    }

    // Candidates go to out_ through a small buffer, flushed when full and at the end of run() and
    // run_task(): a push to out_ in the recursion compiled to an out-of-line call per candidate
    // (3.5% of the samples of a first-hit DCD query on the armadillo step).
    [[gnu::always_inline]] void emit(int32_t s, int32_t t) {
        buffer_[buffered_++] = {s < t ? s : t, s < t ? t : s};
        if (buffered_ == kBuffer) flush();
    }
    // Also where the traversal looks at the Ctrl-C flag: a long traversal is one that emits many
    // candidates (every other box test is bounded by them and the nodes), so once per kBuffer of
    // them. Thrown from the recursion, Interrupted unwinds it; the collider then forgets the front
    // being built (SelfCollider::dcd / ccd).
    [[gnu::noinline]] void flush() {
        out_.insert(out_.end(), buffer_.begin(), buffer_.begin() + buffered_);
        buffered_ = 0;
        if (interrupt_requested(interrupt_)) throw Interrupted{};
    }

    const Bvh& bvh_;
    const Contours& contours_;
    const std::vector<NormalCone>& cones_;
    Motion motion_;
    Tracer& tracer_;
    DcdStats& stats_;
    std::vector<TrianglePair>& out_;
    const std::atomic<bool>* interrupt_;
    BvttFront* front_;  // kTrackFront only
    FrontPart* part_;   // where the new sub-segments go
    bool rebase_;       // part_ is a task's: its records are numbered, and begin rebased, at the join
    // How many entries at the end of the sub-segment being built may merge with a sibling: their
    // boxes are apart and they were not just made by descending a parent whose boxes overlap. A
    // merge only ever looks at the last two, and replaces them by one that may merge again, so
    // this count is all it needs (one sub-segment is built at a time).
    int32_t mergeable_run_ = 0;
    static constexpr int32_t kBuffer = 64;
    std::array<TrianglePair, kBuffer> buffer_;
    int32_t buffered_ = 0;
};

}  // namespace conecull
