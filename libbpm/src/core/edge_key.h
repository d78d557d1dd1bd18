#pragma once
// One 64-bit key per undirected edge {a, b} of an indexed mesh: the smaller vertex id in
// the high half, the larger in the low half. Keys of edges sort by their smaller vertex
// first, then by the other; both orders (a, b) and (b, a) give the same key.

#include <cstdint>
#include <utility>

namespace bpm::detail {

inline uint64_t edge_key(int32_t a, int32_t b) {
    if (a > b) std::swap(a, b);
    return (static_cast<uint64_t>(static_cast<uint32_t>(a)) << 32) | static_cast<uint64_t>(static_cast<uint32_t>(b));
}

// The two vertices of an edge key, smaller first.
inline int32_t edge_key_first(uint64_t k) { return static_cast<int32_t>(k >> 32); }
inline int32_t edge_key_second(uint64_t k) { return static_cast<int32_t>(k & 0xffffffffu); }

}  // namespace bpm::detail
