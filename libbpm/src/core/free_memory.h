#pragma once
// Handing freed memory back to the operating system (internal to libbpm).

#ifdef __GLIBC__
#include <malloc.h>

#include <cstddef>
#endif

namespace bpm::detail {

// The simplifier's state is hundreds of thousands of small blocks (triangle lists, paths,
// grid cells) that glibc keeps resident after they are freed, while the next large
// arrays (phi, the file) come from fresh mappings on top of them. Handing the free pages
// back makes the peak of a run closer to that of its live data. A no-op elsewhere, and
// when glibc holds less than 8 MiB free: each page range handed back is a system call
// and a TLB flush, together 2-3 % of a small run (bpm-simplify elephant --vertices 1000
// --threads 1 trims 1.3 MB twice: 0.0075 s of 0.24 CPU s, the peak 0.4 MB higher without
// it), while on a large input the free bytes are tens of megabytes.
inline void return_free_memory() {
#ifdef __GLIBC__
#if __GLIBC_PREREQ(2, 33)
    if (mallinfo2().fordblks < (size_t(8) << 20)) return;
#endif
    malloc_trim(0);
#endif
}

}  // namespace bpm::detail
