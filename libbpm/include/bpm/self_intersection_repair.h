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
// - The triangles must be consistently oriented (neighbours across an edge of two
//   triangles traverse it in opposite directions); otherwise nothing is changed and
//   `refused` names the triangle. Edges of three or more triangles and pinched vertices
//   (fans that meet only at their tip) are no obstacle: the repair sees the sheets there
//   as separate, and they stay as they were. Also refused: a repair whose new triangles
//   would border several patches (an intersection where materials meet: which patch the
//   new triangles belong to is not known).
// - Kept vertices and triangles keep their order (removed ones are dropped); new vertices
//   and triangles follow them. New triangles get the patch of the triangles around them;
//   new vertices the vertex data of the nearest kept vertex on the repaired patch's rim.
//   Kept vertices may move (the repair smooths before it cuts out): they count as changed.
// - The local repairs are CGAL's (Polygon_mesh_processing::experimental::
//   remove_self_intersections: smoothing, else removal and hole filling, growing the
//   region a few times); they can fail on large or tangled intersections, which are then
//   left as they were (`remaining_pairs` > 0), never made worse by more than the rest.
// - Deterministic: the result depends only on the input surface.
// - Progress and cancellation through `context` (bpm::Cancelled).

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
    int64_t moved_vertices = 0;      // kept vertices that the repair moved
    // How far the surface changed, as a fraction of the bounding-box diagonal: the largest
    // distance from a new or moved vertex (and from the centroid of a new triangle) to the
    // input surface, and from a removed triangle's corners and centroid to the repaired one.
    double largest_change = 0.0;
    // Why nothing was changed although the surface intersects itself (empty otherwise).
    std::string refused;
};

SelfIntersectionRepair repair_self_intersections(Surface& surface, const Context& context = {});

}  // namespace bpm
