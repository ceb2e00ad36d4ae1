// SelfCollide(root) on several threads, with exactly the serial traversal's candidates, in the
// serial order, and its counters; for the front methods also exactly the serial BVTT front.
//
// Alg. 2 is a depth-first recursion whose output is the concatenation of its children's:
// SelfCollide(N) = SelfCollide(L) + SelfCollide(R) + Collide(L, R), and Collide(A, B) likewise
// over the two halves of the larger node. So the top of the BVTT is expanded, in place, into an
// ordered list of independent tasks (each step doing the cone / box test the recursion would do
// there), until there are enough to keep every thread busy; the tasks then run on any thread,
// each into its own buffer, and the buffers are concatenated in task order. Counters are sums,
// kept per worker and added up. Every test is made once, in the expansion or in a task, so the
// candidates, the front and the counters do not depend on where the list stops.
//
// Alg. 4 (and the conventional front) has the same shape with FrontTracking(Front_N) in place
// of Collide(L, R): it reads only Front_N of the previous query and writes only the new Front_N,
// whose entries come out in traversal order after those of the nodes below N. So a task writes
// its sub-segments and records into its own part, each record's begin relative to that part;
// the parts are concatenated in task order, each begin shifted by its part's offset and each
// record's slot set: the same entries and records, in the same layout, as the serial traversal.
// (A FrontTracking task is not split: its merges join neighbouring entries of one sub-segment.)
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "conecull/parallel.hpp"
#include "conecull/traversal/self_collide.hpp"

namespace conecull {

// The candidates of a query, in traversal order: one array (serial traversal), or the parallel
// traversal's per-task arrays one after another, read in place (copying them into one array
// would cost a pass over all of them, ~4 MB for "aabb" on the 64K-triangle benchmark).
struct CandidateList {
    const std::vector<TrianglePair>* whole = nullptr;
    const std::vector<Padded<std::vector<TrianglePair>>>* parts = nullptr;
    std::vector<int64_t> offset{0};  // parts: part k holds the candidates [offset[k], offset[k + 1])

    int64_t size() const { return whole ? static_cast<int64_t>(whole->size()) : offset.back(); }
    // fn(pair) for the candidates [b, e), in order.
    template <class Fn>
    void for_range(int64_t b, int64_t e, const Fn& fn) const {
        for_range(b, e, fn, [](const TrianglePair&, int) {});
    }
    // The same, and ahead(pair, d) for the pair d = 8 and d = 16 places later (same part), so
    // that the caller can prefetch what that pair's test will load.
    template <class Fn, class Ahead>
    void for_range(int64_t b, int64_t e, const Fn& fn, const Ahead& ahead) const {
        find_in_range(b, e, [&](const TrianglePair& c) {
            fn(c);
            return false;
        }, ahead);
    }
    // fn(pair) for the candidates [b, e) in order until it returns true: the index of that
    // candidate, or e. ahead as for for_range.
    template <class Fn, class Ahead>
    int64_t find_in_range(int64_t b, int64_t e, const Fn& fn, const Ahead& ahead) const {
        return scan_runs(b, e, [&](const TrianglePair* p, int64_t n) {
            for (int64_t i = 0; i < n; ++i) {
                if (i + 16 < n) ahead(p[i + 16], 16);
                if (i + 8 < n) ahead(p[i + 8], 8);
                if (fn(p[i])) return i;
            }
            return n;
        });
    }
    // scan(p, n) over the candidates [b, e) as contiguous runs p[0, n), in order, until one
    // returns k < n (it stopped at its k-th candidate): the index of that candidate, or e.
    template <class Scan>
    int64_t scan_runs(int64_t b, int64_t e, const Scan& scan) const {
        if (whole) {
            const int64_t k = scan(whole->data() + b, e - b);
            return k < e - b ? b + k : e;
        }
        size_t part = static_cast<size_t>(std::upper_bound(offset.begin(), offset.end(), b) - offset.begin()) - 1;
        for (; b < e; ++part) {
            const int64_t hi = std::min(e, offset[part + 1]);
            const int64_t k = scan((*parts)[part].value.data() + (b - offset[part]), hi - b);
            if (k < hi - b) return b + k;
            b = hi;
        }
        return e;
    }
    void set(const std::vector<TrianglePair>& all) {
        whole = &all;
        parts = nullptr;
    }
};

// Buffers reused between queries.
struct ParallelTraversalScratch {
    std::vector<BvttTask> tasks, expanded;
    std::vector<std::vector<BvttTask>> expanded_of;  // per seed task: its list, and scratch
    std::vector<int32_t> run_order;
    std::vector<Padded<std::vector<TrianglePair>>> candidates;  // per task
    std::vector<Padded<FrontPart>> fronts;                      // per task (front methods)
    std::vector<Padded<DcdStats>> stats;                        // per worker
};

// Expands `list` level by level, in place and in order (each task replaced by its subtasks),
// until it holds at least `enough` tasks or no task progresses; `tmp` is scratch.
template <class Traversal>
void expand_levels(Traversal&& traversal, size_t enough, std::vector<BvttTask>& list, std::vector<BvttTask>& tmp) {
    while (list.size() < enough) {
        tmp.clear();
        bool progressed = false;
        for (const BvttTask& t : list) progressed |= traversal.expand(t, tmp);
        list.swap(tmp);
        if (!progressed) break;
    }
}

// Two ways to expand the top of the BVTT into an ordered list of tasks in s.tasks, the tests of
// the expansion counted in s.stats (one per worker); either list depends on `enough` only, never
// on the thread count.
//
// expand_tasks_by_levels, for the first-hit traversal: level by level over the whole list until it
// holds at least `enough` tasks (or every task is at the leaves), each level a parallel region.
// Every task of the list is then as deep as the others, as the first-hit order wants
// (first_hit_order sorts the tasks by depth).
template <class Make>
void expand_tasks_by_levels(int threads, const Make& make, size_t enough, ParallelTraversalScratch& s) {
    std::vector<TrianglePair> none;  // the expansion emits no candidates
    std::vector<BvttTask>& tasks = s.tasks;
    tasks.assign(1, BvttTask{0, BvttTask::kSelfTask});
    s.stats.assign(threads, Padded<DcdStats>{});
    std::vector<uint8_t> progressed;
    while (tasks.size() < enough) {
        const size_t n = tasks.size();
        if (s.expanded_of.size() < n) s.expanded_of.resize(n);
        progressed.assign(n, 0);
        parallel_chunks(static_cast<int64_t>(n), n < 4 ? 1 : threads, [&](int64_t k, int w) {
            s.expanded_of[k].clear();
            progressed[k] = make(s.stats[w].value, none, nullptr).expand(tasks[k], s.expanded_of[k]);
        });
        s.expanded.clear();
        for (size_t k = 0; k < n; ++k) s.expanded.insert(s.expanded.end(), s.expanded_of[k].begin(), s.expanded_of[k].end());
        tasks.swap(s.expanded);
        if (std::find(progressed.begin(), progressed.end(), 1) == progressed.end()) break;
    }
}

// expand_tasks, for the full traversal: serially until kSeedTasks tasks (the first levels: a few
// tests), then each of these seeds on its own, in parallel, level by level to its share of
// `enough`; concatenated in seed order. Why: level by level over the whole list, each level is a
// parallel region that ends when its slowest task does, and a level's cost is mostly one long
// contour test (a large node's). On the 64K fold (nc, to ~128 tasks; a throw-away timed build,
// medians of 40 queries) two threads took 0.104-0.116 ms by levels, 0.123-0.134 with the regions
// on one thread, and 0.076 ms by seeds.
inline constexpr size_t kSeedTasks = 4;
template <class Make>
void expand_tasks(int threads, const Make& make, size_t enough, ParallelTraversalScratch& s) {
    std::vector<TrianglePair> none;  // the expansion emits no candidates
    std::vector<BvttTask>& tasks = s.tasks;
    s.stats.assign(threads, Padded<DcdStats>{});
    tasks.assign(1, BvttTask{0, BvttTask::kSelfTask});
    expand_levels(make(s.stats[0].value, none, nullptr), kSeedTasks, tasks, s.expanded);
    const size_t n = tasks.size();
    if (n >= enough || n == 0) return;
    const size_t share = (enough + n - 1) / n;
    if (s.expanded_of.size() < 2 * n) s.expanded_of.resize(2 * n);
    parallel_chunks(static_cast<int64_t>(n), threads, [&](int64_t k, int w) {
        std::vector<BvttTask>& list = s.expanded_of[k];
        list.assign(1, tasks[k]);
        expand_levels(make(s.stats[w].value, none, nullptr), share, list, s.expanded_of[n + k]);
    });
    tasks.clear();
    for (size_t k = 0; k < n; ++k) tasks.insert(tasks.end(), s.expanded_of[k].begin(), s.expanded_of[k].end());
}

// make(stats, candidates, part) constructs a SelfCollideTraversal writing to them (and, with a
// front, its sub-segments to part); front: the front of a front method, else null. The
// candidates are left in s, listed by `candidates`.
template <class Make>
void parallel_self_collide(const Bvh& bvh, int threads, const Make& make, BvttFront* front, DcdStats& stats,
                           CandidateList& candidates, ParallelTraversalScratch& s) {
    candidates.whole = nullptr;
    candidates.parts = &s.candidates;
    candidates.offset.assign(1, 0);
    if (front) front->prepare(bvh);
    if (bvh.size() > 0) {
        std::vector<BvttTask>& tasks = s.tasks;
        // Many tasks per thread: they are uneven (a culled subtree costs one test), and the
        // traversal ends with its last task. The expansion runs in parallel too: its cone and
        // contour tests (Alg. 2 lines 5-6) are on the largest nodes, with the longest contours.
        expand_tasks(threads, make, 64 * static_cast<size_t>(threads), s);
        const size_t n = tasks.size();
        if (s.candidates.size() < n) s.candidates.resize(n);
        if (front && s.fronts.size() < n) s.fronts.resize(n);
        // Run order (the output order stays the task order): FrontTracking tasks, which are not
        // split, first and the top nodes' (the largest) first, so that no large task starts
        // last while the other threads run out of work; then the others in order.
        s.run_order.resize(n);
        for (size_t k = 0; k < n; ++k) s.run_order[k] = static_cast<int32_t>(k);
        if (front) {
            std::stable_sort(s.run_order.begin(), s.run_order.end(), [&](int32_t p, int32_t q) {
                const bool fp = tasks[p].b == BvttTask::kFrontTask, fq = tasks[q].b == BvttTask::kFrontTask;
                if (fp != fq) return fp;
                return fp && bvh[tasks[p].a].depth < bvh[tasks[q].a].depth;
            });
        }
        parallel_chunks(static_cast<int64_t>(n), threads, [&](int64_t i, int w) {
            const int32_t k = s.run_order[i];
            s.candidates[k].value.clear();
            FrontPart* part = nullptr;
            if (front) {
                part = &s.fronts[k].value;
                part->clear();
            }
            make(s.stats[w].value, s.candidates[k].value, part).run_task(tasks[k]);
        });
        for (const Padded<DcdStats>& w : s.stats) stats.add_traversal_counters(w.value);
        candidates.offset.resize(n + 1);
        for (size_t k = 0; k < n; ++k)
            candidates.offset[k + 1] = candidates.offset[k] + static_cast<int64_t>(s.candidates[k].value.size());
        if (front) {
            // The parts one after another, each record's sub-segment moved by its part's offset
            // and numbered in the whole: the serial query's entries and records, in its order.
            std::vector<int64_t> offset(n + 1, 0), first(n + 1, 0);
            for (size_t k = 0; k < n; ++k) {
                offset[k + 1] = offset[k] + static_cast<int64_t>(s.fronts[k].value.entries.size());
                first[k + 1] = first[k] + static_cast<int64_t>(s.fronts[k].value.segments.size());
            }
            front->next.entries.resize(static_cast<size_t>(offset[n]));
            front->next.segments.resize(static_cast<size_t>(first[n]));
            FrontEntry* dst = front->next.entries.data();
            FrontSegment* rec = front->next.segments.data();
            parallel_chunks(static_cast<int64_t>(n), offset[n] < (1 << 16) ? 1 : threads, [&](int64_t k, int) {
                const FrontPart& p = s.fronts[k].value;
                std::copy(p.entries.begin(), p.entries.end(), dst + offset[k]);
                for (size_t i = 0; i < p.segments.size(); ++i) {
                    FrontSegment r = p.segments[i];
                    r.begin += offset[k];
                    const int64_t at = first[k] + static_cast<int64_t>(i);
                    rec[at] = r;
                    front->slot[r.node] = static_cast<int32_t>(at);  // each node in one part only
                }
            });
        }
    }
    if (front) front->finish_query(stats);
}

// The first colliding candidate in the order the tasks were visited (first_hit_order), and the
// candidates tested up to it; `tasks`: how many tasks in that order count, the hit's included
// (their ids are run_order[0, tasks) of the scratch).
struct FirstHit {
    bool found = false;
    TrianglePair pair{};
    int64_t tests = 0;
    size_t tasks = 0;
};

// Tasks and blocks of the first-hit traversal: fixed, so that what it runs, and so every counter,
// is the same for any thread count. Blocks start small (a hit among the first tasks ends the
// query early) and then double (16, 16, 32, 64, 128 tasks), so that a pose without a hit pays five
// parallel regions, not sixteen (measured with 16-task blocks on the 64K fold at 2 threads:
// aabb 61 -> 69 ms against the full query).
inline constexpr size_t kFirstHitTasks = 256;
inline constexpr size_t kFirstHitBlock = 16;

// Depth of the lowest BVH node holding both a and b (a itself for a self task, b < 0): how far
// apart on the surface the regions a task pairs up can be. Subtrees are ranges of the pre-order.
inline int32_t common_ancestor_depth(const Bvh& bvh, int32_t a, int32_t b) {
    if (b < 0) return bvh[a].depth;
    int32_t x = 0, end = bvh.size();  // x's subtree: [x, end)
    for (;;) {
        const BvhNode& n = bvh[x];
        if (n.is_leaf()) return n.depth;
        const int32_t l = Bvh::left(x), r = n.right;
        if (a < r && b < r && a >= l && b >= l) {
            x = l;
            end = r;
        } else if (a >= r && b >= r && a < end && b < end) {
            x = r;
        } else {
            return n.depth;
        }
    }
}

// The order in which the first-hit traversal visits its tasks: the traversal order and the
// distant-first order (tasks by common_ancestor_depth, the top's first; ties in traversal order)
// taking turns, each skipping the tasks the other has taken. Why both: where a pose intersects
// itself because a layer passed through another (cloth folded through itself), the colliding
// pairs lie between regions that meet only high in the BVH, in the last tasks of the traversal
// order (measured: the 64K jittered fold's first hit in traversal order is its 197378th
// candidate; distant-first, its 2nd); where it intersects locally (a fold poking through its
// neighbour), in a small subtree, often early in traversal order (the cloth-funnel step: its
// 2445th candidate; distant-first, its 28785th). Taking turns reaches either within twice as
// many tasks as the order that suits it.
inline void first_hit_order(const Bvh& bvh, const std::vector<BvttTask>& tasks, std::vector<int32_t>& order) {
    const auto n = static_cast<int32_t>(tasks.size());
    std::vector<int32_t> distant(n), depth(n);
    for (int32_t k = 0; k < n; ++k) {
        distant[k] = k;
        depth[k] = common_ancestor_depth(bvh, tasks[k].a, tasks[k].b);
    }
    std::stable_sort(distant.begin(), distant.end(), [&](int32_t p, int32_t q) { return depth[p] < depth[q]; });
    std::vector<uint8_t> taken(n, 0);
    order.clear();
    for (int32_t i = 0, j = 0; static_cast<int32_t>(order.size()) < n;) {
        while (i < n && taken[i]) ++i;
        if (i < n) {
            taken[i] = 1;
            order.push_back(i);
        }
        while (j < n && taken[distant[j]]) ++j;
        if (j < n) {
            taken[distant[j]] = 1;
            order.push_back(distant[j]);
        }
    }
}

// dcd / ccd(stop_at_first) without a front: the tasks of expand_tasks_by_levels, in first_hit_order, a block
// at a time; each task traverses its part of the BVTT and at once tests its candidates in order
// with find_hit(candidates, outs[k]) (the index of the first colliding one, or their count; outs[k]:
// what the caller keeps of task k's tests, e.g. CCD's contact and counters). The first block
// holding a hit ends the query: the traversal stops there too, not only the tests. Within that
// block the tasks after the hit are skipped once it is found (FirstHitChunk over the block's
// positions: every task before the hit runs to its end), and only the tasks up to the hit count,
// their traversal counters included (each task counts into its own stats), so every counter is
// the same for any thread count. The hit is the first colliding candidate in that order (tasks in
// first_hit_order, each task's candidates in traversal order), and every candidate before it has
// been tested.
template <class Make, class FindHit, class TaskOut>
FirstHit self_collide_until_first_hit(const Bvh& bvh, int threads, const Make& make, const FindHit& find_hit,
                                      std::vector<TaskOut>& outs, DcdStats& stats, ParallelTraversalScratch& s) {
    FirstHit out;
    if (bvh.size() == 0) return out;
    expand_tasks_by_levels(threads, make, kFirstHitTasks, s);
    for (const Padded<DcdStats>& w : s.stats) stats.add_traversal_counters(w.value);  // the expansion's
    const std::vector<BvttTask>& tasks = s.tasks;
    const size_t n = tasks.size();
    first_hit_order(bvh, tasks, s.run_order);
    if (s.candidates.size() < n) s.candidates.resize(n);
    outs.assign(n, TaskOut{});
    std::vector<Padded<DcdStats>> task_stats(n);
    std::vector<int64_t> hit_at(n, 0);
    for (size_t b = 0, e = 0; b < n && !out.found; b = e) {
        e = std::min(n, b + std::max(kFirstHitBlock, b));
        FirstHitChunk first(static_cast<int64_t>(e - b));
        parallel_chunks(static_cast<int64_t>(e - b), threads, [&](int64_t i, int) {
            if (first.skip(i)) return;
            const int32_t k = s.run_order[b + i];
            std::vector<TrianglePair>& c = s.candidates[k].value;
            c.clear();
            make(task_stats[k].value, c, nullptr).run_task(tasks[k]);
            hit_at[k] = find_hit(c, outs[k]);
            if (hit_at[k] < static_cast<int64_t>(c.size())) first.found(i);
        });
        const size_t last = first.get() < static_cast<int64_t>(e - b) ? b + static_cast<size_t>(first.get()) : e - 1;
        for (size_t i = b; i <= last; ++i) {
            const int32_t k = s.run_order[i];
            const std::vector<TrianglePair>& c = s.candidates[k].value;
            stats.add_traversal_counters(task_stats[k].value);
            out.tasks = i + 1;
            if (hit_at[k] < static_cast<int64_t>(c.size())) {
                out.found = true;
                out.pair = c[hit_at[k]];
                out.tests += hit_at[k] + 1;
                break;
            }
            out.tests += static_cast<int64_t>(c.size());
        }
    }
    return out;
}

}  // namespace conecull
