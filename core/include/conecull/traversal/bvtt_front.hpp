// The BVTT front of Sec. 4 (Fig. 5), kept by the collider between queries: one sub-segment
// Front_X per internal BVH node X, a cut of the BVTT of Collide(X->left, X->right).
//
// What makes any cut exact: every pair of leaves (one under X->left, one under X->right) lies
// below exactly one entry, and a parent's box is the union of its children's boxes, so an entry
// whose boxes are apart has no overlapping pair of leaves below it. Resuming Collide from the
// entries (descending the overlapping ones) therefore finds exactly the candidates of
// Collide(X->left, X->right) from the top, however stale the cut is; the cut only decides how
// much work that takes. This is why fronts need no invalidation for correctness, not even when
// the motion between queries is large.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include "conecull/bvh/bvh.hpp"
#include "conecull/traversal/stats.hpp"

namespace conecull {

// How one query's FrontTracking(Front_X) (Alg. 4 line 13) went, for its trace event: resumed from
// the front the last query left; built from the top (none was kept); Collide from the top,
// unrecorded, because X rests after churning; or resumed but churned, so dropped (X rests).
enum class FrontMode : uint8_t { kResumed = 0, kFromTop = 1, kResting = 2, kChurned = 3 };

// A BVTT node A * B: BVH nodes with disjoint triangle sets (A under X->left, B under X->right).
struct FrontEntry {
    int32_t a, b;
};

// The entries of a front: an array like std::vector's, whose append is inline. Every entry a
// query keeps is appended once; std::vector::push_back compiled to an out-of-line call through
// the PLT per entry, and around that opaque call the update loop reloaded the node array and
// its counters from memory (flamenco, perf: the call and its reloads took about a fifth of
// FrontTracking's samples). resize() leaves new entries uninitialised: every use overwrites
// them (the parallel traversal's join) or only shrinks.
class FrontEntries {
   public:
    FrontEntries() = default;
    FrontEntries(const FrontEntries&) = delete;
    FrontEntries& operator=(const FrontEntries&) = delete;
    FrontEntries(FrontEntries&& o) noexcept { swap(o); }
    FrontEntries& operator=(FrontEntries&& o) noexcept {
        swap(o);
        return *this;
    }
    ~FrontEntries() { std::free(data_); }

    size_t size() const { return size_; }
    FrontEntry* data() { return data_; }
    const FrontEntry* data() const { return data_; }
    FrontEntry* begin() { return data_; }
    FrontEntry* end() { return data_ + size_; }
    const FrontEntry* begin() const { return data_; }
    const FrontEntry* end() const { return data_ + size_; }
    FrontEntry& operator[](size_t i) { return data_[i]; }
    const FrontEntry& operator[](size_t i) const { return data_[i]; }
    FrontEntry& back() { return data_[size_ - 1]; }

    [[gnu::always_inline]] void push_back(FrontEntry e) {
        if (__builtin_expect(size_ == capacity_, 0)) grow(size_ + 1);
        data_[size_++] = e;
    }
    void clear() { size_ = 0; }
    void resize(size_t n) {
        if (n > capacity_) grow(n);
        size_ = n;
    }
    void swap(FrontEntries& o) {
        std::swap(data_, o.data_);
        std::swap(size_, o.size_);
        std::swap(capacity_, o.capacity_);
    }

   private:
    [[gnu::noinline]] void grow(size_t at_least) {
        const size_t cap = std::max<size_t>({at_least, 2 * capacity_, 1024});
        void* p = std::realloc(data_, cap * sizeof(FrontEntry));
        if (!p) throw std::bad_alloc();
        data_ = static_cast<FrontEntry*>(p);
        capacity_ = cap;
    }
    FrontEntry* data_ = nullptr;
    size_t size_ = 0, capacity_ = 0;
};
static_assert(std::is_trivially_copyable_v<FrontEntry>, "FrontEntries moves entries with realloc");

// Sub-segments built one after another (by a query, or by one task of the parallel traversal).
struct FrontPart {
    FrontEntries entries;
    std::vector<int32_t> nodes;  // parallel traversal only: X with begin[X] into `entries`
    void clear() {
        entries.clear();
        nodes.clear();
    }
};

struct BvttFront {
    // The sub-segments tracked by the last query, one after another in traversal order; Front_X
    // is entries[begin[X], begin[X] + count[X]) if tracked[X] == query, i.e. X was visited and
    // not culled by the last query. Nothing else is kept: a culled region keeps no front (the
    // memory Alg. 4 saves) and is rebuilt from the top when it is not culled again.
    FrontEntries entries;
    std::vector<int64_t> begin;
    std::vector<int32_t> count;
    std::vector<uint64_t> tracked;
    uint64_t query = 0;  // queries answered with this front (so 0: never tracked)

    // Churn. Any cut gives Collide's candidates, but one far from the new pose costs more to
    // update than Collide from the top would (a real step's two end poses queried in turn: 82%
    // of armadillo's entries new each query). Then X rests: Collide(X->left, X->right) runs from
    // the top, as in Alg. 2, with nothing recorded, for 1, 2, 4, 8, then 16 queries after
    // successive churning updates (back to 1 after one that pays); then it is rebuilt from the
    // top and tracked again. Each X is touched by its own FrontTracking task only, so the
    // policy is the same for any thread count.
    std::vector<uint8_t> rest;     // queries X has left to rest
    std::vector<uint8_t> backoff;  // log2 of X's next rest
    static constexpr uint8_t kMaxBackoff = 4;

    // An update of Front_X that did `spent` box tests and ended with `kept` entries: true if it
    // churned, and X rests from the next query. Collide from the top visits a full binary tree
    // of BVTT nodes whose leaves form the highest cut, which every cut refines, so it does at
    // most 2 kept - 1 tests: more than that and the front cost more than it saved.
    bool churned(int32_t x, int64_t spent, int64_t kept) {
        if (spent <= 2 * kept - 1) {
            backoff[x] = 0;
            return false;
        }
        rest[x] = static_cast<uint8_t>(1u << backoff[x]);
        if (backoff[x] < kMaxBackoff) ++backoff[x];
        return true;
    }

    // Being built by the current query: the new sub-segments. The parallel traversal builds one
    // such part per task (`nodes`: the X whose begin[X] is relative to the part) and
    // concatenates them here.
    FrontPart next;

    void reset(const Bvh& bvh) {
        entries.clear();
        begin.assign(bvh.nodes.size(), 0);
        count.assign(bvh.nodes.size(), 0);
        tracked.assign(bvh.nodes.size(), 0);
        rest.assign(bvh.nodes.size(), 0);
        backoff.assign(bvh.nodes.size(), 0);
        query = 0;
    }

    // End of a query, `next` built and stats.front_added summed: the new front replaces the old.
    void finish_query(DcdStats& stats) {
        const auto kept = static_cast<int64_t>(next.entries.size());
        stats.front_removed = static_cast<int64_t>(entries.size()) + stats.front_added - kept;
        entries.swap(next.entries);
        ++query;
        stats.front_entries = kept;
        stats.front_bytes = kept * static_cast<int64_t>(sizeof(FrontEntry));
    }

    bool is_tracked(int32_t x) const { return query > 0 && tracked[x] == query; }

    // The BVTT node whose children are the sibling entries e1, e2 (e1 the left one), if they are
    // siblings: (p, b) for the parent p of e1.a, e2.a, or (a, q) for the parent q of e1.b, e2.b.
    // Left children are parent + 1 in the pre-order BVH. Merging them keeps the cut a cut.
    static bool parent_of(const Bvh& bvh, FrontEntry e1, FrontEntry e2, FrontEntry& parent) {
        if (e1.b == e2.b && bvh.nodes[e1.a - 1].right == e2.a) {
            parent = {e1.a - 1, e1.b};
            return true;
        }
        if (e1.a == e2.a && bvh.nodes[e1.b - 1].right == e2.b) {
            parent = {e1.a, e1.b - 1};
            return true;
        }
        return false;
    }
};

}  // namespace conecull
