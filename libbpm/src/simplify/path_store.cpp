#include "simplify/path_store.h"

#include <cstring>
#include <stdexcept>

#include "core/huge_pages.h"

namespace bpm::detail {

void PathStore::reset(size_t edges) {
    release();
    reserve_huge_pages(slots_, edges);
    slots_.assign(edges, Slot());
}

void PathStore::release() {
    decltype(slots_)().swap(slots_);
    pool_.release();
}

size_t PathStore::total_crossings() const {
    size_t total = 0;
    for (const Slot& s : slots_) total += s.size;
    return total;
}

void PathStore::assign(size_t e, const Crossing* crossings, size_t n) {
    if (n > UINT32_MAX) throw std::length_error("bpm: a path of more than 2^32 crossings");
    Slot& slot = slots_[e];
    const int old_bits = slot.size == 0 ? -1 : BlockPool<Crossing>::capacity_bits(slot.size);
    const int new_bits = n == 0 ? -1 : BlockPool<Crossing>::capacity_bits(n);
    if (old_bits != new_bits) {
        if (old_bits >= 0) pool_.give(slot.block, old_bits);
        slot.block = new_bits >= 0 ? pool_.take(new_bits) : 0;
    }
    if (n > 0) std::memcpy(static_cast<void*>(pool_.at(slot.block)), crossings, n * sizeof(Crossing));
    slot.size = uint32_t(n);
}

}  // namespace bpm::detail
