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

// The entries (and records) of a front: an array like std::vector's, whose append is inline.
// Every entry a query keeps is appended once; std::vector::push_back compiled to an out-of-line
// call through the PLT per entry, and around that opaque call the update loop reloaded the node
// array and its counters from memory (flamenco, perf: the call and its reloads took about a
// fifth of FrontTracking's samples). resize() leaves new items uninitialised: every use
// overwrites them (the parallel traversal's join) or only shrinks.
template <class T>
class FrontArray {
   public:
    FrontArray() = default;
    FrontArray(const FrontArray&) = delete;
    FrontArray& operator=(const FrontArray&) = delete;
    FrontArray(FrontArray&& o) noexcept { swap(o); }
    FrontArray& operator=(FrontArray&& o) noexcept {
        swap(o);
        return *this;
    }
    ~FrontArray() { std::free(data_); }

    size_t size() const { return size_; }
    T* data() { return data_; }
    const T* data() const { return data_; }
    T* begin() { return data_; }
    T* end() { return data_ + size_; }
    const T* begin() const { return data_; }
    const T* end() const { return data_ + size_; }
    T& operator[](size_t i) { return data_[i]; }
    const T& operator[](size_t i) const { return data_[i]; }
    T& back() { return data_[size_ - 1]; }

    [[gnu::always_inline]] void push_back(const T& e) {
        if (__builtin_expect(size_ == capacity_, 0)) grow(size_ + 1);
        data_[size_++] = e;
    }
    void clear() { size_ = 0; }
    void resize(size_t n) {
        if (n > capacity_) grow(n);
        size_ = n;
    }
    void swap(FrontArray& o) {
        std::swap(data_, o.data_);
        std::swap(size_, o.size_);
        std::swap(capacity_, o.capacity_);
    }

   private:
    [[gnu::noinline]] void grow(size_t at_least) {
        const size_t cap = std::max<size_t>({at_least, 2 * capacity_, 1024});
        void* p = std::realloc(data_, cap * sizeof(T));
        if (!p) throw std::bad_alloc();
        data_ = static_cast<T*>(p);
        capacity_ = cap;
    }
    T* data_ = nullptr;
    size_t size_ = 0, capacity_ = 0;
};
static_assert(std::is_trivially_copyable_v<FrontEntry>, "FrontArray moves items with realloc");
using FrontEntries = FrontArray<FrontEntry>;

// The record of Front_X kept between queries: where its entries are (if tracked) and its churn
// state. One per node the last query visited, none for the others: a culled region keeps
// neither entries nor records (the memory Alg. 4 saves, Sec. 4).
struct FrontSegment {
    int64_t begin;    // Front_X is entries[begin, begin + count) (a task's part: relative to it)
    int32_t node;     // X
    int32_t count;    // 0 unless tracked
    uint8_t tracked;  // 1: Front_X was kept; 0: X rested or churned (Collide from the top, nothing kept)
    uint8_t rest;     // queries X has left to rest
    uint8_t backoff;  // log2 of X's next rest
};
static_assert(sizeof(FrontSegment) == 24, "front_bytes (stats.hpp) counts 24 bytes per record");
static_assert(std::is_trivially_copyable_v<FrontSegment>, "FrontArray moves items with realloc");
using FrontSegments = FrontArray<FrontSegment>;

// Sub-segments built one after another (by a query, or by one task of the parallel traversal),
// with their records in the same order.
struct FrontPart {
    FrontEntries entries;
    FrontSegments segments;
    void clear() {
        entries.clear();
        segments.clear();
    }
};

struct BvttFront {
    // The sub-segments tracked by the last query, one after another in traversal order, and a
    // record per node it visited, in the same order. Front_X is the entries of X's record if
    // it is tracked. Nothing else is kept: a culled region keeps no front and no record (the
    // memory Alg. 4 saves) and is rebuilt from the top when it is not culled again.
    FrontEntries entries;
    FrontSegments segments;
    // X -> its record in `segments`, valid only if that record's node is X. Each query writes the
    // slots of the nodes it visits, so a stale slot points past the records or at another
    // node's: a node the last query did not visit has no record. Sized on the first query.
    std::vector<int32_t> slot;

    // Churn. Any cut gives Collide's candidates, but one far from the new pose costs more to
    // update than Collide from the top would (a real step's two end poses queried in turn: 82%
    // of armadillo's entries new each query). Then X rests: Collide(X->left, X->right) runs from
    // the top, as in Alg. 2, with nothing recorded, for 1, 2, 4, 8, then 16 queries after
    // successive churning updates (back to 1 after one that pays); then it is rebuilt from the
    // top and tracked again. The state lives in X's record, so a node that drops out of the
    // traversal (culled above) starts afresh. Each X is touched by its own FrontTracking task
    // only, so the policy is the same for any thread count.
    static constexpr uint8_t kMaxBackoff = 4;

    // An update of Front_X that did `spent` box tests and ended with `kept` entries: true if it
    // churned, and X rests from the next query. Collide from the top visits a full binary tree
    // of BVTT nodes whose leaves form the highest cut, which every cut refines, so it does at
    // most 2 kept - 1 tests: more than that and the front cost more than it saved.
    static bool churned(FrontSegment& x, int64_t spent, int64_t kept) {
        if (spent <= 2 * kept - 1) {
            x.backoff = 0;
            return false;
        }
        x.rest = static_cast<uint8_t>(1u << x.backoff);
        if (x.backoff < kMaxBackoff) ++x.backoff;
        return true;
    }

    // Being built by the current query: the new sub-segments and records. The parallel
    // traversal builds one such part per task (begin relative to the part) and concatenates
    // them here.
    FrontPart next;

    // X's record from the last query, or null if it did not visit X.
    const FrontSegment* record(int32_t x) const {
        if (static_cast<size_t>(x) >= slot.size()) return nullptr;
        const int32_t s = slot[x];
        if (s < 0 || static_cast<size_t>(s) >= segments.size() || segments[s].node != x) return nullptr;
        return &segments[s];
    }

    // Start of a query on `bvh`: the slots sized (a collider without a front method never
    // allocates them), the part being built empty.
    void prepare(const Bvh& bvh) {
        if (slot.size() != bvh.nodes.size()) {
            slot.assign(bvh.nodes.size(), -1);
            entries.clear();
            segments.clear();
        }
        next.clear();
    }

    // A fresh front (a new BVH, or a query that threw): nothing tracked, the memory released.
    void reset() {
        FrontEntries().swap(entries);
        FrontEntries().swap(next.entries);
        FrontSegments().swap(segments);
        FrontSegments().swap(next.segments);
        std::vector<int32_t>().swap(slot);
    }

    // End of a query, `next` built and stats.front_added summed: the new front replaces the old.
    // front_bytes counts all the front keeps for the next query: entries, records and slots.
    void finish_query(DcdStats& stats) {
        const auto kept = static_cast<int64_t>(next.entries.size());
        stats.front_removed = static_cast<int64_t>(entries.size()) + stats.front_added - kept;
        entries.swap(next.entries);
        segments.swap(next.segments);
        stats.front_entries = kept;
        stats.front_segments = static_cast<int64_t>(segments.size());
        stats.front_bytes = kept * static_cast<int64_t>(sizeof(FrontEntry)) +
                            stats.front_segments * static_cast<int64_t>(sizeof(FrontSegment)) +
                            static_cast<int64_t>(slot.size() * sizeof(int32_t));
    }

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
