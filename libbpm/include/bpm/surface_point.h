#pragma once
// A point on the coarse surface S: the parameter point of phi.
//
// One value type for "a coarse triangle and barycentric coordinates in it", used by every
// part of the API that takes or returns a point of S (phi and its inverse, the parameter
// points of tet-mesh vertices, boundary midpoints, the repair after refinement), instead
// of parallel arrays of triangles and barycentrics.
//
// Conventions (those of bpm/parametrization.h and spec/bpm-format.md): the barycentric
// coordinates (b0, b1, b2) refer to the corners (c0, c1, c2) of coarse triangle
// `triangle` in their stored order, b0 + b1 + b2 = 1 and all >= 0. A point on a coarse
// edge or corner lies in every coarse triangle that contains it; any of them may be used.

#include <cstdint>

#include "bpm/geometry.h"

namespace bpm {

struct SurfacePoint {
    int32_t triangle = -1;          // coarse triangle, 0 <= triangle < #S.T; -1 = no point (e.g. an interior vertex)
    Vec3 barycentric{0, 0, 0};      // in that triangle's corner order

    bool valid() const { return triangle >= 0; }
};

inline bool operator==(const SurfacePoint& a, const SurfacePoint& b) {
    return a.triangle == b.triangle && a.barycentric == b.barycentric;
}
inline bool operator!=(const SurfacePoint& a, const SurfacePoint& b) { return !(a == b); }

}  // namespace bpm
