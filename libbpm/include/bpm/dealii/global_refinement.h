#pragma once
// deal.II adapter, part 3: refinement of a BpmTriangulation — global only, each level
// followed by the boundary repair so that no cell is inverted.
//
// deal.II 9.4 refines tetrahedral meshes correctly only globally: local refinement of
// simplices (hanging nodes) fails assertions in a Debug build and silently gives wrong
// results in Release. So the adapter's refinement entry points refuse anything else with
// an OptionError that says so, instead of letting deal.II produce a broken mesh:
//   refine_global(mesh)        flags every active cell, refines once, repairs;
//   execute_refinement(mesh)   for code that sets flags itself: runs only if every active
//                              cell is flagged for (isotropic) refinement and none for
//                              coarsening.
//
// A new boundary vertex put on the curved S0 can invert the thin cells next to it (femur
// 10 %: 193 of 16384 cells at level 1 with deal.II's refinement through PhiManifold alone).
// So by default deal.II places the new points at the midpoints of their edges (PhiBoundary
// records their parameter points all the same), which keeps every cell positive, and the
// repair (bpm::repair_boundary, bpm/boundary_repair.h) then moves every boundary vertex
// towards phi of its parameter point as far as no cell inverts, and smooths the interior
// (the §3.3 remedy; most vertices reach phi). The repair also gets the plain positions
// (BpmTriangulation::plain_positions: the midpoint of the line each vertex was made on), so
// that a boundary vertex next to a cell below the angle bound may move back towards it
// where that widens the worst cell around it (step 5, retreat), or slide along S0 with a
// new parameter point (step 6, repair_boundary_sliding). The adapter writes the
// moved positions back into the triangulation (deal.II lets a caller move vertices:
// cell->vertex(i) = x) and re-keys the parameter points PhiBoundary knows by the new
// positions, so that the next level's new points still follow phi. A vertex held back short of phi gets another chance
// at every later level (the repair continues it on its own segment).

#include <deal.II/grid/tria.h>

#include <cstdint>
#include <string>
#include <vector>

#include "bpm/boundary_repair.h"
#include "bpm/dealii/triangulation_from_bpm.h"
#include "bpm/errors.h"
#include "bpm/predicates.h"
#include "bpm/tetmesh.h"

namespace bpm::dealii {

struct GlobalRefineOptions {
    // Repair after refining (BoundaryMode::Phi only): deal.II places the new points at
    // the midpoints (the PhiBoundary records their parameter points), then
    // bpm::repair_boundary moves every boundary vertex towards phi as far as no cell
    // inverts and smooths the interior. Off: deal.II places them at phi through
    // PhiManifold directly, which may invert cells (to measure what the repair prevents).
    bool repair = true;
    BoundaryRepairOptions repair_options;
};

struct GlobalRefineResult {
    int level = 0;                       // refinement level of the triangulation after this call
    int64_t cells = 0;                   // active cells
    int64_t vertices = 0;
    int64_t surface_faces = 0;           // active faces on S (boundary and interfaces)
    // Cells not positively oriented (exact orient3d) with every boundary vertex at phi of
    // its parameter point, i.e. what deal.II's refinement through PhiManifold alone gives
    // at this level (from the previous, repaired, level); 0 in Flat mode.
    int64_t inverted_without_repair = 0;
    int64_t inverted = 0;                // cells not positively oriented after this call
    bool repaired = false;               // the repair ran
    BoundaryRepairResult repair;         // its report (when repaired)
    int64_t phi_fallbacks = 0;           // new points made without a parameter point so far (PhiBoundary::fallbacks)
};

// Cells of the active mesh that are not positively oriented (exact orient3d; deal.II's
// reference tetrahedron is positive, and the adapter's level-0 cells are).
inline int64_t count_inverted_cells(const ::dealii::Triangulation<3>& tria) {
    int64_t inverted = 0;
    for (const auto& cell : tria.active_cell_iterators()) {
        Vec3 p[4];
        for (unsigned k = 0; k < 4; ++k) p[k] = to_vec3(cell->vertex(k));
        if (orient3d(p[0], p[1], p[2], p[3]) != 1) ++inverted;
    }
    return inverted;
}

namespace detail {

inline std::string describe_flags(int64_t refine, int64_t coarsen, int64_t active) {
    return std::to_string(refine) + " of " + std::to_string(active) + " active cells flagged for refinement, " +
           std::to_string(coarsen) + " for coarsening";
}

}  // namespace detail

// Runs deal.II's refinement of the flagged cells if the flags ask for global refinement,
// then re-marks the lines on S and repairs (GlobalRefineOptions).
// \throw OptionError unless every active cell is flagged for refinement and none for
//        coarsening (deal.II 9.4 cannot refine tetrahedral meshes locally);
//        AlgorithmError if a child face of a face on S lost the manifold id.
inline GlobalRefineResult execute_refinement(BpmTriangulation& mesh, const GlobalRefineOptions& options = {}) {
    ::dealii::Triangulation<3>& tria = mesh.triangulation();
    int64_t refine = 0, coarsen = 0, active = 0;
    for (const auto& cell : tria.active_cell_iterators()) {
        ++active;
        if (cell->refine_flag_set() != ::dealii::RefinementCase<3>::no_refinement) ++refine;
        if (cell->coarsen_flag_set()) ++coarsen;
    }
    if (refine != active || coarsen != 0) {
        throw OptionError("deal.II 9.4 refines tetrahedral meshes only globally (local refinement of simplices fails "
                          "in a Debug build and gives wrong results in Release); the bpm adapter refuses this request: " +
                          detail::describe_flags(refine, coarsen, active) +
                          ". Flag every cell, or call bpm::dealii::refine_global.");
    }
    const bool phi_mode = mesh.mode() == BoundaryMode::Phi;
    const bool repair = phi_mode && options.repair;
    PhiBoundary& boundary = *mesh.boundary();
    const int64_t faces_before = mesh.mark_surface();
    // With the repair, new points start at their midpoints (its contract: a positive mesh).
    boundary.set_applies_phi(phi_mode && !repair);
    try {
        tria.execute_coarsening_and_refinement();
    } catch (...) {
        boundary.set_applies_phi(phi_mode);
        throw;
    }
    boundary.set_applies_phi(phi_mode);
    GlobalRefineResult r;
    r.level = mesh.levels_refined();
    r.surface_faces = mesh.collect_surface_and_unmark();
    if (r.surface_faces != 4 * faces_before)
        throw AlgorithmError("after refinement " + std::to_string(r.surface_faces) + " faces on S carry the manifold id, " +
                             "expected 4 x " + std::to_string(faces_before));
    r.cells = static_cast<int64_t>(tria.n_active_cells());
    r.vertices = static_cast<int64_t>(tria.n_vertices());
    r.phi_fallbacks = boundary.fallbacks();

    if (!phi_mode) {
        r.inverted = count_inverted_cells(tria);
        return r;
    }
    const TetMesh cells = mesh.cells_as_tetmesh();
    std::vector<SurfacePoint> points = mesh.vertex_parameter_points();
    // Every boundary vertex at phi: what PhiManifold alone gives.
    std::vector<Vec3> at_phi = cells.vertices;
    for (size_t i = 0; i < at_phi.size(); ++i)
        if (points[i].valid()) at_phi[i] = boundary.phi().evaluate(points[i].triangle, points[i].barycentric).position;
    for (const Tet& t : cells.tetrahedra)
        if (orient3d(at_phi[t[0]], at_phi[t[1]], at_phi[t[2]], at_phi[t[3]]) != 1) ++r.inverted_without_repair;
    if (!repair) {
        r.inverted = count_inverted_cells(tria);
        return r;
    }
    std::vector<Vec3> positions = cells.vertices;
    // With the plain positions, for the repair's retreat (step 5, bpm/boundary_repair.h);
    // sliding (step 6) may change parameter points, which move_vertices records.
    r.repair = repair_boundary_sliding(boundary.phi(), positions, cells.tetrahedra, points, mesh.plain_positions(),
                                       options.repair_options);
    r.repaired = true;
    mesh.move_vertices(positions, points);
    r.inverted = count_inverted_cells(tria);
    return r;
}

// One level of global refinement: flags every active cell and runs execute_refinement.
inline GlobalRefineResult refine_global(BpmTriangulation& mesh, const GlobalRefineOptions& options = {}) {
    for (const auto& cell : mesh.triangulation().active_cell_iterators()) {
        cell->clear_coarsen_flag();
        cell->set_refine_flag();
    }
    return execute_refinement(mesh, options);
}

}  // namespace bpm::dealii
