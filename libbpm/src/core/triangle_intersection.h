#pragma once
// triangles_intersect_improperly (bpm/predicates.h) without its per-pair degeneracy test,
// for callers that reject degenerate triangles once per triangle (check_intersections).
// That test is exact, and on the thin triangles of a refined surface it falls to exact
// arithmetic for every candidate pair: 15 % of bpm-refine's intersection remedy on femur
// 10 % at --max-error 0.0003 (perf).

#include "bpm/geometry.h"

namespace bpm::detail {

// Precondition: neither triangle has a repeated corner or collinear corners
// (collinear3d); the answer is then triangles_intersect_improperly's.
bool nondegenerate_triangles_intersect_improperly(const Vec3 a[3], const Vec3 b[3], const int shared[3]);

}  // namespace bpm::detail
