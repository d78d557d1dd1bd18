#pragma once
// The wedge guard of the simplifier: a removal (or an edge flip) must not make the wedge
// between two neighbouring sheets of a junction edge (an edge of three or more triangles)
// thinner than kJunctionWedgeFloorDegrees, unless it was thinner already, and then it may
// only stay or widen. Internal to libbpm.
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
// folded one sheet onto its neighbour: noisy 32^3 at --ratio 0.2 had 124 junction wedges
// below 1 degree, the smallest 1.1e-13 degrees, where the original's smallest was 4.45; the
// tetrahedral mesh had the same 1.2e-13 degrees (spec/tetmesh.md; tests/cli noisy label
// images). The sheet-order guard (simplify/sheet_guard.h) only asks that a new sheet lie
// strictly inside its wedge, which a sheet 1e-13 degrees from its neighbour does.
//
// The rule, for every edge a -- b of a new triangle that has three or more triangles after
// the change: `after` is the smallest angle between cyclically neighbouring sheets there
// after the change, `before` the same before it (for the new edge a -- b of a removal along
// a junction line through v, the smaller of those at a -- v and v -- b, the edges it
// replaces). Refused when after < min(kJunctionWedgeFloorDegrees, before): the coarse
// surface's junction wedges stay at least min(floor, the original's smallest) wide.
// Edges with two triangles after the change are the ridge guard's, not this guard's.
//
// Floating point: the angles are measured, not topological decisions (the sheet order is
// decided exactly by the sheet-order guard); the same operations in the same order give
// the same answer on every thread.

#include <cstdint>
#include <vector>

#include "bpm/geometry.h"
#include "simplify/coarse_mesh.h"

namespace bpm::detail {

// Junction wedges are kept at least this wide (degrees) where the coarse surface has
// them so wide. See bench/RESULTS.md, "Junction wedges", for the floors measured.
inline constexpr double kJunctionWedgeFloorDegrees = 15.0;

// The reason recorded for a refused removal.
inline constexpr const char* kJunctionWedgeReason =
    "would make a wedge between two sheets of a junction edge thinner (junction wedge floor)";

// The smallest angle (degrees, in [0, 360]) between cyclically neighbouring half-planes of
// the triangles (a, b, apexes[i]) around the line through a and b; 360 for fewer than two.
double smallest_wedge_degrees(const Vec3& a, const Vec3& b, const std::vector<Vec3>& apexes);

struct WedgeScratch {
    std::vector<int32_t> tris;
    std::vector<Vec3> apexes;
};

// Does the change of `removed` (alive triangles of `mesh`) into `added` keep the rule
// above? `line_v`: the vertex removed along a feature line from line_a -- line_v --
// line_b (the plan's feature_a, feature_b), else -1.
bool keeps_junction_wedges(const CoarseMesh& mesh, const std::vector<int32_t>& removed, const std::vector<Tri>& added,
                           int32_t line_a, int32_t line_v, int32_t line_b, WedgeScratch& scratch,
                           double floor_degrees = kJunctionWedgeFloorDegrees);

}  // namespace bpm::detail
