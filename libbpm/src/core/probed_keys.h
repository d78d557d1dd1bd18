#pragma once
// The key half of libbpm's open-addressing hash tables (internal): 64-bit keys in a
// power-of-two array of slots, Fibonacci hashing, linear probing, at most half full, and
// backward-shift deletion (no tombstones). The values live in the owner's own arrays,
// parallel to the slots (the triangle grid's cell lists, the coarse edges' entry indices);
// ProbedKeys tells the owner, through a callback, which slot's value moves where when it
// rehashes or deletes.
//
// Why not std::unordered_map: the simplifier looks up grid cells and coarse edges
// millions of times per run; prime-modulo buckets and a node per element cost a few
// percent of the run time (a third of a grid query's). With the keys alone in one array,
// 8 to a cache line, a probe that misses reads no value.
//
// The slot of a key depends only on the sequence of insertions, deletions and rehashes
// (deterministic), never on addresses.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/huge_pages.h"

namespace bpm::detail {

class ProbedKeys {
public:
    static constexpr uint64_t kEmpty = ~uint64_t(0);  // no key may be this
    static constexpr size_t kNone = ~size_t(0);

    // `huge_pages`: ask for transparent huge pages for the key array (core/huge_pages.h).
    explicit ProbedKeys(bool huge_pages = false) : huge_pages_(huge_pages) {}

    size_t slots() const { return keys_.size(); }
    size_t size() const { return size_; }
    uint64_t key(size_t slot) const { return keys_[slot]; }
    bool occupied(size_t slot) const { return keys_[slot] != kEmpty; }

    // The slot of `key`, or kNone.
    size_t find(uint64_t key) const {
        if (keys_.empty()) return kNone;
        const size_t mask = keys_.size() - 1;
        for (size_t i = home(key);; i = (i + 1) & mask) {
            if (keys_[i] == key) return i;
            if (keys_[i] == kEmpty) return kNone;
        }
    }
    // The slot a lookup of `key` reads first (0 while there are no slots), for cache hints.
    size_t first_probe(uint64_t key) const { return keys_.empty() ? 0 : home(key); }
    const uint64_t* data() const { return keys_.data(); }

    // Whether `keys` keys would make the table more than half full.
    bool needs_room_for(size_t keys) const { return 2 * keys > keys_.size(); }
    // Puts an absent `key` into a free slot and returns it; there must be room
    // (!needs_room_for(size() + 1)).
    size_t insert(uint64_t key) {
        const size_t mask = keys_.size() - 1;
        size_t i = home(key);
        while (keys_[i] != kEmpty) i = (i + 1) & mask;
        keys_[i] = key;
        ++size_;
        return i;
    }
    // `capacity` slots (a power of two, at least 2 size()); move(from, to) for every key,
    // in the order of the old slots, after the key array is rebuilt.
    template <class Move>
    void rehash(size_t capacity, Move move) {
        std::vector<uint64_t> old = std::move(keys_);
        keys_ = std::vector<uint64_t>();
        if (huge_pages_) reserve_huge_pages(keys_, capacity);
        keys_.assign(capacity, kEmpty);
        shift_ = 64;
        for (size_t c = capacity; c > 1; c >>= 1) --shift_;
        const size_t mask = capacity - 1;
        for (size_t j = 0; j < old.size(); ++j) {
            if (old[j] == kEmpty) continue;
            size_t i = home(old[j]);
            while (keys_[i] != kEmpty) i = (i + 1) & mask;
            keys_[i] = old[j];
            move(j, i);
        }
    }
    // Removes the key in `slot`: later keys of its probe run move back into the hole when
    // their home slot does not lie after it (move(from, to) for each), so that lookups need
    // no tombstones.
    template <class Move>
    void erase(size_t slot, Move move) {
        const size_t mask = keys_.size() - 1;
        size_t hole = slot;
        for (size_t j = (hole + 1) & mask; keys_[j] != kEmpty; j = (j + 1) & mask) {
            const size_t h = home(keys_[j]);
            if (((j - h) & mask) >= ((j - hole) & mask)) {
                keys_[hole] = keys_[j];
                move(j, hole);
                hole = j;
            }
        }
        keys_[hole] = kEmpty;
        --size_;
    }
    void clear() {
        keys_.clear();
        size_ = 0;
        shift_ = 64;
    }
    void release() {
        std::vector<uint64_t>().swap(keys_);
        size_ = 0;
        shift_ = 64;
    }

private:
    std::vector<uint64_t> keys_;  // power-of-two size, at most half full
    size_t size_ = 0;
    int shift_ = 64;  // 64 - log2(keys_.size())
    bool huge_pages_;
    size_t home(uint64_t key) const { return size_t((key * 0x9E3779B97F4A7C15ull) >> shift_); }
};

}  // namespace bpm::detail
