#pragma once
// Small hand-made stars for the direct tests of the vertex-removal stages
// (tests/internal/simplify/removal_*_test.cpp): vertex 0 is the centre, 1..n the link.

#include <cmath>

#include "bpm/surface.h"

namespace bpm::removal_test {

// Centre at the origin, link vertex k at angle angles[k-1] (degrees) and radius radii[k-1]
// in the plane z = 0, centre lifted to `height`. Triangles (0, k, k+1) counter-clockwise;
// `closed` adds (0, n, 1).
inline Surface fan_surface(const std::vector<double>& angles, const std::vector<double>& radii, bool closed,
                           double height = 0.0) {
    Surface s;
    s.vertices.push_back({0.0, 0.0, height});
    for (size_t k = 0; k < angles.size(); ++k) {
        const double a = angles[k] * M_PI / 180.0;
        s.vertices.push_back({radii[k] * std::cos(a), radii[k] * std::sin(a), 0.0});
    }
    const int32_t n = static_cast<int32_t>(angles.size());
    for (int32_t k = 1; k < n; ++k) s.triangles.push_back({0, k, k + 1});
    if (closed) s.triangles.push_back({0, n, 1});
    s.patches.assign(s.triangles.size(), 0);
    return s;
}

// The regular hexagon fan: six equilateral triangles around the origin.
inline Surface hexagon_fan() { return fan_surface({0, 60, 120, 180, 240, 300}, {1, 1, 1, 1, 1, 1}, true); }

// A closed fan whose link is star-shaped but not convex: vertex 4 pulled towards the centre.
inline Surface dented_fan() { return fan_surface({0, 60, 120, 180, 240, 300}, {1, 1, 1, 0.3, 1, 1}, true); }

// The upper half of a disk: the centre is on the boundary, its two boundary edges (to 1
// and to 5) are hard feature edges after CoarseMesh::mark_feature_edges.
inline Surface half_disk_fan() { return fan_surface({0, 45, 90, 135, 180}, {1, 1, 1, 1, 1}, false); }

}  // namespace bpm::removal_test
