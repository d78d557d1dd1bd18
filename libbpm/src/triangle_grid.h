#pragma once
// A uniform grid over triangle bounding boxes, for finding the triangles near a new
// one while the surface changes. Internal to libbpm.

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "bpm/geometry.h"

namespace bpm::detail {

class TriangleGrid {
public:
    // `cell` is the edge length of a grid cell.
    explicit TriangleGrid(double cell) : cell_(cell) {}
    double cell() const { return cell_; }
    void insert(int32_t id, const Vec3& a, const Vec3& b, const Vec3& c);
    void remove(int32_t id, const Vec3& a, const Vec3& b, const Vec3& c);
    // Ids of triangles whose cells overlap the box [lo, hi] (may repeat; sorted unique on return).
    void query(const Vec3& lo, const Vec3& hi, std::vector<int32_t>& out) const;
    void clear() {
        cells_.clear();
        big_.clear();
    }

private:
    double cell_;
    std::unordered_map<uint64_t, std::vector<int32_t>> cells_;
    std::vector<int32_t> big_;  // triangles spanning too many cells
    bool oversized(const Vec3& lo, const Vec3& hi) const;
    template <class F>
    void for_cells(const Vec3& lo, const Vec3& hi, F&& f) const;
};

}  // namespace bpm::detail
