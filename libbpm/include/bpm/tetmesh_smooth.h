#pragma once
// Quality improvement of a tetrahedral mesh by moving its interior vertices only
// (Krause & Sander §3.3: "the aim is to improve the quality of the mesh ... by moving
// interior vertices"; the discrete topology is kept, so refinement hierarchies stay nested
// combinatorially).
//
// The quality of a tetrahedron is its smallest dihedral angle (signed: negative when the
// tetrahedron is inverted, so the same measure untangles). Vertices that have a
// tetrahedron worse than `target_degrees` around them are visited worst first, in a few
// sweeps, and each visit tries
//   1. smart Laplacian smoothing: the centroid of the vertex's edge neighbours, accepted
//      only if the worst tetrahedron around the vertex gets better (Freitag, "On combining
//      Laplacian and optimization-based mesh smoothing techniques", AMD 220, 1997);
//   2. local optimisation of the worst tetrahedron around the vertex: non-smooth steepest
//      ascent of the minimum of the dihedral angles around it (the search direction is
//      the smallest convex combination of the gradients of the active angles), with a
//      backtracking line search (Freitag & Plassmann, "Local optimization-based
//      simplicial mesh untangling and improvement", IJNME 49, 2000).
// A move is accepted only if the smallest dihedral angle around the vertex increases, and
// no tetrahedron that was positively oriented becomes degenerate or inverted (exact
// orient3d, bpm/predicates.h). So the minimum dihedral angle of the mesh never
// decreases, no tetrahedron is inverted that was not inverted before, and a vertex that is
// not movable keeps its position bit for bit. The angles are compared in floating point,
// as sin(angle) continued monotonically beyond 90 degrees (no atan2; the max-min problem is
// the same); only the inversion decisions are exact.
//
// Interior vertices of every level may move, the coarse ones included: the refined mesh's
// element shapes, not the geometric nesting of its interior in the coarser levels, is what
// this optimises (the hierarchy stays nested combinatorially).

#include <cstdint>
#include <vector>

#include "bpm/context.h"
#include "bpm/geometry.h"
#include "bpm/tetmesh.h"
#include "bpm/tetmesh_smooth_options.h"

namespace bpm {

struct TetSmoothResult {
    int64_t visits = 0;            // vertex visits over all sweeps
    int64_t moves = 0;             // accepted moves (Laplacian and optimisation steps)
    int64_t moved_vertices = 0;    // distinct vertices that moved
    double min_dihedral_before_degrees = 0;  // over all tetrahedra (signed: < 0 if one is inverted)
    double min_dihedral_after_degrees = 0;
    double seconds = 0;
};

// Moves the interior vertices of `mesh` (vertex_parameter_points invalid); vertices on S,
// interfaces between regions included, do not move. \pre tetrahedra are positively
// oriented (inverted ones are allowed and may get untangled, never the other way round).
// \throw OptionError for sweeps < 0, max_iterations < 0 or target_degrees outside (0, 180)
// (above 70.5, the angle of the regular tetrahedron, every vertex is always visited).
TetSmoothResult smooth_tetmesh(TetMesh& mesh, const TetSmoothOptions& options, const Context& context = {});

// The smallest dihedral angle of (a, b, c, d) in degrees; negative when the tetrahedron is
// inverted (orient3d(a, b, c, d) < 0), 0 when it is flat. Floating point (for measuring,
// not for decisions).
double tet_min_dihedral_degrees(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace bpm
