#pragma once
// Planar regions of the coarse surface for refinement's Hausdorff bound: sets of coarse
// triangles that, together with phi's image of them, lie in one plane (up to a measured
// offset). On such a region phi may move points within the plane (tangential drift: the
// simplifier's or bpm-smooth's parameter positions are not the points' own positions)
// without any geometric error, and max |flat - phi| would count that drift. Refiner::
// region_bounds (refine.cpp) proves a bound for the whole region from its boundary and
// its offsets from the plane instead; the argument is there.

#include <array>
#include <cstdint>
#include <vector>

#include "bpm/geometry.h"
#include "bpm/parametrization.h"

namespace bpm::detail {

struct PlanarRegion {
    Vec3 origin{0, 0, 0};  // a point of the reference plane (a corner of its first triangle)
    Vec3 normal{0, 0, 1};  // unit normal of the reference plane
    int axis = 2;          // the coordinate the projection drops: the largest |normal| component
    // Largest |vertical_offset| of phi's node images in the region's coarse triangles
    // (absolute length): phi's image of the region is within this of the plane along `axis`.
    double phi_offset = 0;
    // Sign of every piece of phi in the region, projected (orient2d of the projected node
    // images times the piece's orientation in its parameter triangle): all the same.
    int piece_sign = 0;
};

// Where a point is relative to the segment between a coarse edge's corners a and b:
// `off` its distance from the line ab, `overshoot` how far beyond a or b along it (0
// between them); both absolute lengths, maxima over the points added.
struct LineDeviation {
    double off = 0, overshoot = 0;
    void add(const Vec3& a, const Vec3& b, const Vec3& x);
};

struct PlanarRegions {
    std::vector<PlanarRegion> regions;
    // Per coarse triangle: its region, -1 = none.
    std::vector<int32_t> region;
    // Per coarse triangle and local edge k (corners k, k+1), for triangles in a region:
    // whether the edge is on the region's boundary (not shared with a consistently
    // oriented triangle of the same region), and phi's node images on it relative to the
    // segment between its corners.
    std::vector<std::array<uint8_t, 3>> boundary;
    std::vector<std::array<LineDeviation, 3>> phi_line;

    // The point projected to 2D by dropping region.axis (exact: no arithmetic).
    static Vec2 project(const PlanarRegion& region, const Vec3& x);
    // Signed distance of x from the reference plane along region.axis: two points with the
    // same projection are |vertical_offset(x) - vertical_offset(y)| apart.
    static double vertical_offset(const PlanarRegion& region, const Vec3& x);
};

// Groups the coarse triangles of `p` into planar regions: a region grows from its first
// triangle (lowest index) across coarse edges to consistently oriented neighbours whose
// corners and node images are all within 1e-6 of the diagonal of the first triangle's
// plane and whose pieces project with the region's sign. Triangles with phi's pieces
// projecting with mixed signs belong to none. Deterministic.
PlanarRegions planar_regions(const Parametrization& p, double diagonal);

}  // namespace bpm::detail
