#include "simplify/path_store.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "core/huge_pages.h"

namespace bpm::detail {

namespace {

// The capacity class of a path of n > 0 crossings: the smallest k with 2^k >= n.
int capacity_bits(size_t n) {
    int k = 0;
    while ((size_t(1) << k) < n) ++k;
    return k;
}

}  // namespace

void PathStore::reset(size_t edges) {
    release();
    reserve_huge_pages(slots_, edges);
    slots_.assign(edges, Slot());
}

void PathStore::release() {
    decltype(slots_)().swap(slots_);
    decltype(chunks_)().swap(chunks_);
    for (auto& list : free_) decltype(free_)::value_type().swap(list);
    filled_ = kChunkSize;
    shared_chunk_ = 0;
    reserved_ = 0;
}

size_t PathStore::total_crossings() const {
    size_t total = 0;
    for (const Slot& s : slots_) total += s.size;
    return total;
}

uint32_t PathStore::add_chunk(size_t size) {
    // Blocks larger than a chunk take whole chunks' worth of addresses, so that the
    // addresses stay below 2^32 crossings in all.
    const size_t index = chunks_.size();
    const size_t spans = std::max<size_t>(1, (size + kChunkSize - 1) / kChunkSize);
    if (index + spans > (size_t(1) << (32 - kChunkBits)))
        throw std::length_error("bpm: more than 2^32 path crossings (96 GB) while simplifying");
    // Not value-initialised: pages a block never writes are never touched.
    chunks_.emplace_back(new Crossing[size]);
    reserved_ += size;
    for (size_t k = 1; k < spans; ++k) chunks_.emplace_back();
    return uint32_t(index) << kChunkBits;
}

uint32_t PathStore::take_block(int bits) {
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

void PathStore::assign(size_t e, const Crossing* crossings, size_t n) {
    if (n > UINT32_MAX) throw std::length_error("bpm: a path of more than 2^32 crossings");
    Slot& slot = slots_[e];
    const int old_bits = slot.size == 0 ? -1 : capacity_bits(slot.size);
    const int new_bits = n == 0 ? -1 : capacity_bits(n);
    if (old_bits != new_bits) {
        if (old_bits >= 0) free_[size_t(old_bits)].push_back(slot.block);
        slot.block = new_bits >= 0 ? take_block(new_bits) : 0;
    }
    if (n > 0) std::memcpy(static_cast<void*>(address(slot.block)), crossings, n * sizeof(Crossing));
    slot.size = uint32_t(n);
}

}  // namespace bpm::detail
