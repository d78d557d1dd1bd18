#pragma once
// Handing freed memory back to the operating system (internal to libbpm).

#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace bpm::detail {

// The simplifier's state is hundreds of thousands of small blocks (triangle lists, paths,
// grid cells) that glibc keeps resident after they are freed, while the next large
// arrays (phi, the file) come from fresh mappings on top of them. Handing the free pages
// back makes the peak of a run closer to that of its live data. A no-op elsewhere.
inline void return_free_memory() {
#ifdef __GLIBC__
    malloc_trim(0);
#endif
}

}  // namespace bpm::detail
