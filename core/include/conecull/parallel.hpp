// A deterministic parallel-for on std::thread (no OpenMP, no dependency).
//
// The work is cut into chunks by the caller, independently of the timing; workers take chunks
// in turn from an atomic counter (load balance), and every chunk writes only its own output
// slot, which the caller then concatenates in chunk order. Results therefore never depend on
// which thread ran which chunk, nor on how many threads there were.
//
// The helpers are a process-wide pool, started on first use. A region never waits for a helper
// that has not started on it: the caller works through the chunks too, then closes the region
// and waits only for the helpers that joined. On a busy machine a helper that is not scheduled
// in time costs nothing (the caller does its share). A forked child gets a fresh pool: it has
// none of the parent's threads, and a mutex one of them held at the fork would stay locked.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <pthread.h>
#include <system_error>
#include <thread>
#include <vector>

#include "conecull/interrupt.hpp"

namespace conecull {

// threads <= 0: all cores.
inline int resolve_threads(int threads) {
    if (threads > 0) return threads;
    const unsigned hw = std::thread::hardware_concurrency();
    return hw > 0 ? static_cast<int>(hw) : 1;
}

// Busy-waits (with the CPU's spin-wait hint) until ready() or `limit` has passed; ready()'s value.
template <class Ready>
bool spin_until(const Ready& ready, std::chrono::microseconds limit) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 1;; ++i) {
        if (ready()) return true;
#if defined(__x86_64__) || defined(__i386__)
        __builtin_ia32_pause();
#elif defined(__aarch64__)
        asm volatile("yield");
#endif
        if ((i & 63) == 0 && std::chrono::steady_clock::now() - t0 > limit) return ready();
    }
}

class ThreadPool {
   public:
    static ThreadPool& instance() {
        static const bool registered = [] {
            current() = new ThreadPool;  // never destroyed: its threads are detached
            // In a forked child (one thread, the forking one) the parent's pool is abandoned as it
            // is, its mutexes perhaps locked by helpers that do not exist there.
            pthread_atfork(nullptr, nullptr, [] { current() = new ThreadPool; });
            return true;
        }();
        (void)registered;
        return *current();
    }

    // work(worker) on the caller (worker 0) and on up to n_workers - 1 helpers (workers 1, ...);
    // returns when the caller's call and every helper's call that started have returned. One
    // region at a time: a caller finding the pool busy (another query on another thread) gets
    // no helpers.
    template <class Work>
    void run(int n_workers, const Work& work) {
        std::unique_lock<std::mutex> busy(busy_, std::try_to_lock);
        if (n_workers <= 1 || !busy.owns_lock()) {
            work(0);
            return;
        }
        grow(n_workers - 1);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            fn_ = [](const void* ctx, int w) { (*static_cast<const Work*>(ctx))(w); };
            ctx_ = &work;
            max_workers_ = n_workers;
            next_worker_ = 1;
            open_ = true;
            region_.fetch_add(1, std::memory_order_release);  // seen by spinning helpers
        }
        wake_.notify_all();  // and sleeping ones
        run_below_gap(work);  // the caller is worker 0
        {
            std::lock_guard<std::mutex> lock(mutex_);
            open_ = false;  // late helpers stay out
        }
        // The helpers that joined are finishing their last chunk: wait for them spinning first.
        if (!spin_until([&] { return active_.load(std::memory_order_acquire) == 0; }, kSpin)) {
            std::unique_lock<std::mutex> lock(mutex_);
            done_.wait(lock, [&] { return active_.load(std::memory_order_acquire) == 0; });
        }
    }

    // Wakes sleeping helpers (starting them if needed) so that they spin, ready for a region,
    // for up to kSpin; returns at once. A query calls it before its input checks: a helper
    // asleep since the last query otherwise joins the query's first region (the refit) tens to
    // hundreds of microseconds late in this VM (measured: median 31 us, 90th percentile 585 us,
    // and in 9 of 112 refits not at all), and the caller sweeps alone meanwhile.
    void prewake(int n_workers) {
        if (n_workers <= 1) return;
        std::unique_lock<std::mutex> busy(busy_, std::try_to_lock);
        if (!busy.owns_lock()) return;  // a region is running: its helpers are awake
        grow(n_workers - 1);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            ++pokes_;
        }
        wake_.notify_all();
    }

   private:
    // work(0) on the caller, its stack frames at least 256 bytes below those of the region's
    // callers. Helpers read what a region captures by reference from those frames (a pointer to
    // the nodes, the positions, a counter bound) all through it, while the caller writes its own
    // deeper frames (spilled locals) all the time; without the gap the two could share a cache
    // line, depending on where ASLR put the stack, and every write took the line from the
    // helper's core. Measured: a 64K-triangle boxes-only refit on 2 threads took 1.2-2.7 ms in
    // some processes and 0.6 ms in others (0.9 ms on 1 thread); with the gap, 0.6 ms in all.
    // 256 bytes: two pairs of lines, beyond the adjacent-line prefetcher's 128-byte pairs.
    // The gap is taken off the stack pointer (alloca), so the work's frame, of its own (not
    // inlined: its spills could then sit anywhere in this frame), lies below it; the asm
    // statements keep the gap and forbid a tail call, which would free it first.
    template <class Work>
    [[gnu::noinline]] static void run_below_gap(const Work& work) {
        void* gap = __builtin_alloca(256);
        asm volatile("" : : "r"(gap) : "memory");
        run_worker0(work);
        asm volatile("" : : "r"(gap) : "memory");
    }
    template <class Work>
    [[gnu::noinline]] static void run_worker0(const Work& work) {
        work(0);
    }

    static ThreadPool*& current() {
        static ThreadPool* pool = nullptr;
        return pool;
    }

    // How long an idle helper spins before it sleeps. A query runs several regions separated by
    // short serial steps, and waking a sleeping thread costs tens of microseconds, more in a VM
    // whose idle vCPU halts (measured here: median 22 us after 1 ms asleep, 62 us after 10 ms,
    // and ~30% of 0.6 ms regions ended before the helper arrived); a spinning helper joins
    // within ~1 us. Spinning costs at most this much CPU after each region.
    static constexpr std::chrono::microseconds kSpin{200};

    void grow(int helpers) {
        std::lock_guard<std::mutex> lock(mutex_);
        while (n_threads_ < helpers) {
            try {
                std::thread([this] { loop(); }).detach();
            } catch (const std::system_error&) {
                return;  // no more threads to be had: fewer helpers
            }
            ++n_threads_;
        }
    }

    void loop() {
        uint64_t seen = 0, pokes_seen = 0;
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            if (region_.load(std::memory_order_relaxed) == seen) {
                lock.unlock();
                spin_until([&] { return region_.load(std::memory_order_acquire) != seen; }, kSpin);
                lock.lock();
                wake_.wait(lock, [&] { return region_.load(std::memory_order_relaxed) != seen || pokes_ != pokes_seen; });
                if (pokes_ != pokes_seen && region_.load(std::memory_order_relaxed) == seen) {
                    pokes_seen = pokes_;  // woken by prewake: spin again, then sleep
                    continue;
                }
                pokes_seen = pokes_;
            }
            seen = region_.load(std::memory_order_relaxed);
            if (!open_ || next_worker_ >= max_workers_) continue;  // closed or full: the next one
            const int w = next_worker_++;
            active_.fetch_add(1, std::memory_order_relaxed);
            void (*fn)(const void*, int) = fn_;
            const void* ctx = ctx_;
            lock.unlock();
            fn(ctx, w);
            lock.lock();
            // Under the lock: a caller that saw active_ > 0 sleeps only once it holds it.
            if (active_.fetch_sub(1, std::memory_order_acq_rel) == 1) done_.notify_all();
        }
    }

    std::mutex busy_;   // held by the caller of the current region
    std::mutex mutex_;  // guards the fields below (region_ and active_ are also read without it)
    std::condition_variable wake_, done_;
    void (*fn_)(const void*, int) = nullptr;
    const void* ctx_ = nullptr;
    int max_workers_ = 0, next_worker_ = 0, n_threads_ = 0;
    uint64_t pokes_ = 0;  // prewake calls
    std::atomic<int> active_{0};
    bool open_ = false;
    std::atomic<uint64_t> region_{0};
};

// Calls body(chunk, worker) once for every chunk in [0, n_chunks), on up to `threads` threads;
// worker ids are < threads. With one thread (or one chunk) the chunks run in order on the
// caller. The first exception of any chunk is rethrown here.
//
// The chunks are cut into one block per worker; a worker takes the chunks of its own block in
// order, then helps with the others'. Neighbouring chunks touch neighbouring data (subtrees of
// the BVH, runs of candidates), which so stays in one core's cache: each core here has its own
// 2 MB L2 and a miss costs ~150 ns: with the chunks handed out alternately, each of two
// threads took ~1.5x as long for its half of the "aabb+front" traversal tasks as one thread
// alone (measured on the 64K-triangle benchmark).
template <class Body>
void parallel_chunks(int64_t n_chunks, int threads, const Body& body) {
    const int n_workers = static_cast<int>(std::min<int64_t>(std::max(threads, 1), n_chunks));
    if (n_workers <= 1) {
        for (int64_t c = 0; c < n_chunks; ++c) body(c, 0);
        return;
    }
    struct alignas(64) Block {
        std::atomic<int64_t> next{0};
        int64_t end = 0;
    };
    std::unique_ptr<Block[]> blocks(new Block[n_workers]);
    for (int w = 0; w < n_workers; ++w) {
        blocks[w].next.store(n_chunks * w / n_workers, std::memory_order_relaxed);
        blocks[w].end = n_chunks * (w + 1) / n_workers;
    }
    std::vector<std::exception_ptr> errors(n_workers);
    ThreadPool::instance().run(n_workers, [&](int w) {
        try {
            for (int j = 0; j < n_workers; ++j) {
                Block& b = blocks[(w + j) % n_workers];
                for (int64_t c; (c = b.next.fetch_add(1, std::memory_order_relaxed)) < b.end;) body(c, w);
            }
        } catch (...) {
            errors[w] = std::current_exception();
            for (int k = 0; k < n_workers; ++k) blocks[k].next.store(blocks[k].end);  // the others stop soon
        }
    });
    for (const std::exception_ptr& e : errors)
        if (e) std::rethrow_exception(e);
}

// A region that stops at its first hit in chunk order: the lowest chunk known to hold a hit.
// A chunk above it is skipped; a chunk below the final value never is (the value only falls),
// so every chunk before the first chunk with a hit runs to its end, and what the chunks up to
// it hold does not depend on the threads. Later chunks that ran anyway are to be ignored.
class FirstHitChunk {
   public:
    explicit FirstHitChunk(int64_t none) : k_(none) {}
    bool skip(int64_t chunk) const { return chunk > k_.load(std::memory_order_relaxed); }
    void found(int64_t chunk) {
        for (int64_t k = k_.load(); chunk < k && !k_.compare_exchange_weak(k, chunk);) {
        }
    }
    int64_t get() const { return k_.load(); }

   private:
    std::atomic<int64_t> k_;
};

// [0, n) cut into chunks of at least `grain` items (one chunk for one thread), many per thread
// so that uneven chunks even out: the region ends when its last chunk does, so a thread left
// with one chunk of 1/16 of the work idles the other for up to that long (the CCD tests' cost
// per pair varies 100-fold).
struct Chunks {
    int64_t n = 0, size = 1, count = 0;
    Chunks(int64_t n_items, int threads, int64_t grain) : n(n_items) {
        if (n <= 0) return;
        const int64_t want = threads <= 1 ? 1 : std::min<int64_t>(32 * static_cast<int64_t>(threads), (n + grain - 1) / grain);
        size = (n + want - 1) / want;
        count = (n + size - 1) / size;
    }
    int64_t begin(int64_t c) const { return c * size; }
    int64_t end(int64_t c) const { return std::min(n, (c + 1) * size); }
};

// body(i) for every i in [0, n): for loops whose iteration i writes only slot i.
template <class Body>
void parallel_for(int64_t n, int threads, int64_t grain, const Body& body) {
    const Chunks ch(n, threads, grain);
    parallel_chunks(ch.count, threads, [&](int64_t c, int) {
        for (int64_t i = ch.begin(c), e = ch.end(c); i < e; ++i) body(i);
    });
}

// A value on its own cache lines. Per-worker counters and per-chunk output vectors are written
// all the time by different threads; side by side in an array, neighbours would share a line
// and every increment or push_back would steal it from the other core (false sharing).
template <class T>
struct alignas(64) Padded {
    T value;
};

// out = parts[0] + parts[1] + ... + parts[n_parts - 1], copied in parallel.
template <class T>
void concat_in_order(const std::vector<Padded<std::vector<T>>>& parts, size_t n_parts, int threads, std::vector<T>& out) {
    std::vector<size_t> offset(n_parts + 1, 0);
    for (size_t k = 0; k < n_parts; ++k) offset[k + 1] = offset[k] + parts[k].value.size();
    out.resize(offset[n_parts]);
    T* dst = out.data();
    parallel_chunks(static_cast<int64_t>(n_parts), offset[n_parts] < (1u << 16) ? 1 : threads, [&](int64_t k, int) {
        std::copy(parts[k].value.begin(), parts[k].value.end(), dst + offset[k]);
    });
}

// std::sort(v) on up to `threads` threads: slices sorted in parallel, then merged pairwise. For
// element types whose equal elements are identical (pairs of ints, integers), the result is
// std::sort's, whatever the thread count. An interruptible sort (`interrupt` given, interrupt.hpp)
// is cut into slices of ~2^20 elements whatever the threads, and looks at the flag before each
// slice and each merge (throws Interrupted): the pairs of a mesh crumpled onto itself take
// seconds to sort. Only then: slices and merges cost 4-12% more than std::sort on 14M pairs.
template <class T>
void parallel_sort(std::vector<T>& v, int threads, const std::atomic<bool>* interrupt = nullptr) {
    constexpr size_t kSlice = size_t{1} << 20;
    const size_t n = v.size();
    const size_t parts = std::max<size_t>(std::min<size_t>(std::max(threads, 1), 8), interrupt ? n / kSlice : 0);
    if (parts <= 1 || n < (1u << 13)) {
        std::sort(v.begin(), v.end());
        return;
    }
    const auto look = [interrupt] {
        if (interrupt_requested(interrupt)) throw Interrupted{};
    };
    std::vector<size_t> at(parts + 1);
    for (size_t k = 0; k <= parts; ++k) at[k] = n * k / parts;
    parallel_chunks(static_cast<int64_t>(parts), threads, [&](int64_t k, int) {
        look();
        std::sort(v.begin() + at[k], v.begin() + at[k + 1]);
    });
    for (size_t width = 1; width < parts; width *= 2) {  // merge neighbouring runs
        const size_t pairs = (parts + 2 * width - 1) / (2 * width);
        parallel_chunks(static_cast<int64_t>(pairs), threads, [&](int64_t p, int) {
            look();
            const size_t lo = 2 * width * static_cast<size_t>(p), mid = std::min(lo + width, parts),
                         hi = std::min(lo + 2 * width, parts);
            if (mid < hi) std::inplace_merge(v.begin() + at[lo], v.begin() + at[mid], v.begin() + at[hi]);
        });
    }
}

}  // namespace conecull
