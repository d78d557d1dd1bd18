#pragma once
// The corner-wedge guard of the simplifier: on a surface of two or more patches, a
// removal (or an edge flip) must not lay two triangles that share exactly one corner onto
// each other at a smaller angle than a floor, unless its star had such a pair already, and
// then not at a smaller angle. Internal to libbpm.
//
// Why: two triangles a and b with a common corner s whose sectors at s overlap (seen
// along a's normal, an edge of b from s falls inside a's sector, or the other way)
// enclose a thin wedge of volume with its tip at s. Every tetrahedral mesh that keeps the
// coarse triangles as faces fills it with tetrahedra whose dihedral angles are about the
// wedge's angle. The wedge guard (simplify/wedge_guard.h) sees only triangles with a
// common edge; the clearance guard (simplify/clearance_guard.h) measures distances, and
// such a wedge has none at its tip whatever its angle (with one common corner it
// measures the edges opposite it, relative to the size). Noisy 48^3 at --ratio 0.2
// (tests/cli/lib label_images.noisy(48, 3)): a removal beside a junction line put a new
// triangle 0.29 degrees under another sheet's triangle at their common corner (its
// opposite edge 0.2 % of the size away, past the clearance floor), and bpm-mesh's three
// smallest dihedral angles (0.34, 0.55, 0.70 degrees) lay in such wedges (0.29, 0.64,
// 0.70 degrees); noisy 32^3's smallest (1.48) in a sheet folded over onto itself at a
// corner, through edges the ridge guard lets pass one at a time.
//
// Corner wedge of a and b (one common corner s): the smallest angle between a ray from s
// along an edge of one of them and the other's plane, over the rays that fall inside the
// other's sector when projected onto its plane; 90 degrees when none does (the sectors
// are apart, as two triangles of one flat fan that are not neighbours).
//
// The rule, per removal: `after` is the smallest corner wedge between a new triangle and
// an alive triangle outside the removed ones, or another new triangle; `before` the same
// for the removed triangles (among themselves too). Refused when after < min(floor,
// before).
//
// The floor, 4 degrees, on surfaces of two or more patches (label images, several
// materials): noisy 14^3 / 32^3 / 48^3 at --ratio 0.2 kept 1.6 / 3.2 / 5.0 % more
// vertices, and bpm-mesh's smallest dihedral angle rose from 2.66 / 1.48 / 0.34 to 5.12 /
// 2.63 / 1.36 degrees (3: 0.6 / 1.8 / 2.9 % more vertices, 4.13 / 1.86 / 1.02 degrees;
// 5: 2.3 / 5.0 / 7.0 %, 5.12 / 2.35 / 1.36). Only the pairs of different patches: 1.17
// on noisy 48^3, but noisy 32^3's fold stays. On one patch (every reference output but
// two_cubes) it is off: a floor of 4 or 5 changed femur and mech-holes-shark at 10 % and
// at 1000 vertices, and femur's tetrahedra at 10 % got no better (bpm-mesh 10.65 ->
// 10.50 degrees at 5); there bpm-mesh meshes only the inside, and a fold's wedge is as
// often outside.
//
// Floating point: the angles are measured, not topological decisions; the same
// operations in the same order give the same answer on every thread.

#include <cstdint>
#include <vector>

#include "bpm/geometry.h"
#include "simplify/coarse_mesh.h"

namespace bpm::detail {

// The floor (degrees; see the top of this file).
inline constexpr double kCornerWedgeFloorDegrees = 4.0;

inline constexpr const char* kCornerWedgeReason =
    "would lay two triangles with a common corner onto each other (corner wedge floor, min_ridge_angle_degrees)";

// The corner wedge of a and b in degrees (see above): 90 unless they have exactly one
// common corner and their sectors overlap; 90 for a triangle without area.
double corner_wedge_degrees(const std::vector<Vec3>& x, const Tri& a, const Tri& b);

// Does the change of `removed` (alive triangles of `mesh`) into `added` keep the rule
// above (floor in degrees; 0 turns it off)? Always on a mesh of one patch.
bool keeps_corner_wedges(const CoarseMesh& mesh, const std::vector<int32_t>& removed, const std::vector<Tri>& added,
                         double floor_degrees = kCornerWedgeFloorDegrees);

}  // namespace bpm::detail
