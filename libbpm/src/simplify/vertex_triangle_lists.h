#pragma once
// The alive triangles at each vertex of the coarse surface, sorted by id (CoarseMesh).
// A list per vertex as a std::vector was a 24-byte header in one array and a heap block
// elsewhere: two cache misses per list on the planner's hot path (has_edge,
// classify_star), and a few hundred thousand small blocks. Here each vertex owns one
// 64-byte block in a flat array, its count and up to kInline ids in one cache line; a
// vertex of higher degree (rare) keeps its list in a std::vector of its own instead.

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/huge_pages.h"

namespace bpm::detail {

class VertexTriangleLists {
public:
    // A read-only range of triangle ids.
    class View {
    public:
        View(const int32_t* b, const int32_t* e) : b_(b), e_(e) {}
        const int32_t* begin() const { return b_; }
        const int32_t* end() const { return e_; }
        size_t size() const { return size_t(e_ - b_); }
        bool empty() const { return b_ == e_; }
        int32_t operator[](size_t i) const { return b_[i]; }

    private:
        const int32_t* b_;
        const int32_t* e_;
    };

    explicit VertexTriangleLists(size_t num_vertices = 0) : num_vertices_(num_vertices) {
        reserve_huge_pages(blocks_, num_vertices);  // 64 bytes a vertex, read at random by the planners
        blocks_.resize(num_vertices);
    }
    size_t num_vertices() const { return num_vertices_; }

    View of(int32_t v) const {
        if (compact_) return View(flat_.data() + offsets_[v], flat_.data() + offsets_[v + 1]);
        const Block& b = blocks_[v];
        if (b.count >= 0) return View(b.ids, b.ids + b.count);
        const std::vector<int32_t>& list = spilled_[size_t(-1 - b.count)];
        return View(list.data(), list.data() + list.size());
    }
    // A cache hint for of(v) (CoarseMesh::prefetch_vertex); not after compact().
    void prefetch(int32_t v) const { __builtin_prefetch(blocks_.data() + v); }
    bool empty(int32_t v) const { return compact_ ? offsets_[v] == offsets_[v + 1] : blocks_[v].count == 0; }

    // Stores the lists in one array with offsets (CSR) and frees the blocks: once the
    // simplification is done, most vertices are removed and their 64-byte blocks empty
    // (208k triangles to 10k vertices: 6.7 MB of blocks for 60k ids). Read-only after.
    void compact() {
        if (compact_) return;
        std::vector<uint32_t> offsets(num_vertices_ + 1, 0);
        for (size_t v = 0; v < num_vertices_; ++v) offsets[v + 1] = offsets[v] + uint32_t(of(int32_t(v)).size());
        std::vector<int32_t> flat;
        flat.reserve(offsets.back());
        for (size_t v = 0; v < num_vertices_; ++v)
            for (int32_t t : of(int32_t(v))) flat.push_back(t);
        offsets_ = std::move(offsets);
        flat_ = std::move(flat);
        decltype(blocks_)().swap(blocks_);
        decltype(spilled_)().swap(spilled_);
        decltype(free_spilled_)().swap(free_spilled_);
        compact_ = true;
    }

    // Appends t, which must be larger than every id in the list of v (ids only grow).
    void push_back(int32_t v, int32_t t) {
        Block& b = blocks_[v];
        if (b.count < 0) {
            spilled_[size_t(-1 - b.count)].push_back(t);
        } else if (b.count < kInline) {
            b.ids[b.count++] = t;
        } else {
            // Move the full block into a list of its own, for good (a degree that grew this
            // far tends to stay high; the list's order does not change).
            std::vector<int32_t> list(b.ids, b.ids + b.count);
            list.push_back(t);
            size_t slot;
            if (!free_spilled_.empty()) {
                slot = free_spilled_.back();
                free_spilled_.pop_back();
                spilled_[slot] = std::move(list);
            } else {
                slot = spilled_.size();
                spilled_.push_back(std::move(list));
            }
            b.count = -1 - int32_t(slot);
        }
    }

    // Removes t from the list of v (it must be there), keeping the order.
    void erase(int32_t v, int32_t t) {
        Block& b = blocks_[v];
        if (b.count >= 0) {
            int32_t* end = b.ids + b.count;
            std::copy(std::find(b.ids, end, t) + 1, end, std::find(b.ids, end, t));
            --b.count;
            return;
        }
        const size_t slot = size_t(-1 - b.count);
        std::vector<int32_t>& list = spilled_[slot];
        list.erase(std::find(list.begin(), list.end(), t));
        if (list.empty()) {
            std::vector<int32_t>().swap(list);
            free_spilled_.push_back(slot);
            b.count = 0;
        }
    }

private:
    static constexpr int32_t kInline = 15;
    struct alignas(64) Block {
        int32_t count = 0;  // >= 0: ids[0, count); < 0: the list is spilled_[-1 - count]
        int32_t ids[kInline];
    };
    std::vector<Block> blocks_;
    std::vector<std::vector<int32_t>> spilled_;
    std::vector<size_t> free_spilled_;  // slots of spilled_ whose list was emptied
    size_t num_vertices_ = 0;
    bool compact_ = false;              // after compact(): the lists are flat_[offsets_[v], offsets_[v + 1])
    std::vector<uint32_t> offsets_;
    std::vector<int32_t> flat_;
};

// Calls visit(t) for every triangle id on both sorted lists `a` and `b` (the triangles on
// an edge, when they are the lists of its two ends), in increasing order, until visit
// returns false. Merging the two short lists needs no triangle's corners, which are
// scattered in memory (CoarseMesh::has_edge runs for every ear a planner considers).
template <class Visit>
void for_each_common(VertexTriangleLists::View a, VertexTriangleLists::View b, Visit&& visit) {
    for (const int32_t *i = a.begin(), *j = b.begin(); i != a.end() && j != b.end();) {
        if (*i < *j) {
            ++i;
        } else if (*j < *i) {
            ++j;
        } else {
            if (!visit(*i)) return;
            ++i;
            ++j;
        }
    }
}

}  // namespace bpm::detail
