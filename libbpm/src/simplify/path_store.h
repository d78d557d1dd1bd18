#pragma once
// The paths of the original edges over the coarse surface while it is simplified
// (Embedding::path): per original edge, the coarse edges it crosses, in order from its
// smaller vertex to its larger. Internal to libbpm.
//
// Why not a std::vector<Crossing> per edge: most paths are short (none to a few
// crossings); at the end of the removals, the peak of a run, vectors were 7.5 MB of
// headers for 3.4 MB of crossings (208k-triangle input to 10k vertices). Here an edge has
// 8 bytes (where its crossings start, how many) and the crossings live in a BlockPool
// (core/block_pool.h), a block of the smallest power-of-two capacity per path.
//
// Contract: a path's crossings stay where they are until that path is assigned again
// (assigning one path moves no other), as with a vector per edge, so a reader may hold
// ranges of several paths. The placement depends only on the sequence of assignments
// (deterministic); no result ever depends on it. assign() must not run while another
// thread reads (the simplifier writes paths only between its planning rounds).

#include <cstdint>
#include <vector>

#include "core/block_pool.h"
#include "core/const_range.h"

namespace bpm::detail {

// Where an original edge crosses a coarse edge.
struct Crossing {
    int32_t a, b;  // the coarse edge, a < b
    double s;      // position on the coarse edge, from a to b, in (0,1)
    double sigma;  // position on the original edge, from its smaller vertex to its larger, in (0,1)
};

class PathStore {
public:
    // `edges` paths, all empty; frees what was held before.
    void reset(size_t edges);
    // Frees everything; size() is 0 after it.
    void release();
    size_t size() const { return slots_.size(); }
    bool empty() const { return slots_.empty(); }

    // The crossings of path e (valid until path e is assigned again, or reset/release).
    ConstRange<Crossing> operator[](size_t e) const {
        const Slot s = slots_[e];
        if (s.size == 0) return {};
        const Crossing* p = address(s.block);
        return {p, p + s.size};
    }
    // Makes path e the `n` crossings at `crossings` (which must not lie in this store).
    void assign(size_t e, const Crossing* crossings, size_t n);
    // The number of crossings over all paths.
    size_t total_crossings() const;
    // Room for crossings in the pool, in use or free (what the store costs beside its
    // 8 bytes per path).
    size_t reserved_crossings() const { return pool_.reserved(); }

    // Cache hints, no effect on any result: the slot of path e, and its crossings (the
    // slot must have been read or asked for first, or this waits for it).
    void prefetch_slot(size_t e) const { __builtin_prefetch(slots_.data() + e); }
    void prefetch_crossings(size_t e) const {
        const Slot s = slots_[e];
        if (s.size != 0) __builtin_prefetch(address(s.block));
    }

private:
    struct Slot {
        uint32_t block = 0;  // in pool_, when size > 0
        uint32_t size = 0;
    };
    const Crossing* address(uint32_t block) const { return pool_.at(block); }

    std::vector<Slot> slots_;  // per original edge
    BlockPool<Crossing> pool_;
};

}  // namespace bpm::detail
