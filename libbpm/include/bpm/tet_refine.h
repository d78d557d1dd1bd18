#pragma once
// Uniform red refinement of a tetrahedral mesh whose boundary is the coarse surface S,
// with the new boundary vertices moved onto the original surface S0 through phi
// (Krause & Sander §3, §3.3).
//
// Each level splits every tetrahedron into 8 by Bey's rule (J. Bey, "Simplicial grid
// refinement: on Freudenthal's algorithm and the optimal number of congruence classes",
// Numer. Math. 85, 2000: children ordered so that repeated refinement produces at most 3
// similarity classes per initial tetrahedron) and every face on S into 4. A new vertex is
// the midpoint x of an edge of the current (already moved) mesh. If the edge lies on S,
// the vertex's parameter position (a coarse triangle and barycentric coordinates there,
// the midpoint of its ends' parameter positions) is known exactly, and the vertex is moved
// to phi of it. Where that would invert a tetrahedron, the §3.3 remedy places the vertex
// at lambda*x + (1-lambda)*phi(x) instead, with the largest fraction 1-lambda in [0, 1]
// (bisection) that keeps every tetrahedron around it positively oriented (exact orient3d);
// lambda = 1 is plain red refinement, which is always valid because the children of a
// positive tetrahedron are positive. To avoid nearly flat elements at the bisection's
// limit, "admissible" also asks each tetrahedron to keep a fraction of its red-refinement
// volume (BoundaryRepairOptions::min_volume_fraction) and a smallest dihedral angle
// (BoundaryRepairOptions::min_dihedral_degrees), or at least not to lose any; both 0 is the
// paper's rule, positivity only. (The paper writes "lambda = 0 corresponds to standard
// red-green refinement"; with its formula that is lambda = 1.)
//
// Moving boundary vertices squashes the thin tetrahedra next to the boundary. So, after
// the boundary vertices of a level are placed, the interior vertices (those not on S) are
// smoothed (bpm/tetmesh_smooth.h: smart Laplacian, then local optimisation of the smallest
// dihedral angle; never inverting, never making the worst element around a vertex worse),
// and every boundary vertex still short of phi, of this level or an earlier one, is
// retried: smoothing often makes room, so fewer vertices stay off S0 (without the
// widening of bpm/boundary_repair.h's step 4: repair.widen is off here). The boundary can
// also approach phi in several steps with smoothing in between (boundary_steps; on the
// benchmark meshes one step did as well). This step 4 of each level is the repair a solver
// applies to its own refined grid (bpm/boundary_repair.h, the same implementation; here a
// vertex held back at one level is retried later on the segment from the midpoint it was
// created at, which is the same line the solver's call uses). Each level is finished (placed, smoothed) before
// the next one is cut, so new midpoints are those of the smoothed mesh. Vertices on S
// never move except towards phi along their own segment from x; vertex indices, the
// faces on S and the parameter positions are those of plain red refinement.
//
// After each level's step 4, tetrahedra below 15 degrees are flipped where that raises the
// smallest dihedral angle (options.flip; 2-3 flips and edge removals, only among the
// descendants of one level-0 tetrahedron in one region, never a face on S; vertices do
// not move). The tetrahedra are then no longer exactly those of plain red refinement;
// tet_ancestor stays valid. Femur at 1000 vertices, level 3: smallest angle 2.56 -> 4.09
// degrees, 1561 -> 544 tetrahedra below 10 degrees.
//
// Typical use (bpm-refine on a .bpm file that has a tet mesh):
//     bpm::BpmFile file = bpm::read_bpm(in);
//     bpm::TetMesh fine;
//     bpm::TetRefineOptions o;  o.levels = 2;
//     bpm::TetRefineResult r = bpm::refine_tetmesh(file.param, *file.tetmesh, o, context, fine);
//     file.tetmesh = std::move(fine);             // then write_bpm, or write_tetmesh for .msh/.vtu/.mesh

#include <cstdint>
#include <string>
#include <vector>

#include "bpm/boundary_repair.h"
#include "bpm/context.h"
#include "bpm/parametrization.h"
#include "bpm/tetmesh.h"

namespace bpm {

struct TetRefineOptions {
    int levels = 1;                // K >= 0 uniform refinement steps (each multiplies #Tet by 8)
    bool move_to_surface = true;   // false: boundary vertices stay on S (plain red refinement of the boundary)
    // What follows the red refinement of each level (bpm/boundary_repair.h, the call a
    // solver makes after refining its own grid): the new boundary vertices, and those of
    // earlier levels still short of phi, move towards phi as far as admissible (not with
    // move_to_surface = false), and the interior vertices are smoothed (repair.smooth).
    // The dihedral guard is 8 degrees here, not repair_boundary's 5: red refinement of a
    // tetrahedron of smallest angle a gives children down to about 0.7 a, and the moves to
    // phi compound it level by level; with 5, elephant at 10 % fell to 2.2 degrees at level
    // 3, with 8 it stays at 3.5 (bench/RESULTS.md, "Tets without slivers"). A solver's
    // repair keeps 5 (more boundary vertices on phi: femur level 2 holds back 10.6 % with 8).
    BoundaryRepairOptions repair = [] {
        BoundaryRepairOptions o;
        o.min_dihedral_degrees = 8;
        // Without the widening step: with it, bpm-mesh --existing --refine K gave femur /
        // elephant / armadillo at 10 % a smallest angle of 6.70 / 7.24 / 8 degrees at K = 2
        // (6.28 / 6.93 / 8 without) but 6.43 / 5.06 / 7.09 at K = 3 (6.48 / 5.21 / 7.22):
        // the flips and the next level undo the gain. It is for a solver's grid, whose
        // refinement this function's levels do not follow.
        o.widen = false;
        return o;
    }();
    // After each level's boundary placement and smoothing, flip tetrahedra (2-3 and 3-2,
    // among the descendants of one level-0 tetrahedron in one region, never a face on S)
    // where that raises the smallest dihedral angle. The tetrahedra are then no longer those
    // of plain red refinement (what a solver refining its own grid gets); false keeps them.
    bool flip = true;
};

struct TetRefineLevel {
    int64_t vertices = 0, tetrahedra = 0;
    int64_t new_boundary_vertices = 0;  // created on S at this level
    int64_t remedied_vertices = 0;      // of those, placed at lambda*x + (1-lambda)*phi(x) with lambda > 0
    int64_t flat_vertices = 0;          // of those, left at x (lambda = 1, nothing of phi admissible)
    // The mesh after this level:
    int64_t off_surface_vertices = 0;   // boundary vertices off S0 (this level's and earlier levels')
    double max_remedy_distance = 0;     // their largest |v - phi(parameter)|, model units
    int64_t smoothed_vertices = 0;      // interior vertices moved by smoothing
    double min_dihedral_degrees = 0;    // smallest dihedral angle of the level's mesh
    int64_t below_1_degree = 0, below_5_degrees = 0, below_10_degrees = 0;  // tetrahedra with a dihedral angle below
    double smoothing_seconds = 0;
    int64_t flips = 0;                  // flips made after the placement (options.flip): 2-3, edge removals
    double flip_seconds = 0;
};

struct TetRefineResult {
    std::vector<TetRefineLevel> levels;  // one per refinement step
    int64_t vertices = 0, tetrahedra = 0, faces = 0;
    int64_t boundary_vertices = 0;       // vertices on S at the finest level (coarse ones included)
    int64_t remedied_vertices = 0;       // boundary vertices off S0 at the end (all levels)
    double max_remedy_distance = 0;      // largest |v - phi(x)| of a remedied vertex, model units
    double max_remedy_distance_relative = 0;  // the same over the bounding-box diagonal of S0
    double min_phi_fraction = 1;         // smallest 1-lambda used (1 = all on S0)
    int64_t inverted = 0;                // tetrahedra not positively oriented at the end (0 unless the input had some)
    double seconds = 0;
};

// Refines `coarse` (a mesh of param.coarse, e.g. from generate_tetmesh or a .bpm file)
// `options.levels` times; `out` gets the finest level with regions, faces on S (with their
// coarse triangles and patches), the parameter position of every boundary vertex,
// level = coarse.level + K, and tet_ancestor = the level-0 tetrahedron of each tetrahedron.
// Vertices keep their indices (new ones are appended); tetrahedra are written positively
// oriented. \pre coarse passes find_tetmesh_inconsistency and is positively oriented.
// \throw OptionError for levels < 0 or a result beyond 2^31-1 tetrahedra,
//        AlgorithmError if `coarse` does not fit param, Cancelled through the progress callback.
TetRefineResult refine_tetmesh(const Parametrization& param, const TetMesh& coarse, const TetRefineOptions& options,
                               const Context& context, TetMesh& out);

// One line about refinement level `number` (1-based) for logs: tetrahedra, dihedral
// angles, boundary vertices off the surface, smoothed vertices.
std::string describe_level(const TetRefineLevel& level, size_t number);

}  // namespace bpm
