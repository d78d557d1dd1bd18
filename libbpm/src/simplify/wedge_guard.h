#pragma once
// The wedge guard of the simplifier: a removal (or an edge flip) must not make the wedge
// between two neighbouring sheets at a feature edge thinner than a floor, unless it was
// thinner already, and then it may only stay or widen. The floor is
// kJunctionWedgeFloorDegrees at junction edges (three or more triangles) and
// kCreaseWedgeFloorDegrees at feature edges of two triangles (creases, patch borders),
// both at most SimplifyOptions::min_ridge_angle_degrees (0 turns the guard off with the
// ridge guard). Internal to libbpm.
//
// Why: every tetrahedral mesh of the coarse surface S that has S's triangles among its
// faces (bpm-mesh keeps S exactly) has a tetrahedron inside every wedge of S at every edge
// of S, and that tetrahedron's dihedral angle at the edge is at most the wedge's angle.
// The smallest wedge of S is so an upper bound of the mesh's smallest dihedral angle that
// no TetGen switch, flip, Steiner point or smoothing can lift (a Steiner point on the edge
// does not either: the two planes meet along the whole edge). The ridge guard
// (simplify/ridge_guard.h) keeps the wedges of edges with two triangles open, but exempts
// feature edges, and every junction edge is one. On noisy label images (three and more
// materials, junction lines everywhere) the removals along and beside the junction lines
// folded one sheet onto its neighbour: noisy 32^3 at --ratio 0.2 (tests/cli/lib
// label_images.noisy(32, 3)) had 124 junction wedges below 1 degree, the smallest 1.1e-13
// degrees, where the original's smallest was 4.45, and bpm-mesh's smallest dihedral angle
// was 1.2e-13 degrees. The sheet-order guard (simplify/sheet_guard.h) only asks that a new
// sheet lie strictly inside its wedge, which a sheet 1e-13 degrees from its neighbour does.
// With the junction floor alone the smallest wedge there was a crease of 1.3 degrees.
//
// The floors: 15 degrees at junctions (noisy 14^3 and 32^3 at --ratio 0.2 kept 1.8 % and
// 2.2 % more vertices, the same error); 5 at creases, where the ridge guard's notes found
// guarding scans' creases costly: the reference outputs of the five benchmark meshes and
// two_cubes are byte-identical with it (10 changed mech-holes-shark's), and it takes the
// noisy images' smallest crease wedges from 1.3-1.9 to 5.2-5.4 degrees.
//
// The rule, for every edge a -- b of a new triangle that is a feature edge (or the new edge
// of a removal along a feature line) with two or more triangles after the change: `after`
// is the smallest angle between cyclically neighbouring sheets there after the change
// (for two triangles: the ridge angle), `before` the same before it (for the new edge
// a -- b of a removal along a feature line through v, the smaller of those at a -- v and
// v -- b, the edges it replaces). Refused when after < min(floor, before): the coarse
// surface's wedges at feature edges stay at least min(floor, the original's smallest).
//
// Floating point: the angles are measured, not topological decisions (the sheet order is
// decided exactly by the sheet-order guard); the same operations in the same order give
// the same answer on every thread.

#include <cstdint>
#include <vector>

#include "bpm/geometry.h"
#include "simplify/coarse_mesh.h"

namespace bpm::detail {

// The floors (degrees; see the top of this file).
inline constexpr double kJunctionWedgeFloorDegrees = 15.0;
inline constexpr double kCreaseWedgeFloorDegrees = 5.0;

// The reason recorded for a refused removal.
inline constexpr const char* kJunctionWedgeReason =
    "would make a wedge between two sheets of a feature edge thinner (wedge floor, min_ridge_angle_degrees)";

// The smallest angle (degrees, in [0, 360]) between cyclically neighbouring half-planes of
// the triangles (a, b, apexes[i]) around the line through a and b; 360 for fewer than two.
double smallest_wedge_degrees(const Vec3& a, const Vec3& b, const std::vector<Vec3>& apexes);

struct WedgeScratch {
    std::vector<int32_t> tris;
    std::vector<Vec3> apexes;
};

// Does the change of `removed` (alive triangles of `mesh`) into `added` keep the rule
// above (floors in degrees)? `line_v`: the vertex removed along a feature line from line_a -- line_v --
// line_b (the plan's feature_a, feature_b), else -1.
bool keeps_feature_wedges(const CoarseMesh& mesh, const std::vector<int32_t>& removed, const std::vector<Tri>& added,
                           int32_t line_a, int32_t line_v, int32_t line_b, WedgeScratch& scratch,
                           double junction_floor_degrees = kJunctionWedgeFloorDegrees,
                           double crease_floor_degrees = kCreaseWedgeFloorDegrees);

}  // namespace bpm::detail
