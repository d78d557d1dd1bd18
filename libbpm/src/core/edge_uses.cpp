#include "core/edge_uses.h"

#include <algorithm>

#include "core/huge_pages.h"

namespace bpm::detail {

EdgeUses::EdgeUses(const Surface& surface) {
    const auto& T = surface.triangles;
    const int64_t nv = surface.num_vertices();
    const auto valid = [nv](int32_t a, int32_t b) { return a >= 0 && b >= 0 && a < nv && b < nv && a != b; };
    // Counting sort by the smaller vertex: the triangles in order, so each vertex's uses
    // come in triangle order (a triangle has an edge once: its corners differ).
    offsets_.assign(size_t(nv) + 1, 0);
    for (const Tri& t : T)
        for (int k = 0; k < 3; ++k) {
            const int32_t a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
            if (valid(a, b)) ++offsets_[size_t(std::min(a, b)) + 1];
        }
    for (size_t v = 1; v < offsets_.size(); ++v) offsets_[v] += offsets_[v - 1];
    reserve_huge_pages(uses_, offsets_.back());
    uses_.resize(offsets_.back());
    for (size_t t = 0; t < T.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int32_t a = T[t][size_t(k)], b = T[t][size_t((k + 1) % 3)];
            if (!valid(a, b)) continue;
            uses_[offsets_[size_t(std::min(a, b))]++] = {std::max(a, b), uint32_t(t) << 1 | uint32_t(a < b)};
        }
    // offsets_[v] is now where v's uses end: shift them back to where they begin.
    for (size_t v = offsets_.size() - 1; v > 0; --v) offsets_[v] = offsets_[v - 1];
    offsets_[0] = 0;
    // Each vertex's few uses by the larger vertex, stably (triangle order within an edge).
    const auto by_larger = [](const Use& x, const Use& y) { return x.larger < y.larger; };
    for (size_t v = 0; v + 1 < offsets_.size(); ++v) {
        Use* first = uses_.data() + offsets_[v];
        Use* last = uses_.data() + offsets_[v + 1];
        if (last - first > 32) {
            std::stable_sort(first, last, by_larger);
        } else {
            for (Use* i = first + 1; i < last; ++i) {
                const Use x = *i;
                Use* j = i;
                for (; j > first && by_larger(x, j[-1]); --j) *j = j[-1];
                *j = x;
            }
        }
        for (Use* i = first; i < last; ++i) num_edges_ += i == first || i->larger != i[-1].larger;
    }
}

std::vector<std::pair<int32_t, int32_t>> EdgeUses::boundary_edges() const {
    std::vector<std::pair<int32_t, int32_t>> boundary;
    for_each_edge([&](int32_t a, int32_t b, const Use*, size_t count) {
        if (count == 1) boundary.emplace_back(a, b);
    });
    return boundary;
}

}  // namespace bpm::detail
