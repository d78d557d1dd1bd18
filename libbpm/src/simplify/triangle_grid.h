#pragma once
// A uniform grid over triangle bounding boxes, for finding the triangles near a new
// one while the surface changes. Internal to libbpm.

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "bpm/geometry.h"

namespace bpm::detail {

class TriangleGrid {
public:
    // A triangle with its bounding box, as stored in the cells: queries test the boxes
    // while they scan a cell, without looking the triangles up. The box is in float,
    // rounded outwards (it only filters candidates for exact tests, and a triangle sits
    // in several cells, so the entries are a large part of the simplifier's memory).
    struct Entry {
        int32_t id;
        std::array<float, 3> lo, hi;
    };

    // `cell` is the edge length of a grid cell.
    explicit TriangleGrid(double cell) : cell_(cell) {}
    double cell() const { return cell_; }
    void insert(int32_t id, const Vec3& a, const Vec3& b, const Vec3& c);
    void remove(int32_t id, const Vec3& a, const Vec3& b, const Vec3& c);
    // insert() of triangle ids[i] with corners x[corners[i][0..2]] for every i, into an
    // empty grid: the cells are counted first and each list allocated once at its size
    // (inserting one by one grows every list several times and leaves it up to half empty).
    void insert_all(const std::vector<int32_t>& ids, const std::vector<Tri>& corners, const std::vector<Vec3>& x);
    // The triangles whose bounding box meets the closed box [lo, hi], sorted by id,
    // each once.
    void query_boxes(const Vec3& lo, const Vec3& hi, std::vector<Entry>& out) const;
    void clear() {
        cells_.clear();
        big_.clear();
    }

private:
    double cell_;
    std::unordered_map<uint64_t, std::vector<Entry>> cells_;
    std::vector<Entry> big_;  // triangles spanning too many cells
    bool oversized(const Vec3& lo, const Vec3& hi) const;
    template <class F>
    void for_cells(const Vec3& lo, const Vec3& hi, F&& f) const;
    // Calls f(entry) for every stored entry of a cell the box overlaps (repeats possible).
    template <class F>
    void for_entries(const Vec3& lo, const Vec3& hi, F&& f) const;
};

}  // namespace bpm::detail
