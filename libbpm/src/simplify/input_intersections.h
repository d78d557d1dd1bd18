#pragma once
// Whether the simplifier's input passes check_intersections, decided on the grid the
// simplifier builds for its own intersection tests (IntersectionTest) instead of on a
// second spatial structure: the check's box intersection (its float boxes, their sort
// and segment tree) and the grid were two structures over the same triangles, ~20 % of
// the floor (bpm-simplify --ratio 1) on 832k triangles. Internal to libbpm.
//
// Every pair of triangles whose bounding boxes meet shares a grid cell (the cell of the
// low corner of the boxes' intersection: the grid places a box by floor(x / cell) of
// its corners, which is monotone in x) and has lattice boxes that are not apart (they
// are rounded outwards). Each such pair is decided once, in that cell, by the check's
// own exact decision (check/improper_pair.h): the pairs that meet improperly, and so
// the verdict, are exactly the check's. Only the verdict: a surface that may fail is
// left to check_intersections itself, for its report.

#include "bpm/surface.h"
#include "core/triangle_grid.h"

namespace bpm::detail {

// True when check_intersections(surface) passes: no triangle is degenerate (a repeated
// corner, collinear corners) and no two meet improperly. False when it fails, or when
// the walk would be slow (many triangles too large for the grid's cells) or the
// surface is not one the check examines: check_intersections decides then.
// `grid` holds exactly the triangles of `surface`, by index (IntersectionTest of a
// CoarseMesh made from it, before any change).
bool surely_passes_intersection_check(const Surface& surface, const TriangleGrid& grid);

}  // namespace bpm::detail
