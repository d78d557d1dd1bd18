#include "simplify/edge_content_map.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace bpm::detail {

void EdgeContentMap::release() {
    keys_.release();
    decltype(index_)().swap(index_);
    decltype(entries_)().swap(entries_);
    ids_.release();
}

void EdgeContentMap::rehash(size_t capacity) {
    std::vector<uint32_t> old_index(capacity);
    old_index.swap(index_);
    keys_.rehash(capacity, [&](size_t from, size_t to) { index_[to] = old_index[from]; });
}

EdgeContentMap::Entry& EdgeContentMap::find_or_add(uint64_t key) {
    if (const Entry* e = find(key)) return entries_[size_t(e - entries_.data())];
    if (keys_.needs_room_for(entries_.size() + 1)) rehash(std::max<size_t>(64, 2 * keys_.slots()));
    index_[keys_.insert(key)] = static_cast<uint32_t>(entries_.size());
    entries_.push_back({key, 0, 0, 0});
    return entries_.back();
}

void EdgeContentMap::erase(size_t removed) {
    keys_.erase(keys_.find(entries_[removed].key), [&](size_t from, size_t to) { index_[to] = index_[from]; });
    // The last entry takes the erased one's place.
    const size_t last = entries_.size() - 1;
    if (removed != last) {
        entries_[removed] = entries_[last];
        index_[keys_.find(entries_[removed].key)] = static_cast<uint32_t>(removed);
    }
    entries_.pop_back();
    // Less than an eighth full: half the room (a quarter full then), so that the table
    // follows the entries down as the coarse surface shrinks.
    if (keys_.slots() > 64 && 8 * entries_.size() < keys_.slots()) rehash(keys_.slots() / 2);
}

void EdgeContentMap::resize_block(Entry& e, size_t new_size) {
    const size_t old_size = size_t(e.vertices) + e.crossing_edges;
    if (new_size > UINT32_MAX) throw std::length_error("bpm: more than 2^32 ids on a coarse edge");
    const int old_bits = old_size == 0 ? -1 : BlockPool<int32_t>::capacity_bits(old_size);
    const int new_bits = new_size == 0 ? -1 : BlockPool<int32_t>::capacity_bits(new_size);
    if (old_bits == new_bits) return;
    const uint32_t block = new_bits >= 0 ? ids_.take(new_bits) : 0;
    if (new_bits >= 0 && old_bits >= 0)
        std::memcpy(ids_.at(block), ids_.at(e.block), std::min(old_size, new_size) * sizeof(int32_t));
    if (old_bits >= 0) ids_.give(e.block, old_bits);
    e.block = block;
}

void EdgeContentMap::add_vertex(uint64_t key, int32_t vertex) {
    Entry& e = find_or_add(key);
    resize_block(e, size_t(e.vertices) + e.crossing_edges + 1);
    int32_t* ids = ids_.at(e.block);
    // The crossing edges move up by one to make room at the end of the vertices.
    std::memmove(ids + e.vertices + 1, ids + e.vertices, size_t(e.crossing_edges) * sizeof(int32_t));
    ids[e.vertices++] = vertex;
}

void EdgeContentMap::add_crossing_edge(uint64_t key, int32_t edge) {
    Entry& e = find_or_add(key);
    resize_block(e, size_t(e.vertices) + e.crossing_edges + 1);
    ids_.at(e.block)[e.vertices + e.crossing_edges++] = edge;
}

void EdgeContentMap::remove_vertex(uint64_t key, int32_t vertex) {
    const Entry* found = find(key);
    if (!found) return;
    const size_t index = size_t(found - entries_.data());
    Entry& e = entries_[index];
    int32_t* ids = ids_.at(e.block);
    int32_t* end = ids + e.vertices;
    int32_t* at = std::find(ids, end, vertex);
    if (at == end) return;
    *at = end[-1];
    // The crossing edges move down by one into the freed place.
    std::memmove(end - 1, end, size_t(e.crossing_edges) * sizeof(int32_t));
    const size_t new_size = size_t(e.vertices) + e.crossing_edges - 1;
    resize_block(e, new_size);
    --e.vertices;
    if (new_size == 0) erase(index);
}

void EdgeContentMap::remove_crossing_edge(uint64_t key, int32_t edge) {
    const Entry* found = find(key);
    if (!found) return;
    const size_t index = size_t(found - entries_.data());
    Entry& e = entries_[index];
    int32_t* first = ids_.at(e.block) + e.vertices;
    int32_t* end = first + e.crossing_edges;
    int32_t* at = std::find(first, end, edge);
    if (at == end) return;
    *at = end[-1];
    const size_t new_size = size_t(e.vertices) + e.crossing_edges - 1;
    resize_block(e, new_size);
    --e.crossing_edges;
    if (new_size == 0) erase(index);
}

}  // namespace bpm::detail
