#pragma once
// Transparent huge pages for the large arrays of a run (internal to libbpm).
//
// A large input touches hundreds of megabytes of fresh memory: the 832k-triangle floor
// (bpm-simplify --ratio 1 --threads 1) took ~160k page faults of 4 KiB, which on a
// virtual machine cost ~10 % of the run, and its random reads (vertex positions, the
// grid's cells, the phi arrays) miss the TLB on 4 KiB pages. Where the kernel gives huge
// pages only to memory that asks for them (/sys/kernel/mm/transparent_hugepage/enabled
// = madvise, as on this project's test machine), the big arrays ask, before they are
// first written. Only memory and speed change, never a result. A no-op where madvise or
// MADV_HUGEPAGE does not exist, where THP is off, and for arrays under 4 MiB (a huge page
// is 2 MiB: a small array would round up to more than it uses).

#include <cstddef>
#include <vector>

namespace bpm::detail {

// Asks for huge pages for the whole 2 MiB pages inside [p, p + bytes) (madvise
// MADV_HUGEPAGE): those not yet touched get a huge page at their first fault. The part
// before the first and after the last 2 MiB boundary is left alone, so the resident
// size grows by nothing that is not written. Errors are ignored (it is advice).
void advise_huge_pages(const void* p, size_t bytes);

// v.reserve(n) and the advice for the room: call it before the elements are written
// (a reserve that reallocates copies the old elements into the new room first).
template <class T>
void reserve_huge_pages(std::vector<T>& v, size_t n) {
    v.reserve(n);
    advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

}  // namespace bpm::detail
