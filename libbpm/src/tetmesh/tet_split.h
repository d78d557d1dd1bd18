#pragma once
// Splits the level-0 tetrahedra whose refinement would make tetrahedra with all four corners
// on S (not public API; generate_tetmesh runs it).
//
// Why: phi moves the boundary vertices of a refined mesh onto the original surface, which is
// smooth at the scale of a fine level; four points of it close together are nearly coplanar,
// so a tetrahedron with all four corners on S gets flat (or inverted) at phi, and the repair
// (bpm/boundary_repair.h) can only hold its corners back or slide them. Refinement makes such
// tetrahedra at every level below a level-0 tetrahedron with a *surface corner*: a corner v
// whose three edges in the tetrahedron are all edges of S (e.g. a tetrahedron with two faces
// on S, on two neighbouring coarse triangles; or one at a coarse vertex). Red refinement's
// corner child at v has v and the midpoints of those three edges, all on S, and it has a
// surface corner again, flatter at each level (femur at 10 %: deal.II level 3 4.48 degrees,
// DUNE adaptive steps 5/6 3.49/2.63 before the repair's slide).
//
// Why this criterion suffices: a child's corners are its parent's corners and edge
// midpoints; a midpoint is on S only if its edge is an edge of S. A tetrahedron with at most
// three corners on S therefore has no child with four (its points on S lie in the plane of
// those three corners, and children are not flat), whatever the refinement rule (red, UG's
// green closures, deal.II's). A tetrahedron with four corners on S has a red child with four
// only if a corner has three edges on S (the corner child), or its octahedron has a
// tetrahedron of four midpoints of edges on S, i.e. two opposite edges and two edges through
// a common corner, which then has three edges on S too. So once no level-0 tetrahedron has a
// surface corner, no level of red refinement has a tetrahedron with four corners on S.
//
// How: for each such tetrahedron t (index order), its longest edge that is not an edge of S
// is split at its midpoint m, with every tetrahedron around it: (.., c, .., d, ..) becomes
// the same with d -> m and with c -> m. m is strictly inside a region (the edge is not on S,
// and at level 0 every edge of the mesh that lies on S is an edge of S), every tetrahedron
// containing m has at most three corners on S, no face on S changes, the children keep their
// parent's region. Tetrahedra whose six edges are all on S (a thin part of S enclosed by a
// few coarse triangles) get a vertex at their centroid instead (1-4 split). A split is made
// only if every new tetrahedron is positively oriented (exact orient3d); a tetrahedron none
// of whose candidates passes stays (counted in `left`). The new vertices are appended to x;
// generate_tetmesh then runs the vertex insertion and the flips (keeping surface corners
// out) and smooths them (they are interior vertices).
// Deterministic.

#include <cstdint>
#include <vector>

#include "bpm/geometry.h"
#include "bpm/tetmesh.h"

namespace bpm::detail {

// The edges of S (sorted vertex pairs, sorted): those of `faces`.
std::vector<std::array<int32_t, 2>> surface_edges(const std::vector<Tri>& faces);

// Does tetrahedron t have a corner whose three edges are all in `edges` (surface_edges)?
bool has_surface_corner(const Tet& t, const std::vector<std::array<int32_t, 2>>& edges);

struct TetSplitResult {
    int64_t found = 0;          // tetrahedra with a surface corner before
    int64_t edge_splits = 0;    // edges split at their midpoints (a vertex each)
    int64_t centroid_splits = 0;  // 1-4 splits (a vertex each)
    int64_t left = 0;           // tetrahedra with a surface corner after (no valid split)
    double seconds = 0;
};

// Splits every tetrahedron of `tets` over x that has a surface corner (see the top of this
// file). Every tetrahedron is positively oriented; regions (#Tet) follow them. New vertices
// are appended to x; split tetrahedra are replaced in place by a child and the other
// children appended. \pre the mesh is conforming and every edge of it that lies on S is an
// edge of `faces` (true at level 0: S is a union of faces of the mesh).
TetSplitResult split_surface_corners(std::vector<Vec3>& x, std::vector<Tet>& tets, std::vector<int32_t>& regions,
                                     const std::vector<Tri>& faces);

}  // namespace bpm::detail
