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
// After deal.II has placed the new vertices (phi through PhiManifold, or midpoints), a
// boundary vertex moved onto the curved S0 can invert the thin cells next to it. The repair
// (bpm::repair_boundary, bpm/boundary_repair.h) moves vertices so that every cell is
// positively oriented again, and the adapter writes the moved positions back into the
// triangulation (deal.II lets a caller move vertices: cell->vertex(i) = x) and updates the
// parameter points PhiBoundary knows, so that the next level's new points still follow phi.

#include <deal.II/grid/tria.h>

#include <cstdint>
#include <string>
#include <vector>

#include "bpm/dealii/triangulation_from_bpm.h"
#include "bpm/errors.h"
#include "bpm/predicates.h"
#include "bpm/tetmesh.h"

namespace bpm {

struct GlobalRefineOptions {
    // Run the boundary repair after refining (bpm/boundary_repair.h). Off only to measure
    // what deal.II's refinement alone gives.
    bool repair = true;
};

struct GlobalRefineResult {
    int level = 0;                       // refinement level of the triangulation after this call
    int64_t cells = 0;                   // active cells
    int64_t vertices = 0;
    int64_t surface_faces = 0;           // active faces on S (boundary and interfaces)
    int64_t inverted_before_repair = 0;  // cells not positively oriented (exact orient3d) after deal.II's refinement
    int64_t inverted = 0;                // the same after the repair (== before if no repair ran)
    int64_t moved_vertices = 0;          // vertices the repair moved
    int64_t phi_fallbacks = 0;           // new points made without a parameter point so far (PhiBoundary::fallbacks)
    bool repaired = false;               // the repair ran
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
                          ". Flag every cell, or call bpm::refine_global.");
    }
    const int64_t faces_before = mesh.mark_surface();
    tria.execute_coarsening_and_refinement();
    GlobalRefineResult r;
    r.level = mesh.levels_refined();
    r.surface_faces = mesh.collect_surface_and_unmark();
    if (r.surface_faces != 4 * faces_before)
        throw AlgorithmError("after refinement " + std::to_string(r.surface_faces) + " faces on S carry the manifold id, " +
                             "expected 4 x " + std::to_string(faces_before));
    r.cells = static_cast<int64_t>(tria.n_active_cells());
    r.vertices = static_cast<int64_t>(tria.n_vertices());
    r.inverted_before_repair = count_inverted_cells(tria);
    r.inverted = r.inverted_before_repair;
    if (options.repair) {
        // Filled in with bpm::repair_boundary (bpm/boundary_repair.h, branch `repair`).
    }
    r.phi_fallbacks = mesh.boundary()->fallbacks();
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

}  // namespace bpm
