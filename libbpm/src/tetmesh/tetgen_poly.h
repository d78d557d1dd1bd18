#pragma once
// TetGen's input format, written by generate_tetmesh (tetmesh.cpp); not public API
// (the unit tests check it directly).

#include <string>
#include <vector>

#include "bpm/geometry.h"
#include "bpm/surface.h"

namespace bpm {

// The surface as a TetGen .poly file (0-based, facet markers = patch ids), with the given
// region points (`region_points[r]` gets region attribute r + 1).
std::string tetgen_poly(const Surface& surface, const std::vector<Vec3>& region_points);

}  // namespace bpm
