#pragma once
// The batch driver of the queries on phi (PhiEvaluator's and PhiInverse's batched calls):
// queries in chunks, each chunk visited grouped by a key (the coarse triangle, the grid
// block or the original triangle group) so that the data of one key is loaded into the
// cache once per chunk instead of once per query, chunks shared out over threads.
//
// Why (perf on armadillo at 10%, see phi_evaluation.cpp and phi_inverse.cpp): in random
// order both are bound by memory latency. In grouped order the queries are read from and
// their results written to scattered places; every such access misses the cache, so
// `prefetch(i)` is called a few queries ahead of `eval(key, i)` in the visiting order
// (the caller prefetches the query's input and output lines there).
//
// Each query is computed on its own, so neither the grouping nor the thread count
// changes a result.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <thread>
#include <vector>

namespace bpm::detail {

// Asks for the cache line holding `address` (for writing if `write`); a hint only.
template <bool write>
inline void prefetch_line(const void* address) {
#if defined(__GNUC__) || defined(__clang__)
    __builtin_prefetch(address, write ? 1 : 0, 3);
#else
    (void)address;
#endif
}

// Both cache lines an object may straddle.
template <bool write, class T>
inline void prefetch_object(const T* object) {
    prefetch_line<write>(object);
    prefetch_line<write>(reinterpret_cast<const char*>(object) + sizeof(T) - 1);
}

// Runs work(first, step) on `threads` threads, first = 0 .. threads-1, all with step =
// threads; the calling thread does first = 0. threads == 1 runs on the calling thread only.
template <class Work>
void run_on_threads(int threads, const Work& work) {
    if (threads <= 1) {
        work(size_t(0), size_t(1));
        return;
    }
    std::vector<std::thread> pool;
    for (int k = 1; k < threads; ++k) pool.emplace_back(work, size_t(k), size_t(threads));
    work(size_t(0), size_t(threads));
    for (std::thread& th : pool) th.join();
}

// Runs eval(key(i), i) for every query i in [0, n), see the file comment. key(i) <
// nkeys; a chunk holds at least 2^20 queries and at least `per_key` per key (per caller,
// measured); queries are grouped only when a chunk has 1024 or more of them and at least
// 4 per key (fewer gain nothing). `threads` 0 = the hardware's count; at most one thread
// per chunk.
template <class Key, class Eval, class Prefetch>
void for_each_grouped(size_t n, size_t nkeys, size_t per_key, int threads, const Key& key, const Eval& eval,
                      const Prefetch& prefetch) {
    if (threads == 0) threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    const size_t chunk = std::min(n, std::max<size_t>(size_t(1) << 20, per_key * nkeys));
    const size_t chunks = chunk == 0 ? 0 : (n + chunk - 1) / chunk;
    threads = static_cast<int>(std::min<size_t>(static_cast<size_t>(threads), std::max<size_t>(1, chunks)));
    const bool group = n >= 1024 && chunk >= 4 * nkeys;
    run_on_threads(threads, [&](size_t first_chunk, size_t step) {
        std::vector<uint32_t> start, keys;
        std::vector<uint32_t> sorted;  // query indices within the chunk, grouped by key
        for (size_t c = first_chunk; c < chunks; c += step) {
            const size_t begin = c * chunk, end = std::min(n, begin + chunk), m = end - begin;
            if (!group) {
                for (size_t i = begin; i < end; ++i) eval(key(i), i);
                continue;
            }
            // Counting sort of the chunk's query indices by key.
            keys.resize(m);
            start.assign(nkeys + 1, 0);
            for (size_t i = 0; i < m; ++i) {
                keys[i] = static_cast<uint32_t>(key(begin + i));
                ++start[keys[i] + 1];
            }
            for (size_t k = 0; k < nkeys; ++k) start[k + 1] += start[k];
            sorted.resize(m);
            for (size_t i = 0; i < m; ++i) sorted[start[keys[i]]++] = static_cast<uint32_t>(i);
            // start[k] is now the end of key k's queries.
            constexpr size_t ahead = 16;
            for (size_t k = 0; k < std::min(ahead, m); ++k) prefetch(begin + sorted[k]);
            size_t k = 0;
            for (size_t g = 0; g < nkeys; ++g)
                for (; k < start[g]; ++k) {
                    if (k + ahead < m) prefetch(begin + sorted[k + ahead]);
                    eval(g, begin + sorted[k]);
                }
        }
    });
}

}  // namespace bpm::detail
