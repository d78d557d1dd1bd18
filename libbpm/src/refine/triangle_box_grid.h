#pragma once
// A uniform grid over the bounding boxes of a surface's triangles, for the intersection
// remedy's release step (Refiner::release, refine.cpp): which triangles may meet a box,
// without scanning every triangle per query. Why: release asks once per vertex held back
// farther than the tolerance, and a scan made that (held-back vertices x triangles):
// femur 10 % at T = 0.0003, 397 x 323k = 128M box tests in pass 1, 1.05M with the grid
// (T = 0.0002: 762 x 563k = 429M, 3.5M). The grid is built once per release and kept
// current where vertices move (update: only the moved vertices' incident triangles
// change their boxes).
//
// Candidates are a superset of the triangles whose current box meets the query box
// (closed boxes, as `lo <= hi` comparisons): cell indices are clamped to the grid, and
// clamping is monotone, so two boxes that meet share a cell even where a vertex has
// moved outside the box the grid was built on. Callers filter them with their own
// exact test.

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "bpm/surface.h"

namespace bpm::detail {

class TriangleBoxGrid {
public:
    // Files every triangle of `surface` under the cells its box covers (positions as they
    // are now). Deterministic: the cells depend on the positions only.
    explicit TriangleBoxGrid(const Surface& surface);

    // Triangle t's corners moved: re-files it under its box at the current positions.
    void update(const Surface& surface, int32_t t);

    // Every triangle whose box (as last filed) meets [lo, hi], and maybe others, each
    // once, in ascending order, into `out` (replaced).
    void candidates(const Vec3& lo, const Vec3& hi, std::vector<int32_t>& out);

    // Triangle ids looked at by candidates() so far (with repeats across cells): the
    // grid's work, against the triangles x queries of a scan.
    int64_t visited() const { return visited_; }

private:
    using CellRange = std::array<int32_t, 6>;  // i0, i1, j0, j1, k0, k1 (inclusive)
    CellRange range(const Vec3& lo, const Vec3& hi) const;
    CellRange range_of(const Surface& surface, int32_t t) const;
    void file(int32_t t, const CellRange& r);
    void unfile(int32_t t, const CellRange& r);
    static bool large(const CellRange& r);
    size_t cell(int32_t i, int32_t j, int32_t k) const {
        return (size_t(i) * size_t(n_[1]) + size_t(j)) * size_t(n_[2]) + size_t(k);
    }

    Vec3 origin_{0, 0, 0};
    double inverse_size_ = 1;       // 1 / cell edge length (cubic cells)
    std::array<int32_t, 3> n_{1, 1, 1};  // cells per axis
    // The filing at construction, cell by cell (cell c: entries [start_[c], start_[c + 1])),
    // -1 where a triangle has been re-filed since; later filings go to `moved_`, by cell.
    // Why two: one block is built without an allocation per cell, and few cells see a
    // moved triangle (a vector per cell made a release call on 55k triangles cost 15 ms
    // more, mostly page faults, than the scans of femur 10 % at T = 0.001's 1-12 queries).
    std::vector<int64_t> start_;
    std::vector<int32_t> filed_at_start_;
    std::unordered_map<size_t, std::vector<int32_t>> moved_;
    // Triangles covering more than kLargeCells cells: looked at by every query instead of
    // filed in each cell (a stretched triangle would fill a whole row of cells).
    std::vector<int32_t> large_;
    std::vector<CellRange> filed_;  // per triangle: the cells it is filed under
    std::vector<uint32_t> stamp_;   // per triangle: the query that last returned it
    uint32_t query_ = 0;
    int64_t visited_ = 0;
};

}  // namespace bpm::detail
