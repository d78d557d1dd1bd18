#include "core/triangle_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/huge_pages.h"

namespace bpm::detail {

void TriangleGrid::CellTable::rehash(size_t capacity) {
    std::vector<std::vector<Entry>> old_lists = std::move(lists_);
    std::vector<uint32_t> old_counts = std::move(counts_);
    lists_ = {};
    reserve_huge_pages(lists_, capacity);
    lists_.resize(capacity);
    counts_ = {};
    if (!old_counts.empty()) reserve_huge_pages(counts_, capacity);
    counts_.assign(old_counts.empty() ? 0 : capacity, 0);
    keys_.rehash(capacity, [&](size_t from, size_t to) {
        lists_[to] = std::move(old_lists[from]);
        if (!old_counts.empty()) counts_[to] = old_counts[from];
    });
}

void TriangleGrid::CellTable::count(uint64_t key) {
    std::vector<Entry>& list = (*this)[key];  // may rehash, which moves the counts along
    if (counts_.size() != keys_.slots()) counts_.resize(keys_.slots(), 0);
    ++counts_[size_t(&list - lists_.data())];
}

void TriangleGrid::CellTable::reserve_counted() {
    for (size_t i = 0; i < counts_.size(); ++i)
        if (counts_[i] != 0) lists_[i].reserve(lists_[i].size() + counts_[i]);
    decltype(counts_)().swap(counts_);
}

void TriangleGrid::CellTable::reserve(size_t cells) {
    size_t capacity = std::max<size_t>(64, keys_.slots());
    while (capacity < 2 * cells) capacity *= 2;
    if (capacity > keys_.slots()) rehash(capacity);
}

std::vector<TriangleGrid::Entry>& TriangleGrid::CellTable::operator[](uint64_t key) {
    if (std::vector<Entry>* list = find(key)) return *list;
    if (keys_.needs_room_for(keys_.size() + 1)) rehash(std::max<size_t>(64, 2 * keys_.slots()));
    return lists_[keys_.insert(key)];
}

template <class F>
void TriangleGrid::for_cells(const Vec3& lo, const Vec3& hi, F&& f) const {
    const std::array<int64_t, 3> a = cell_of(lo), b = cell_of(hi);
    for (int64_t x = a[0]; x <= b[0]; ++x)
        for (int64_t y = a[1]; y <= b[1]; ++y)
            for (int64_t z = a[2]; z <= b[2]; ++z) f(cell_key(x, y, z));
}

namespace {
void box_of(const Vec3& a, const Vec3& b, const Vec3& c, Vec3& lo, Vec3& hi) {
    for (int k = 0; k < 3; ++k) {
        lo[k] = std::min({a[k], b[k], c[k]});
        hi[k] = std::max({a[k], b[k], c[k]});
    }
}

// The lattice index of coordinate x, rounded outwards by one step (`down`: below, else
// above) and clamped to the lattice: (x - origin) * scale is off by far less than a step
// (x lies in the frame's box), so the index stays on the side of the exact one.
uint16_t lattice_index(double x, double origin, double scale, bool down) {
    const double q = std::floor((x - origin) * scale) + (down ? -1.0 : 1.0);
    if (!(q > 0.0)) return 0;  // also NaN
    return q >= 65535.0 ? uint16_t(65535) : uint16_t(q);
}
}  // namespace

TriangleGrid::Frame TriangleGrid::Frame::of_box(const Vec3& lo, const Vec3& hi) {
    Frame f;
    f.origin = lo;
    for (int k = 0; k < 3; ++k) {
        // 65000 steps over the extent: the box's points get indices 0..65000, inside
        // the 16 bits with room for the rounding.
        const double extent = hi[k] - lo[k];
        f.scale[k] = extent > 0 && std::isfinite(extent) ? 65000.0 / extent : 0.0;
        if (!std::isfinite(f.scale[k])) f.scale[k] = 0.0;
    }
    return f;
}

TriangleGrid::LatticeBox TriangleGrid::lattice_box(const Vec3& lo, const Vec3& hi) const {
    LatticeBox b;
    for (int k = 0; k < 3; ++k) {
        b.lo[k] = lattice_index(lo[k], frame_.origin[k], frame_.scale[k], true);
        b.hi[k] = lattice_index(hi[k], frame_.origin[k], frame_.scale[k], false);
    }
    return b;
}

bool TriangleGrid::oversized(const Vec3& lo, const Vec3& hi) const {
    double cells = 1.0;
    for (int k = 0; k < 3; ++k) cells *= std::floor(hi[k] / cell_) - std::floor(lo[k] / cell_) + 1.0;
    return cells > 512.0;
}

void TriangleGrid::insert(int32_t id, const Vec3& a, const Vec3& b, const Vec3& c) {
    Vec3 lo, hi;
    box_of(a, b, c, lo, hi);
    // Triangles much larger than a cell are kept in one list that every query sees.
    const LatticeBox box = lattice_box(lo, hi);
    const Entry e{id, box.lo, box.hi};
    if (oversized(lo, hi)) {
        big_.push_back(e);
        return;
    }
    for_cells(lo, hi, [&](uint64_t key) { cells_[key].push_back(e); });
}

void TriangleGrid::insert_all(const std::vector<int32_t>& ids, const std::vector<Tri>& corners,
                              const std::vector<Vec3>& x) {
    for (size_t i = 0; i < ids.size(); ++i) {
        Vec3 lo, hi;
        box_of(x[corners[i][0]], x[corners[i][1]], x[corners[i][2]], lo, hi);
        if (!oversized(lo, hi)) for_cells(lo, hi, [&](uint64_t key) { cells_.count(key); });
    }
    cells_.reserve_counted();
    for (size_t i = 0; i < ids.size(); ++i) {
        const Tri& c = corners[i];
        insert(ids[i], x[c[0]], x[c[1]], x[c[2]]);
    }
}

void TriangleGrid::remove(int32_t id, const Vec3& a, const Vec3& b, const Vec3& c) {
    Vec3 lo, hi;
    box_of(a, b, c, lo, hi);
    auto same_id = [id](const Entry& e) { return e.id == id; };
    if (oversized(lo, hi)) {
        auto pos = std::find_if(big_.begin(), big_.end(), same_id);
        if (pos != big_.end()) big_.erase(pos);
        return;
    }
    for_cells(lo, hi, [&](uint64_t key) {
        std::vector<Entry>* list = cells_.find(key);
        if (!list) return;
        auto pos = std::find_if(list->begin(), list->end(), same_id);
        if (pos != list->end()) {
            *pos = list->back();
            list->pop_back();
        }
    });
}

template <class F>
void TriangleGrid::for_entries(const Vec3& lo, const Vec3& hi, F&& f) const {
    for (const Entry& e : big_) f(e);
    if (oversized(lo, hi)) {
        // A huge query box: every registered triangle is a candidate.
        cells_.for_each([&](const std::vector<Entry>& list) {
            for (const Entry& e : list) f(e);
        });
    } else
    for_cells(lo, hi, [&](uint64_t key) {
        if (const std::vector<Entry>* list = cells_.find(key))
            for (const Entry& e : *list) f(e);
    });
}

void TriangleGrid::query_boxes(const Vec3& lo, const Vec3& hi, std::vector<Entry>& out) const {
    out.clear();
    const LatticeBox box = lattice_box(lo, hi);
    for_entries(lo, hi, [&](const Entry& e) {
        if (!apart(box, e.lo, e.hi)) out.push_back(e);
    });
    std::sort(out.begin(), out.end(), [](const Entry& a, const Entry& b) { return a.id < b.id; });
    out.erase(std::unique(out.begin(), out.end(), [](const Entry& a, const Entry& b) { return a.id == b.id; }),
              out.end());
}

void TriangleGrid::query_within(const Vec3& lo, const Vec3& hi, std::vector<Entry>& out) const {
    out.clear();
    const LatticeBox box = lattice_box(lo, hi);
    for_entries(lo, hi, [&](const Entry& e) {
        for (int k = 0; k < 3; ++k)
            if (e.lo[k] < box.lo[k] || e.hi[k] > box.hi[k]) return;
        out.push_back(e);
    });
}

}  // namespace bpm::detail
