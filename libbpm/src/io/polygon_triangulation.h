#pragma once
// Polygon faces of OFF, OBJ and PLY files split into triangles (the triangulate-polygons
// repair of SurfaceReadOptions). CAD exports and many scanners write quads and larger
// planar polygons; bpm works on triangles only.
//
// Ear clipping in the polygon's own plane: the corners are projected along the largest
// component of the Newell normal (dropping one coordinate, so the projection itself is
// exact), ears are decided with the exact orient2d, and among the valid ears the one
// whose triangle has the best 3D aspect ratio is cut first (ties: the first corner in
// the face's order), as in bpm-simplify's retriangulation. The triangles keep the
// face's orientation. A polygon that is not simple seen along its normal (it crosses
// itself, or is too far from planar for one projection) is refused, never guessed.

#include <cstdint>
#include <string>
#include <vector>

#include "bpm/geometry.h"

namespace bpm::detail {

// Appends corners.size() - 2 triangles to `out`, or returns false with the reason in
// `why` (and `out` unchanged).
bool triangulate_polygon(const std::vector<Vec3>& vertices, const std::vector<int32_t>& corners, std::vector<Tri>& out,
                         std::string& why);

}  // namespace bpm::detail
