#pragma once
// The clearance guard of the simplifier: a removal must not bring a new triangle closer to
// another triangle of the coarse surface than kClearanceFloor times the longer of their
// longest edges, unless its star was that close already, and then it may not come closer.
// Internal to libbpm.
//
// Why: the intersection test (simplify/intersection_test.h) decides exactly whether two
// triangles meet, so two sheets may pass each other at any distance above zero. Every
// tetrahedral mesh of the coarse surface S that keeps S's triangles as faces has
// tetrahedra spanning such a gap, whose dihedral angles are about gap / size of the
// triangles. Noisy 48^3 at --ratio 0.2 (tests/cli/lib label_images.noisy(48, 3)), with
// the wedge guard (simplify/wedge_guard.h): a new coarse edge passed 2.8e-6 from another
// (both 0.1-0.14 long, at vertices the surface nets split where a label touches itself at
// a corner), and bpm-mesh's smallest dihedral angle was 4.4e-6 degrees.
//
// Clearance of two triangles a and b: with no common vertex, their distance; with one
// common vertex, the smaller of the distances from each one's edge opposite it to the
// other triangle; with a common edge none (their wedge is the wedge guard's). Relative:
// divided by the larger of their longest edges (a vertex hovering over a large triangle
// bounds the tetrahedra on that triangle).
//
// The floor, 0.1 %: the reference outputs (scripts/reference-outputs.sh) are
// byte-identical with it; 0.3 % changed femur at 10 % (same error, worst R/r 22.8 -> 20.4,
// bpm-mesh 10.65 -> 10.88 degrees) and mech-holes-shark at 10 %. At 0.1 % it lets pass the
// next near-contact of noisy 48^3 at 0.2, a coarse vertex 0.0084 (0.17 %) above a triangle
// of edges 2.8-4.9, whose tetrahedron has 0.30 degrees.
//
// With two or more patches the floor is 1 % (kMultiPatchClearanceFloor): with the
// corner-wedge guard (simplify/corner_wedge_guard.h), noisy 48^3 at 0.2's smallest
// bpm-mesh angle (1.36 degrees) lay on a triangle of edges 4.5-6.1 with a vertex of a
// small closed component (an island of one label) 0.7 % of its longest edge above it; at
// 1 % the angle is 2.58 and 6 more vertices stay (25723 -> 25729; noisy 32^3 one more,
// 14^3 none; 0.5 % changed nothing). On one patch the reference outputs keep 0.1 %.
//
// The rule, per removal: `after` is the smallest relative clearance between a new
// triangle and an alive triangle outside the removed ones or another new triangle,
// `before` the same for the removed triangles. Refused when after < min(kClearanceFloor,
// before). The final edge flips (simplify/edge_flip.h) are guarded the same way (their
// two triangles out, two in): a flip's new edge lies off the old surface, up to the
// height of the tetrahedron between the two pairs, and may bring it nearer another sheet.
//
// Floating point: distances are measured, not topological decisions.
//
// Cost: keeps_clearance measures exactly (relative_clearance) only the parts of pairs
// that boxes and separating axes (each triangle's normal and in-plane edge normals) do
// not show to lie beyond the floor, with a margin for rounding; its answer is the same
// bit for bit as measuring every pair the box filter lets through.

#include <cstdint>
#include <vector>

#include "bpm/geometry.h"
#include "core/triangle_grid.h"
#include "simplify/coarse_mesh.h"

namespace bpm::detail {

inline constexpr double kClearanceFloor = 0.001;
// The floor on surfaces of two or more patches (label images, several materials).
inline constexpr double kMultiPatchClearanceFloor = 0.01;

inline constexpr const char* kClearanceReason =
    "would bring two sheets of the coarse surface closer than 0.1 % of their triangles' size, 1 % with two or more patches (clearance, min_ridge_angle_degrees)";

// Relative clearance of triangles a and b (see above); +infinity when they share an edge.
double relative_clearance(const std::vector<Vec3>& x, const Tri& a, const Tri& b);

// The length of t's longest edge (keeps_clearance's `longest_edge` is the largest over the
// alive triangles).
double longest_edge(const std::vector<Vec3>& x, const Tri& t);

// `grid`: the alive triangles' boxes (it may still hold removed ones, and lack `also`:
// the new triangles of the removals committed earlier in the same step, which are
// compared as well). `longest_edge`: at least the longest edge of any alive triangle.
bool keeps_clearance(const CoarseMesh& mesh, const TriangleGrid& grid, const std::vector<int32_t>& removed,
                     const std::vector<Tri>& added, const std::vector<Tri>& also, double longest_edge,
                     std::vector<TriangleGrid::Entry>& scratch, double floor = kClearanceFloor);

}  // namespace bpm::detail
