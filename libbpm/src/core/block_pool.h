#pragma once
// Many small lists that change size, without a heap block each (internal to libbpm).
//
// A std::vector per list costs a 24-byte header, a malloc block per non-empty list (its
// header and rounding) and the capacity the list once grew to, kept when it shrinks. The
// simplifier holds a list per original edge (its path) and per coarse edge with content,
// most of them short, and the end of its removals is the peak memory of a run. A
// BlockPool hands out blocks of power-of-two capacity, named by a 32-bit address, cut
// from large chunks; a block given back goes onto the free list of its capacity and is
// the next block of that capacity handed out. Blocks never move: the elements of a block
// stay where they are until it is given back. Which block is handed out depends only on
// the sequence of calls (deterministic). Not thread-safe for take/give; reads from any
// thread while nothing is taken or given.
//
// T must be trivially copyable; blocks are not initialised (pages never written are
// never touched).

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace bpm::detail {

template <class T>
class BlockPool {
    static_assert(std::is_trivially_copyable_v<T>, "BlockPool holds trivially copyable elements");

public:
    // The capacity class of a list of n > 0 elements: the smallest k with 2^k >= n.
    static int capacity_bits(size_t n) {
        int k = 0;
        while ((size_t(1) << k) < n) ++k;
        return k;
    }

    // A block of 2^bits elements.
    uint32_t take(int bits) {
        auto& list = free_[size_t(bits)];
        if (!list.empty()) {
            const uint32_t block = list.back();
            list.pop_back();
            return block;
        }
        const uint32_t capacity = uint32_t(1) << bits;
        if (capacity > kChunkSize) return add_chunk(capacity);
        if (filled_ + capacity > kChunkSize) {
            // The rest of the shared chunk goes to the free lists in power-of-two pieces
            // (largest first), then a new chunk is cut.
            if (!chunks_.empty())
                for (int k = int(kChunkBits); k >= 0 && filled_ < kChunkSize; --k)
                    if (kChunkSize - filled_ >= (uint32_t(1) << k)) {
                        free_[size_t(k)].push_back((shared_chunk_ << kChunkBits) | filled_);
                        filled_ += uint32_t(1) << k;
                    }
            shared_chunk_ = add_chunk(kChunkSize) >> kChunkBits;
            filled_ = 0;
        }
        const uint32_t block = (shared_chunk_ << kChunkBits) | filled_;
        filled_ += capacity;
        return block;
    }
    // Gives back a block of 2^bits elements taken before.
    void give(uint32_t block, int bits) { free_[size_t(bits)].push_back(block); }

    T* at(uint32_t block) { return chunks_[block >> kChunkBits].get() + (block & (kChunkSize - 1)); }
    const T* at(uint32_t block) const { return chunks_[block >> kChunkBits].get() + (block & (kChunkSize - 1)); }

    // Elements of room in all chunks, in use or free.
    size_t reserved() const { return reserved_; }
    // Frees every chunk: every block is invalid after it.
    void release() {
        decltype(chunks_)().swap(chunks_);
        for (auto& list : free_) std::vector<uint32_t>().swap(list);
        filled_ = kChunkSize;
        shared_chunk_ = 0;
        reserved_ = 0;
    }

private:
    // An address is chunk index << kChunkBits | position in the chunk. A chunk holds
    // 2^kChunkBits elements; a block larger than that gets a chunk of its own and takes
    // as many chunk indices as it spans, so that 32 bits address 2^32 elements in all.
    static constexpr uint32_t kChunkBits = 14;
    static constexpr uint32_t kChunkSize = uint32_t(1) << kChunkBits;

    uint32_t add_chunk(size_t size) {
        const size_t index = chunks_.size();
        const size_t spans = std::max<size_t>(1, (size + kChunkSize - 1) / kChunkSize);
        if (index + spans > (size_t(1) << (32 - kChunkBits)))
            throw std::length_error("bpm: more than 2^32 elements in a block pool");
        chunks_.emplace_back(new T[size]);  // not value-initialised
        for (size_t k = 1; k < spans; ++k) chunks_.emplace_back();
        reserved_ += size;
        return uint32_t(index) << kChunkBits;
    }

    std::vector<std::unique_ptr<T[]>> chunks_;
    uint32_t filled_ = kChunkSize;                // of the shared chunk: positions handed out
    uint32_t shared_chunk_ = 0;                   // index of the chunk blocks are cut from
    std::array<std::vector<uint32_t>, 33> free_;  // per capacity bits: blocks given back
    size_t reserved_ = 0;
};

}  // namespace bpm::detail
