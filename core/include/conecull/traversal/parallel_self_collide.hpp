// SelfCollide(root) on several threads, with exactly the serial traversal's candidates, in the
// serial order, and its counters.
//
// Alg. 2 is a depth-first recursion whose output is the concatenation of its children's:
// SelfCollide(N) = SelfCollide(L) + SelfCollide(R) + Collide(L, R), and Collide(A, B) likewise
// over the two halves of the larger node. So the top of the BVTT is expanded, level by level
// and in place, into an ordered list of independent tasks (each step doing the cone / box test
// the recursion would do there), until there are enough to keep every thread busy; the tasks
// then run on any thread, each into its own buffer, and the buffers are concatenated in task
// order. Counters are sums, kept per worker and added up. Methods with a BVTT front traverse
// serially: their front is one array appended in traversal order (bvtt_front.hpp).
#pragma once

#include <cstdint>
#include <vector>

#include "conecull/parallel.hpp"
#include "conecull/traversal/self_collide.hpp"

namespace conecull {

// Buffers reused between queries.
struct ParallelTraversalScratch {
    std::vector<BvttTask> tasks, expanded;
    std::vector<std::vector<TrianglePair>> candidates;  // per task
    std::vector<DcdStats> stats;                        // per worker
};

// make(stats, candidates) constructs a SelfCollideTraversal (no front) writing to them.
template <class Make>
void parallel_self_collide(const Bvh& bvh, int threads, const Make& make, DcdStats& stats,
                           std::vector<TrianglePair>& candidates, ParallelTraversalScratch& s) {
    candidates.clear();
    if (bvh.size() == 0) return;
    std::vector<BvttTask>& tasks = s.tasks;
    tasks.assign(1, BvttTask{0, -1});
    {
        auto top = make(stats, candidates);  // expand() emits nothing
        const size_t enough = 16 * static_cast<size_t>(threads);
        bool expandable = true;
        while (expandable && tasks.size() < enough) {
            s.expanded.clear();
            expandable = false;
            for (const BvttTask& t : tasks) expandable |= top.expand(t, s.expanded);
            tasks.swap(s.expanded);
        }
    }
    const size_t n = tasks.size();
    if (s.candidates.size() < n) s.candidates.resize(n);
    s.stats.assign(threads, DcdStats{});
    parallel_chunks(static_cast<int64_t>(n), threads, [&](int64_t k, int w) {
        s.candidates[k].clear();
        make(s.stats[w], s.candidates[k]).run_task(tasks[k]);
    });
    for (const DcdStats& w : s.stats) stats.add_traversal_counters(w);
    concat_in_order(s.candidates, n, threads, candidates);
}

}  // namespace conecull
