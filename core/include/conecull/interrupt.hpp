// Abandoning a query when the user asks (Ctrl-C in Python).
//
// A query is slow where it does much of one thing: elementary tests (exact CCD on steps where
// every pair is near-degenerate: about 1 ms per pair; DCD on a mesh crumpled onto itself: tens of
// millions of pairs at ~60 ns), or a traversal emitting that many candidates. The bindings point
// a query at a flag that their SIGINT handler sets; the loops read it every kInterruptStride CCD
// tests (a first-hit query: before each candidate's tests), every kDcdInterruptStride DCD tests,
// and every few dozen candidates the traversal emits (SelfCollideTraversal::flush), and stop; the
// query then throws Interrupted, which the bindings turn into KeyboardInterrupt. The collider
// forgets its front and learnt test order, as after any exception out of a query (the front may
// have been half rebuilt; SelfCollider::forget): the next query answers as a fresh collider's.
#pragma once

#include <atomic>
#include <cstdint>

namespace conecull {

struct Interrupted {};

inline constexpr int64_t kInterruptStride = 64;  // at ~1 ms per slow test: a reaction within ~0.1 s
inline constexpr int64_t kDcdInterruptStride = 4096;  // a power of 2; at ~60 ns per test: ~0.25 ms

// True if `flag` (none: never) is set; read relaxed: a stop a few tests late is as good.
inline bool interrupt_requested(const std::atomic<bool>* flag) {
    return flag && flag->load(std::memory_order_relaxed);
}

}  // namespace conecull
