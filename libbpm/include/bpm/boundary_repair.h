#pragma once
// Repair after a solver refines: move the boundary vertices of a refined tetrahedral mesh
// onto the original surface S0 through phi without inverting a tetrahedron (Krause &
// Sander §3.3), and smooth the interior.
//
// A solver that refines its own grid of a bpm tet mesh (DUNE's UGGrid, deal.II) creates
// each new boundary vertex at the midpoint of a boundary edge, on the flat boundary of the
// coarser level, and knows its parameter point (bpm/surface_point.h; the midpoint of its
// edge ends' parameter points). Putting such a vertex at phi(parameter point) can invert
// or flatten the thin tetrahedra next to the boundary. After each adapt step the solver
// calls repair_boundary on its (leaf) grid, which does what bpm-refine --volume does
// after each of its own levels (bpm/tet_refine.h uses the same implementation):
//
//   1. every boundary vertex v (parameter_points[v].valid()) whose position x is not
//      exactly phi(p), p = parameter_points[v], moves along the straight segment from x
//      towards phi(p), to lambda*x + (1-lambda)*phi(p) with the largest 1-lambda in [0, 1]
//      (bisection) at which the position is admissible: every tetrahedron around v is
//      positively oriented (exact orient3d) and keeps at least min_volume_fraction of its
//      volume on entry, or does not shrink from where it is, and keeps a smallest dihedral
//      angle of min_dihedral_degrees, or does not lose any. 1-lambda = 1 is phi(p); 0 is
//      where the vertex was (always admissible for a positive mesh). With
//      boundary_steps > 1 the vertices approach phi(p) in that many steps.
//   2. the interior vertices (parameter point invalid) are smoothed (bpm/tetmesh_smooth.h:
//      never inverting a tetrahedron, never making the worst one around a vertex worse);
//   3. every boundary vertex still short of phi(p) is retried from where it now is, then
//      the interior is smoothed again, up to retry_passes times, stopping when no vertex
//      gets closer (smoothing often makes room);
//   4. widening (options.widen, when min_dihedral_degrees > 0): every boundary vertex still short of
//      phi(p) with a tetrahedron below min_dihedral_degrees around it moves on towards
//      phi(p) as far as the smallest dihedral angle of its tetrahedra does not get smaller
//      (or stays at least min_dihedral_degrees): one of them may lose angle below the bound
//      where the move widens a thinner one, which step 1 refuses. The interior around the
//      vertices that moved is smoothed again. Neither lowers the mesh's smallest angle.
//   5. retreat (options.retreat, when the solver gives plain positions: where plain
//      refinement puts each vertex, the midpoint of the edge it split; repair_uggrid, the
//      deal.II adapter's execute_refinement and Python's File.repair(plain_positions=)
//      pass them, refine_tetmesh does not): every boundary
//      vertex with a tetrahedron below min_dihedral_degrees around it, worst first, moves
//      back on the segment from where it is towards its plain position, to where the worst
//      tetrahedron around it is widest, if that is wider than where it is; then the
//      interior around the vertices that moved is smoothed again. This is the §3.3 remedy
//      applied to vertices that reached phi in an earlier call: four boundary vertices close
//      together on a curved S0 make a flat tetrahedron (a sliver) wherever refinement put
//      one tetrahedron on all four, and a tetrahedron UG then cuts from it at an interior
//      edge midpoint can be no wider than half the sliver's angle at the opposite edge, wherever
//      smoothing puts the midpoint (femur at 10 %, bpm-torsion --adaptive step 5: a 2.02
//      degree sliver of four boundary vertices cut into two 1.01 degree tetrahedra; flat
//      refinement has 2.37). No move lowers the mesh's smallest angle.
//   6. slide (options.slide, only in repair_boundary_sliding, whose caller keeps the new
//      parameter points: repair_uggrid and the deal.II adapter's execute_refinement;
//      refine_tetmesh and Python's File.repair do not slide): every boundary vertex with a
//      tetrahedron below min_dihedral_degrees around it, worst first, moves along S0: its
//      parameter point moves within its coarse triangle (a point on a coarse edge stays on
//      that edge, a coarse vertex stays), the vertex to phi of the new point (or, held
//      back, with its offset from phi kept), to where the worst tetrahedron around it is
//      widest within a quarter of its shortest edge (a compass search), if that is wider
//      than where it is and every tetrahedron around it stays positive (exact); then the
//      interior around the vertices that moved is smoothed again. This widens tetrahedra
//      of four boundary vertices that neither the retreat nor smoothing can: four points
//      of a surface that is smooth at their scale are nearly coplanar, and refinement
//      keeps making such tetrahedra under a level-0 tetrahedron with all four corners on
//      S0 (the children at a corner whose three edges are on S0), flatter at each level,
//      unless their vertices stay off S0 (femur at 10 %, bpm-torsion --adaptive: at step
//      5, 3.49 degrees, a tetrahedron with a face on one coarse triangle and its fourth
//      corner on the neighbouring one, under a level-0 tetrahedron with faces on both; at
//      step 6, 2.63 degrees, two at a coarse vertex; all three inverted with their corners
//      at phi; with the slide both steps keep 5 degrees). No move lowers the mesh's
//      smallest angle.
//
// A vertex whose parameter point is a corner of its coarse triangle (a barycentric
// coordinate exactly 1) is a coarse vertex (level-0 vertex i of a grid built from the .bpm
// file is coarse vertex i): coarse vertices are original vertices, which phi maps to
// themselves, so it keeps its position and counts as at phi. (PhiEvaluator's value there
// may differ from the coarse vertex by rounding.)
//
// Vertices held back by an earlier call: the call keeps no state between calls. A vertex
// that an earlier call left short of phi(p) is moved from where it is towards phi(p) again:
// each call gives it another chance, and the solver only keeps positions and parameter
// points (which it needs anyway). (Without steps 5 and 6 such a vertex lies on the segment
// from its flat position to phi(p), and the call continues on that segment; after a
// retreat it lies towards the plain position of that call instead.) 1-lambda in the result
// refers to this call's segments (from the position on entry). Steps 1-4 leave boundary
// vertices exactly at phi(p) where they are; steps 5 and 6 may move them (back towards a
// plain position, or along S0), so a second call is bit for bit idempotent only without
// plain positions and without sliding.
//
// Contract.
//   The solver guarantees: every tetrahedron is positively oriented,
//   orient3d(x0, x1, x2, x3) == +1 (det[x1-x0, x2-x0, x3-x0] > 0; the convention of
//   bpm/tetmesh.h), as plain refinement of a positive mesh gives when new boundary vertices
//   are at their edge midpoints. A solver whose grid already put new boundary vertices at
//   phi (a UG BoundarySegment or a deal.II Manifold returning phi) may have inverted
//   tetrahedra: it should put its new boundary vertices back at the midpoints of their
//   edges before the call and let the call move them.
//   It gets: no tetrahedron that was positively oriented on entry is inverted or flat on
//   exit (result.inverted_after <= result.inverted_before, 0 when 0 before). Tetrahedra
//   that are inverted on entry are allowed: a boundary vertex next to one moves only to
//   positions where all its tetrahedra are positive, interior smoothing may untangle them.
//   Boundary vertices move only along their own segment towards phi(p), or (step 5) back
//   towards their plain position, or (step 6, repair_boundary_sliding only) along S0 with
//   a new parameter point; interior vertices move only by smoothing; the connectivity is
//   not changed, nor are the parameter points except by step 6.
//
// Typical use (after each refinement of the solver's grid):
//     bpm::PhiEvaluator phi(file.param);                  // once
//     ... adapt; collect the leaf vertices (positions, new boundary vertices at their edge
//         midpoints), the leaf tetrahedra and each vertex's parameter point ...
//     bpm::BoundaryRepairResult r = bpm::repair_boundary(phi, positions, tets, points);
//     ... write positions back into the grid (UGGrid::setPosition, deal.II's vertices) ...

#include <array>
#include <cstdint>
#include <vector>

#include "bpm/context.h"
#include "bpm/geometry.h"
#include "bpm/phi_evaluation.h"
#include "bpm/surface_point.h"
#include "bpm/tetmesh_smooth_options.h"

namespace bpm {

using Tet = std::array<int32_t, 4>;  // four vertex indices (also in bpm/tetmesh.h)

struct BoundaryRepairOptions {
    int bisection_steps = 30;  // >= 1: bisection steps for the largest admissible 1-lambda
    // A position is admissible when every tetrahedron around the vertex is positively
    // oriented (exact orient3d) and keeps at least this fraction of the volume it has on
    // entry (plain refinement: the new vertices at the edge midpoints), or does not shrink
    // from where it is. 0 is the paper's rule (positive volume only), which lets the
    // bisection stop at nearly flat slivers; the default keeps a margin. Relative to each
    // element, so independent of units. In [0, 1).
    double min_volume_fraction = 0.1;
    // Admissible also asks every tetrahedron around the vertex to keep a smallest dihedral
    // angle of at least this many degrees, or not to lose any (0 = no such condition).
    // Trades distance to S0 for element quality where smoothing cannot help (tetrahedra
    // whose four vertices are all on S, which a curved S0 flattens). Step 4 (widening, see
    // the top of this file) asks it of the worst tetrahedron around the vertex only. In [0, 90).
    double min_dihedral_degrees = 5;  // (refine_tetmesh uses 8: bpm/tet_refine.h)
    // The boundary vertices approach phi in boundary_steps steps: in step s each goes to
    // the largest admissible 1-lambda <= s / boundary_steps, and the interior is smoothed
    // after every step. Then up to retry_passes more passes retry every boundary vertex
    // still short of phi, each followed by smoothing; they stop early when no vertex gets
    // closer.
    int boundary_steps = 1;  // >= 1
    int retry_passes = 4;    // >= 0
    // Step 4 (widening, see the top of this file), when min_dihedral_degrees > 0.
    // refine_tetmesh turns it off (bpm/tet_refine.h).
    bool widen = true;
    // Step 5 (retreat, see the top of this file), when min_dihedral_degrees > 0 and the
    // call has plain positions.
    bool retreat = true;
    // Step 6 (slide, see the top of this file), when min_dihedral_degrees > 0; only
    // repair_boundary_sliding slides (it may change parameter points).
    bool slide = true;
    // Interior smoothing (bpm/tetmesh_smooth.h) after each placement of the boundary
    // vertices: only vertices without a parameter point move, the smallest dihedral angle
    // around a moved vertex only grows, and no tetrahedron inverts.
    bool smooth = true;
    TetSmoothOptions smoothing;
};

struct BoundaryRepairResult {
    int64_t boundary_vertices = 0;   // vertices with a valid parameter point
    int64_t at_phi_before = 0;       // of those, exactly at phi(parameter point) on entry (steps 1-4 leave them)
    int64_t at_phi = 0;              // of those, exactly at phi(parameter point) on exit
    int64_t held_back = 0;           // boundary_vertices - at_phi: short of phi on exit (the §3.3 remedy; retreated included)
    int64_t not_moved = 0;           // of those, not moved towards phi at all (no step admissible; steps 1-4)
    int64_t widened = 0;             // boundary vertices the widening pass moved on (step 4, options.widen)
    int64_t retreated = 0;           // boundary vertices moved back towards their plain positions (step 5)
    int64_t slid = 0;                // boundary vertices moved along S0, with new parameter points (step 6)
    double max_distance = 0;         // largest |x - phi(p)| of a held-back vertex, model units
    double max_distance_relative = 0;  // the same over the bounding-box diagonal of the vertices on exit
    double min_phi_fraction = 1;     // smallest 1-lambda of a vertex on this call's segment after steps 1-4 (1: all at phi)
    int64_t smoothed_vertices = 0;   // interior vertices that moved
    double min_dihedral_degrees = 0; // smallest dihedral angle of the mesh on exit (0 for no tetrahedra)
    int64_t inverted_before = 0;     // tetrahedra not positively oriented on entry (exact orient3d)
    int64_t inverted_after = 0;      // the same on exit: <= inverted_before, 0 if it was 0
    double seconds = 0;              // wall time of the call
    double smoothing_seconds = 0;    // of which interior smoothing
};

// Moves the boundary vertices of the tetrahedral mesh (vertices, tetrahedra) towards phi
// of their parameter points and smooths its interior vertices (see the top of this file).
// `vertices`: #V positions, in/out (model units). `tetrahedra`: #T vertex indices, each
// positively oriented. `parameter_points`: #V, the point of the coarse surface S of each
// boundary vertex (triangle >= 0, barycentric in that coarse triangle); triangle = -1 for
// interior vertices, which smoothing may move. `phi` is the evaluator of the .bpm file the
// mesh was made from. The result does not depend on the Context.
// \pre the tetrahedra are positively oriented (those that are not are counted in
//      inverted_before and allowed); barycentrics valid for phi (>= 0, sum 1, rounding
//      tolerated).
// \throw OptionError for options out of range (see BoundaryRepairOptions; smoothing as
//        smooth_tetmesh), std::invalid_argument if parameter_points.size() != #V, a
//        tetrahedron index is outside [0, #V) or a coordinate is not finite,
//        std::out_of_range for a parameter point's coarse triangle outside [0, #S.T),
//        Cancelled through the progress callback.
BoundaryRepairResult repair_boundary(const PhiEvaluator& phi, std::vector<Vec3>& vertices,
                                     const std::vector<Tet>& tetrahedra,
                                     const std::vector<SurfacePoint>& parameter_points,
                                     const BoundaryRepairOptions& options = {}, const Context& context = {});

// The same with step 5 (retreat): `plain_positions` (#V, model units) gives where plain
// refinement of the solver's grid puts each vertex (for a vertex refinement created at an
// edge midpoint: that midpoint of the edge ends' current positions; for the others their
// position); only those of boundary vertices are read. Empty: no step 5, as above.
// \throw std::invalid_argument also if plain_positions is neither empty nor #V long or a
//        coordinate of it is not finite.
BoundaryRepairResult repair_boundary(const PhiEvaluator& phi, std::vector<Vec3>& vertices,
                                     const std::vector<Tet>& tetrahedra,
                                     const std::vector<SurfacePoint>& parameter_points,
                                     const std::vector<Vec3>& plain_positions, const BoundaryRepairOptions& options = {},
                                     const Context& context = {});

// The same with step 6 (slide): boundary vertices may also move along S0, so
// `parameter_points` is in/out, and the caller must keep the new points (a vertex's
// parameter point is what its children's points are made from, and the next call moves it
// towards phi of it). A changed point stays in the same coarse triangle, with the same
// barycentric coordinates 0 (so on the same coarse edge, and in every coarse triangle it
// was in). plain_positions may be empty (no step 5).
// \throw as repair_boundary with plain positions.
BoundaryRepairResult repair_boundary_sliding(const PhiEvaluator& phi, std::vector<Vec3>& vertices,
                                             const std::vector<Tet>& tetrahedra,
                                             std::vector<SurfacePoint>& parameter_points,
                                             const std::vector<Vec3>& plain_positions,
                                             const BoundaryRepairOptions& options = {}, const Context& context = {});

}  // namespace bpm
