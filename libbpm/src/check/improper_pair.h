#pragma once
// The exact decision check_intersections makes for each candidate pair, for the
// callers that find the candidates another way (the simplifier's input check walks the
// grid it builds anyway, simplify/intersection_test.h). Internal to libbpm.

#include <vector>

#include "bpm/geometry.h"
#include "bpm/surface.h"

namespace bpm::detail {

// Whether triangles A and B (corners: indices into V) meet other than in the vertices
// they share and the edge between two of those, decided exactly (orientation tests for
// the common neighbours sharing one vertex or an edge, else
// nondegenerate_triangles_intersect_improperly).
// Precondition: neither triangle is degenerate (a repeated corner or collinear corners).
bool surface_triangles_meet_improperly(const std::vector<Vec3>& V, const Tri& A, const Tri& B);

}  // namespace bpm::detail
