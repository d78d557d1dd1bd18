#pragma once
// The paths of the original edges over the coarse surface while it is simplified
// (Embedding::path): per original edge, the coarse edges it crosses, in order from its
// smaller vertex to its larger. Internal to libbpm.
//
// Why not a std::vector<Crossing> per edge: most paths are short (none to a few
// crossings), and a vector is a 24-byte header per original edge plus a heap block per
// non-empty path (a malloc header, the capacity it once grew to, kept when the path
// shrinks or empties). At the end of the removals, the peak of a run, that was 7.5 MB of
// headers for 3.4 MB of crossings (208k-triangle input to 10k vertices). Here an edge
// has 8 bytes (where its crossings start, how many), and the crossings live in blocks of
// power-of-two capacity cut from large chunks; a block a path gives up goes onto the free
// list of its capacity and is the next block of that capacity handed out.
//
// Contract: a path's crossings stay where they are until that path is assigned again
// (assigning one path moves no other), as with a vector per edge, so a reader may hold
// ranges of several paths. The placement depends only on the sequence of assignments
// (deterministic); no result ever depends on it. assign() must not run while another
// thread reads (the simplifier writes paths only between its planning rounds).

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

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
    // Room for crossings in the chunks, in use or free (what the store costs beside its
    // 8 bytes per path).
    size_t reserved_crossings() const { return reserved_; }

    // Cache hints, no effect on any result: the slot of path e, and its crossings (the
    // slot must have been read or asked for first, or this waits for it).
    void prefetch_slot(size_t e) const { __builtin_prefetch(slots_.data() + e); }
    void prefetch_crossings(size_t e) const {
        const Slot s = slots_[e];
        if (s.size != 0) __builtin_prefetch(address(s.block));
    }

private:
    // A block's address: chunk index << kChunkBits | position in the chunk. A chunk holds
    // 2^kChunkBits crossings (384 KB); a block larger than that gets a chunk of its own
    // (position 0). 32 bits address 2^32 crossings (96 GB) in all.
    static constexpr uint32_t kChunkBits = 14;
    static constexpr uint32_t kChunkSize = uint32_t(1) << kChunkBits;
    struct Slot {
        uint32_t block = 0;  // address of the first crossing, when size > 0
        uint32_t size = 0;
    };
    const Crossing* address(uint32_t block) const {
        return chunks_[block >> kChunkBits].get() + (block & (kChunkSize - 1));
    }
    Crossing* address(uint32_t block) { return chunks_[block >> kChunkBits].get() + (block & (kChunkSize - 1)); }
    // A block of 2^capacity_bits crossings, from its free list or cut anew.
    uint32_t take_block(int capacity_bits);
    // Opens a chunk of `size` crossings; returns its address.
    uint32_t add_chunk(size_t size);

    std::vector<Slot> slots_;                      // per original edge
    std::vector<std::unique_ptr<Crossing[]>> chunks_;
    uint32_t filled_ = kChunkSize;                 // of the last shared chunk: positions handed out
    uint32_t shared_chunk_ = 0;                    // index of the chunk blocks are cut from
    std::array<std::vector<uint32_t>, 33> free_;   // per capacity bits: blocks given up
    size_t reserved_ = 0;                          // crossings in all chunks
};

}  // namespace bpm::detail
