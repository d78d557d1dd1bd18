#include "refine/triangle_box_grid.h"

#include <algorithm>
#include <cmath>

namespace bpm::detail {

namespace {

// A triangle filed under more cells than this is kept in the list every query looks at.
constexpr int64_t kLargeCells = 64;

void triangle_box(const Surface& surface, int32_t t, Vec3& lo, Vec3& hi) {
    const Tri& c = surface.triangles[size_t(t)];
    lo = hi = surface.vertices[size_t(c[0])];
    for (size_t i = 1; i < 3; ++i)
        for (size_t k = 0; k < 3; ++k) {
            const double x = surface.vertices[size_t(c[i])][k];
            lo[k] = std::min(lo[k], x);
            hi[k] = std::max(hi[k], x);
        }
}

}  // namespace

TriangleBoxGrid::TriangleBoxGrid(const Surface& surface) {
    const size_t nt = surface.triangles.size();
    filed_.resize(nt);
    stamp_.assign(nt, 0);
    if (nt == 0) {
        start_.assign(2, 0);
        return;
    }
    // Cell edge: the mean of the triangles' largest box extents, so a typical triangle is
    // filed under at most 2 cells per axis; larger where that would make more cells than
    // triangles (a surface of a few large triangles in a big box; a surface's triangles
    // fill few of the cells of its box).
    Vec3 lo, hi, all_lo, all_hi;
    triangle_box(surface, 0, all_lo, all_hi);
    double sum = 0;
    for (size_t t = 0; t < nt; ++t) {
        triangle_box(surface, int32_t(t), lo, hi);
        double extent = 0;
        for (size_t k = 0; k < 3; ++k) {
            all_lo[k] = std::min(all_lo[k], lo[k]);
            all_hi[k] = std::max(all_hi[k], hi[k]);
            extent = std::max(extent, hi[k] - lo[k]);
        }
        sum += extent;
    }
    origin_ = all_lo;
    double largest = 0;
    for (size_t k = 0; k < 3; ++k) largest = std::max(largest, all_hi[k] - all_lo[k]);
    double size = sum / double(nt);
    if (!(size > 0)) size = largest > 0 ? largest : 1.0;
    const double max_cells = double(nt) + 1.0;
    for (;;) {
        double cells = 1;
        for (size_t k = 0; k < 3; ++k) cells *= std::floor((all_hi[k] - all_lo[k]) / size) + 1;
        if (cells <= max_cells) break;
        size *= 1.25;
    }
    inverse_size_ = 1.0 / size;
    for (size_t k = 0; k < 3; ++k) n_[k] = int32_t(std::floor((all_hi[k] - all_lo[k]) * inverse_size_)) + 1;
    const size_t cells = size_t(n_[0]) * size_t(n_[1]) * size_t(n_[2]);
    // Two passes over the triangles: count per cell, then place (ascending in each cell).
    start_.assign(cells + 1, 0);
    auto each_cell = [&](const CellRange& r, auto&& visit) {
        for (int32_t i = r[0]; i <= r[1]; ++i)
            for (int32_t j = r[2]; j <= r[3]; ++j)
                for (int32_t k = r[4]; k <= r[5]; ++k) visit(cell(i, j, k));
    };
    for (size_t t = 0; t < nt; ++t) {
        filed_[t] = range_of(surface, int32_t(t));
        if (large(filed_[t])) large_.push_back(int32_t(t));
        else each_cell(filed_[t], [&](size_t c) { ++start_[c + 1]; });
    }
    for (size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
    filed_at_start_.resize(size_t(start_[cells]));
    std::vector<int64_t> next(start_.begin(), start_.end() - 1);
    for (size_t t = 0; t < nt; ++t)
        if (!large(filed_[t])) each_cell(filed_[t], [&](size_t c) { filed_at_start_[size_t(next[c]++)] = int32_t(t); });
}

TriangleBoxGrid::CellRange TriangleBoxGrid::range(const Vec3& lo, const Vec3& hi) const {
    // Clamped to the grid: monotone in x, so boxes that meet share a cell.
    auto index = [&](double x, size_t k) {
        const double c = (x - origin_[k]) * inverse_size_;
        if (!(c > 0)) return int32_t(0);
        if (c >= double(n_[k] - 1)) return n_[k] - 1;
        return int32_t(c);
    };
    return {index(lo[0], 0), index(hi[0], 0), index(lo[1], 1), index(hi[1], 1), index(lo[2], 2), index(hi[2], 2)};
}

TriangleBoxGrid::CellRange TriangleBoxGrid::range_of(const Surface& surface, int32_t t) const {
    Vec3 lo, hi;
    triangle_box(surface, t, lo, hi);
    return range(lo, hi);
}

bool TriangleBoxGrid::large(const CellRange& r) {
    return int64_t(r[1] - r[0] + 1) * int64_t(r[3] - r[2] + 1) * int64_t(r[5] - r[4] + 1) > kLargeCells;
}

void TriangleBoxGrid::file(int32_t t, const CellRange& r) {
    if (large(r)) {
        large_.push_back(t);
        return;
    }
    for (int32_t i = r[0]; i <= r[1]; ++i)
        for (int32_t j = r[2]; j <= r[3]; ++j)
            for (int32_t k = r[4]; k <= r[5]; ++k) moved_[cell(i, j, k)].push_back(t);
}

void TriangleBoxGrid::unfile(int32_t t, const CellRange& r) {
    auto remove = [t](std::vector<int32_t>& list) {
        const auto it = std::find(list.begin(), list.end(), t);
        if (it == list.end()) return false;
        *it = list.back();
        list.pop_back();
        return true;
    };
    if (large(r)) {
        remove(large_);
        return;
    }
    for (int32_t i = r[0]; i <= r[1]; ++i)
        for (int32_t j = r[2]; j <= r[3]; ++j)
            for (int32_t k = r[4]; k <= r[5]; ++k) {
                const size_t c = cell(i, j, k);
                const auto moved = moved_.find(c);
                if (moved != moved_.end() && remove(moved->second)) continue;
                const auto first = filed_at_start_.begin() + start_[c], last = filed_at_start_.begin() + start_[c + 1];
                const auto it = std::find(first, last, t);
                if (it != last) *it = -1;
            }
}

void TriangleBoxGrid::update(const Surface& surface, int32_t t) {
    const CellRange r = range_of(surface, t);
    if (r == filed_[size_t(t)]) return;
    unfile(t, filed_[size_t(t)]);
    file(t, r);
    filed_[size_t(t)] = r;
}

void TriangleBoxGrid::candidates(const Vec3& lo, const Vec3& hi, std::vector<int32_t>& out) {
    out.clear();
    if (++query_ == 0) {  // the stamps wrapped around: none may look current
        std::fill(stamp_.begin(), stamp_.end(), 0);
        query_ = 1;
    }
    auto take = [&](int32_t t) {
        ++visited_;
        if (stamp_[size_t(t)] == query_) return;
        stamp_[size_t(t)] = query_;
        out.push_back(t);
    };
    const CellRange r = range(lo, hi);
    for (int32_t i = r[0]; i <= r[1]; ++i)
        for (int32_t j = r[2]; j <= r[3]; ++j)
            for (int32_t k = r[4]; k <= r[5]; ++k) {
                const size_t c = cell(i, j, k);
                for (int64_t e = start_[c]; e < start_[c + 1]; ++e)
                    if (filed_at_start_[size_t(e)] >= 0) take(filed_at_start_[size_t(e)]);
                if (moved_.empty()) continue;
                const auto moved = moved_.find(c);
                if (moved != moved_.end())
                    for (int32_t t : moved->second) take(t);
            }
    for (int32_t t : large_) take(t);
    std::sort(out.begin(), out.end());
}

}  // namespace bpm::detail
