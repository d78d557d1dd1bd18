// bpm-dealii-torsion: the torsion problem -Δu = 1 in the meshed domain, u = 0 on its
// boundary, solved with deal.II (P1 on tetrahedra: FE_SimplexP<3>(1), QGaussSimplex,
// MappingFE; CG with SSOR) on the tet mesh of a .bpm file and on levels 1..K of global
// refinement through the bpm adapter (bpm/dealii/): new boundary vertices on the original
// surface through phi, or at the plain midpoints with --flat.
//
//   bpm-dealii-torsion FILE.bpm --levels K [--flat] [--no-repair] [--no-retreat] [--no-slide] [--adaptive] [--json]
//
// --adaptive asks for local refinement, which the adapter refuses (deal.II 9.4 refines
// tetrahedral meshes correctly only globally): the program exits with the adapter's message.
//
// Prints per level: cells, J = ∫u, the volume, inverted cells (exact orient3d) after the
// adapter's repair and with every boundary vertex at phi (what deal.II's refinement through
// the manifold alone gives), boundary vertices the repair held back short of phi, the
// smallest dihedral angle. J converges to the torsion constant of the
// original surface's domain with phi, and to that of the coarse surface's domain without.

#include <deal.II/base/exceptions.h>
#include <deal.II/base/function.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/precondition.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/vector_tools.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "bpm/bpm_file.h"
#include "bpm/dealii/global_refinement.h"
#include "bpm/dealii/triangulation_from_bpm.h"
#include "bpm/tetmesh.h"
#include "common/tool_main.h"

namespace {

struct Solution {
    double J = 0, volume = 0;
    std::vector<double> region_volumes;  // [material id - 1]: the tet mesh's regions
    int64_t dofs = 0;
    unsigned cg_iterations = 0;
};

// P1 torsion problem on the active cells; J = ∫u and the volume by the same quadrature.
Solution solve_torsion(const dealii::Triangulation<3>& tria) {
    using namespace dealii;
    const FE_SimplexP<3> fe(1);
    const MappingFE<3> mapping(FE_SimplexP<3>(1));
    const QGaussSimplex<3> quadrature(2);
    DoFHandler<3> dofs(tria);
    dofs.distribute_dofs(fe);

    AffineConstraints<double> constraints;
    VectorTools::interpolate_boundary_values(mapping, dofs, 0, Functions::ZeroFunction<3>(), constraints);
    constraints.close();
    DynamicSparsityPattern dsp(dofs.n_dofs());
    DoFTools::make_sparsity_pattern(dofs, dsp, constraints, false);
    SparsityPattern pattern;
    pattern.copy_from(dsp);
    SparseMatrix<double> matrix(pattern);
    Vector<double> u(dofs.n_dofs()), rhs(dofs.n_dofs());

    FEValues<3> values(mapping, fe, quadrature, update_values | update_gradients | update_JxW_values);
    const unsigned n = fe.n_dofs_per_cell();
    FullMatrix<double> cell_matrix(n, n);
    Vector<double> cell_rhs(n);
    std::vector<types::global_dof_index> indices(n);
    for (const auto& cell : dofs.active_cell_iterators()) {
        values.reinit(cell);
        cell_matrix = 0;
        cell_rhs = 0;
        for (unsigned q = 0; q < quadrature.size(); ++q)
            for (unsigned i = 0; i < n; ++i) {
                for (unsigned j = 0; j < n; ++j)
                    cell_matrix(i, j) += values.shape_grad(i, q) * values.shape_grad(j, q) * values.JxW(q);
                cell_rhs(i) += values.shape_value(i, q) * values.JxW(q);
            }
        cell->get_dof_indices(indices);
        constraints.distribute_local_to_global(cell_matrix, cell_rhs, indices, matrix, rhs);
    }

    SolverControl control(20000, 1e-12 * rhs.l2_norm());
    SolverCG<Vector<double>> cg(control);
    PreconditionSSOR<SparseMatrix<double>> ssor;
    ssor.initialize(matrix, 1.2);
    cg.solve(matrix, u, rhs, ssor);
    constraints.distribute(u);

    Solution s;
    s.dofs = static_cast<int64_t>(dofs.n_dofs());
    s.cg_iterations = control.last_step();
    std::vector<double> uq(quadrature.size());
    for (const auto& cell : dofs.active_cell_iterators()) {
        values.reinit(cell);
        values.get_function_values(u, uq);
        const size_t region = cell->material_id() - 1;
        if (s.region_volumes.size() <= region) s.region_volumes.resize(region + 1, 0.0);
        for (unsigned q = 0; q < quadrature.size(); ++q) {
            s.J += uq[q] * values.JxW(q);
            s.volume += values.JxW(q);
            s.region_volumes[region] += values.JxW(q);
        }
    }
    return s;
}

std::string number(double x) {
    if (!std::isfinite(x)) return "null";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", x);
    return buf;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string tool = "bpm-dealii-torsion";
    CLI::App app{"Torsion problem -Δu = 1, u = 0 on the boundary, with deal.II on a .bpm tet mesh refined through phi"};
    std::string input;
    int levels = 2;
    bool flat = false, no_repair = false, no_retreat = false, no_slide = false, json = false, adaptive = false;
    app.add_option("FILE", input, ".bpm file with a tetrahedral mesh (bpm-mesh)")->required();
    app.add_option("--levels", levels, "Solve on levels 0..K of global refinement (default 2)")->check(CLI::Range(0, 6));
    app.add_flag("--flat", flat, "Refine without phi: new boundary vertices at the plain midpoints");
    app.add_flag("--no-repair", no_repair, "Skip the boundary repair after each refinement (to measure what it prevents)");
    app.add_flag("--no-retreat", no_retreat,
                 "Repair without its retreat step (no boundary vertex moves back towards its edge midpoint to "
                 "widen a thin cell; bpm/boundary_repair.h step 5)");
    app.add_flag("--no-slide", no_slide,
                 "Repair without its slide step (no boundary vertex moves along the surface, with a new parameter "
                 "point, to widen a thin cell; bpm/boundary_repair.h step 6)");
    app.add_flag("--adaptive", adaptive,
                 "Refine only part of the cells, as an adaptive run would (refused with exit 2: deal.II 9.4 cannot "
                 "refine tetrahedral meshes locally, and the adapter says so)");
    app.add_flag("--json", json, "Print {\"levels\": [...]} as JSON on standard output");
    bpm::tools::add_version_flag(app, tool);
    return bpm::tools::run(tool, argc, argv, app, [&]() -> int {
        // deal.II's assertions (active in the Debug library this example is built with)
        // throw instead of aborting, so that they reach run()'s error report.
        dealii::deal_II_exceptions::disable_abort_on_exception();
        const bpm::BpmFile file = bpm::read_bpm(input);
        bpm::dealii::BpmTriangulation mesh(file, flat ? bpm::dealii::BoundaryMode::Flat : bpm::dealii::BoundaryMode::Phi);
        bpm::dealii::GlobalRefineOptions options;
        options.repair = !no_repair;
        options.repair_options.retreat = !no_retreat;
        options.repair_options.slide = !no_slide;

        std::ostringstream out;
        if (json) out << "{\"mode\": \"" << (flat ? "flat" : "phi") << "\", \"repair\": " << (no_repair ? "false" : "true")
                      << ", \"retreat\": " << (flat || no_repair || no_retreat ? "false" : "true")
                      << ", \"slide\": " << (flat || no_repair || no_slide ? "false" : "true") << ", \"levels\": [";
        else out << "level cells vertices dofs J volume inverted inverted_without_repair held_back min_dihedral_degrees "
                    "phi_fallbacks seconds\n";
        for (int level = 0; level <= levels; ++level) {
            const auto start = std::chrono::steady_clock::now();
            bpm::dealii::GlobalRefineResult r;
            if (level > 0 && adaptive) {
                // Mark the larger half of the cells (a stand-in for an error estimator): the
                // adapter refuses anything but global refinement with an OptionError.
                std::vector<double> measure;
                for (const auto& cell : mesh.triangulation().active_cell_iterators()) measure.push_back(cell->measure());
                std::vector<double> sorted = measure;
                std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
                const double median = sorted[sorted.size() / 2];
                for (const auto& cell : mesh.triangulation().active_cell_iterators())
                    if (cell->measure() >= median) cell->set_refine_flag();
                r = bpm::dealii::execute_refinement(mesh, options);
            } else if (level > 0) {
                r = bpm::dealii::refine_global(mesh, options);
            }
            const bpm::TetMeshStats stats = bpm::tetmesh_stats(mesh.cells_as_tetmesh());
            // An inverted cell makes the P1 matrix indefinite; J would be meaningless.
            Solution s;
            bool solved = stats.inverted == 0;
            if (solved) s = solve_torsion(mesh.triangulation());
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            const int64_t without = level > 0 ? r.inverted_without_repair : stats.inverted;
            const int64_t held_back = r.repaired ? r.repair.held_back : 0;
            const int64_t fallbacks = mesh.boundary()->fallbacks();
            const auto cells = static_cast<int64_t>(mesh.triangulation().n_active_cells());
            const auto vertices = static_cast<int64_t>(mesh.triangulation().n_vertices());
            if (json) {
                out << (level ? ", " : "") << "{\"level\": " << level << ", \"cells\": " << cells << ", \"tets\": " << cells
                    << ", \"vertices\": " << vertices << ", \"dofs\": " << s.dofs
                    << ", \"J\": " << (solved ? number(s.J) : "null")
                    << ", \"volume\": " << (solved ? number(s.volume) : "null") << ", \"region_volumes\": [";
                for (size_t i = 0; i < s.region_volumes.size(); ++i) out << (i ? ", " : "") << number(s.region_volumes[i]);
                out << "], \"inverted\": " << stats.inverted
                    << ", \"inverted_without_repair\": " << without << ", \"held_back\": " << held_back
                    << ", \"retreated\": " << (r.repaired ? r.repair.retreated : 0)
                    << ", \"slid\": " << (r.repaired ? r.repair.slid : 0)
                    << ", \"max_held_back_distance\": " << number(r.repaired ? r.repair.max_distance : 0.0)
                    << ", \"min_dihedral_degrees\": " << number(stats.min_dihedral_degrees)
                    << ", \"cg_iterations\": " << s.cg_iterations << ", \"phi_fallbacks\": " << fallbacks
                    << ", \"seconds\": " << number(seconds) << "}";
            } else {
                out << level << ' ' << cells << ' ' << vertices << ' ' << s.dofs << ' ' << (solved ? number(s.J) : "-")
                    << ' ' << (solved ? number(s.volume) : "-") << ' ' << stats.inverted << ' ' << without << ' ' << held_back << ' '
                    << number(stats.min_dihedral_degrees) << ' ' << fallbacks << ' ' << number(seconds) << '\n';
            }
            std::cerr << tool << ": level " << level << ": " << cells << " cells, " << stats.inverted << " inverted"
                      << (solved ? ", J = " + number(s.J) : ", not solved (inverted cells)") << '\n';
        }
        if (json) out << "]}\n";
        std::cout << out.str() << std::flush;
        return 0;
    });
}
