#pragma once
// Repair (tools: --repair-self-intersections) for an input that intersects itself in a
// few places: a laser scan whose thin parts were reconstructed through each other, a
// segmentation whose surface folds over at a narrow gap. bpm refuses such an input
// (its coarse surface could not be free of intersections either, and a mesh generator
// needs one that is); this replaces the triangles around each intersection by a new
// local patch, so that the rest of the surface is kept exactly.
//
// Contract:
// - Only where intersections are: a surface without any (bpm::check_intersections) is
//   left untouched, and so is every triangle away from them. The surface the coarse
//   surface and phi then describe is the repaired one, not the file's.
// - All or nothing: the surface changes only if the repair removes intersections, makes
//   no new one (every pair left is one of the input's, between kept triangles) and moves
//   the surface by no more than options.max_change; otherwise it is left as it was and
//   `refused` says why.
// - The triangles should be consistently oriented; an edge of three or more triangles, a
//   pinched vertex (fans that meet only at their tip) or a triangle turned against its
//   neighbours makes the repair see separate sheets there, which stay as they were.
//   Refused: a repair whose new triangles would border several patches (an intersection
//   where materials meet: which patch the new triangles belong to is not known).
// - Kept vertices and triangles keep their order and positions (removed ones are dropped);
//   new vertices and triangles follow them. New triangles get the patch of the triangles
//   around them; new vertices the vertex data of the nearest input vertex of the replaced
//   region. The topology may change (a pinch opened, a handle cut): `topology_change`.
// - The local repairs are CGAL's (Polygon_mesh_processing::experimental::
//   remove_self_intersections: smoothing, else removal and hole filling, growing the
//   region a few times); they can fail on large or tangled intersections.
// - Deterministic: the result depends only on the input surface and the options.
// - Progress and cancellation through `context` (bpm::Cancelled; the surface is then
//   unchanged). \throw std::invalid_argument if patches and triangles differ in number, a
//   vertex data array is malformed, an index is out of range, a coordinate not finite, or
//   options.max_change is not a number >= 0.

#include <cstdint>
#include <string>

#include "bpm/context.h"
#include "bpm/surface.h"

namespace bpm {

struct SelfIntersectionRepair {
    int64_t intersecting_pairs = 0;  // before (bpm::check_intersections' count)
    int64_t remaining_pairs = 0;     // after; 0 when every intersection was repaired
    int64_t removed_triangles = 0;   // replaced (their indices are gone)
    int64_t added_triangles = 0;
    int64_t removed_vertices = 0;    // no kept triangle uses them any more
    int64_t added_vertices = 0;
    // How far the surface changed, as a fraction of the bounding-box diagonal: the largest
    // distance from a new vertex (and from the centroid of a new triangle) to the input
    // surface, and from a removed triangle's corners and centroid to the repaired one
    // (measured at those points, so about, not at most).
    double largest_change = 0.0;
    // describe_topology() before " -> " after, when the repair changed it; else empty.
    std::string topology_change;
    // Why nothing was changed although the surface intersects itself (empty otherwise).
    std::string refused;
};

struct SelfIntersectionRepairOptions {
    // The largest change (SelfIntersectionRepair::largest_change) accepted: a repair that
    // would move the surface further is refused, since it is no longer local (a loose
    // shell replaced whole, a thin part cut off). Scans' few crossings need 1e-4 to 5e-3.
    double max_change = 0.01;
};

SelfIntersectionRepair repair_self_intersections(Surface& surface, const SelfIntersectionRepairOptions& options = {},
                                                 const Context& context = {});

}  // namespace bpm
