#pragma once
// The exact orientation of three points of a parameter triangle given by their
// barycentric coordinates: sign det[p; q; x] times the sign of the identity basis. It is
// the orientation of (p, q, x) in the parameter plane for any positive scaling of the
// rows, so it is exact even when stored coordinates sum to 1 only up to rounding (which
// orient2d on two of the coordinates is not). +1 counter-clockwise, -1 clockwise, 0
// collinear.

#include "bpm/geometry.h"
#include "bpm/predicates.h"

namespace bpm::detail {

inline int orient_barycentric(const Vec3& p, const Vec3& q, const Vec3& x) {
    static const int sign = orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
    return sign * orient3d({0, 0, 0}, p, q, x);
}

}  // namespace bpm::detail
