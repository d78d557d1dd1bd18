#pragma once
// What lies on each coarse edge while the surface is simplified (Embedding::edge_content):
// the original vertices located on it and the original edges crossing it, by coarse edge
// key (core/edge_key.h). Internal to libbpm.
//
// Keys in a ProbedKeys table (core/probed_keys.h: the planners look coarse edges up
// several times per plan, millions of times per run), with per slot an index into a dense
// array of entries, so a probe that misses reads no content. An
// entry's ids are one block of a BlockPool (core/block_pool.h), its vertices first, then
// its crossing edges: a pair of std::vectors per entry was 56 bytes, two heap blocks and
// the capacity they once grew to, and erased entries kept theirs for reuse (208k-triangle
// input to 10k vertices: ~9 MB at the end of the removals, the peak of a run, for
// 0.1 MB of ids in 29k entries). The table shrinks when it is less than an eighth full.
//
// The lists behave as before: an id added goes at the end of its list; an id taken off
// is replaced by the last of its list. Their order is unspecified to readers (every
// reader sorts), but fixed by the sequence of calls. An entry exists exactly while it
// holds an id.

#include <cstdint>
#include <vector>

#include "core/block_pool.h"
#include "core/const_range.h"
#include "core/probed_keys.h"

namespace bpm::detail {

// What lies on a coarse edge, read-only. Valid until the next change of the map.
struct EdgeContentView {
    ConstRange<int32_t> vertices;        // original vertices located OnEdge here
    ConstRange<int32_t> crossing_edges;  // original edge ids with a Crossing here (once per crossing)
};

class EdgeContentMap {
public:
    struct Entry {
        uint64_t key;
        uint32_t block;           // in ids_: vertices, then crossing edges
        uint32_t vertices;        // how many
        uint32_t crossing_edges;  // how many
    };

    // The entry of `key`, or nullptr (valid until the next change of the map).
    const Entry* find(uint64_t key) const {
        const size_t slot = keys_.find(key);
        return slot == ProbedKeys::kNone ? nullptr : &entries_[index_[slot]];
    }
    EdgeContentView view(const Entry& e) const {
        const int32_t* ids = ids_.at(e.block);
        return {{ids, ids + e.vertices}, {ids + e.vertices, ids + e.vertices + e.crossing_edges}};
    }
    // A cache hint, no effect on any result: ask for the slot find(key) reads first (the
    // planners look up every spoke of a star; asked for together, the misses overlap).
    void prefetch(uint64_t key) const {
        const size_t i = keys_.first_probe(key);  // no branch around the prefetches
        __builtin_prefetch(keys_.data() + i);
        __builtin_prefetch(index_.data() + i);
    }
    // Also a cache hint: the ids of an entry found.
    void prefetch_ids(const Entry& e) const { __builtin_prefetch(ids_.at(e.block)); }

    // Appends to key's list (the entry is made if absent).
    void add_vertex(uint64_t key, int32_t vertex);
    void add_crossing_edge(uint64_t key, int32_t edge);
    // Takes one occurrence off key's list, if there (the last of the list takes its
    // place); the entry goes when it holds nothing any more.
    void remove_vertex(uint64_t key, int32_t vertex);
    void remove_crossing_edge(uint64_t key, int32_t edge);

    size_t size() const { return entries_.size(); }
    // Calls f(key, view) for every entry, in no particular order.
    template <class F>
    void for_each(F f) const {
        for (const Entry& e : entries_) f(e.key, view(e));
    }
    // Frees everything (the table's room too).
    void release();
    void clear() { release(); }

private:
    ProbedKeys keys_;              // edge keys (never ProbedKeys::kEmpty: both halves are < 2^31)
    std::vector<uint32_t> index_;  // per slot of keys_: its entry in entries_
    std::vector<Entry> entries_;
    BlockPool<int32_t> ids_;
    void rehash(size_t capacity);
    Entry& find_or_add(uint64_t key);
    void erase(size_t entry);
    // Moves entry e's first min(old, new) ids into a block for `new_size` ids when the
    // capacity class changes (the counts are the caller's to set).
    void resize_block(Entry& e, size_t new_size);
};

}  // namespace bpm::detail
