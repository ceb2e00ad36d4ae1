// Abandoning a query's elementary tests when the user asks (Ctrl-C in Python).
//
// The slow queries are slow in their elementary tests (exact CCD on steps where every pair is
// near-degenerate: about 1 ms per pair), and these come last: the refit, the traversal and the
// front are complete by then, so abandoning the tests leaves the collider as a finished query
// would, minus its result (a first-hit query's traversal, which runs with its tests, learns
// nothing either). The bindings point a query at a flag that their SIGINT handler sets; the test
// loops read it every kInterruptStride tests (a first-hit query: before each candidate's tests)
// and stop; the query then throws Interrupted, which the bindings turn into KeyboardInterrupt.
#pragma once

#include <atomic>
#include <cstdint>

namespace conecull {

struct Interrupted {};

inline constexpr int64_t kInterruptStride = 64;  // at ~1 ms per slow test: a reaction within ~0.1 s

// True if `flag` (none: never) is set; read relaxed: a stop a few tests late is as good.
inline bool interrupt_requested(const std::atomic<bool>* flag) {
    return flag && flag->load(std::memory_order_relaxed);
}

}  // namespace conecull
