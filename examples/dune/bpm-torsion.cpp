// bpm-torsion: the torsion problem -Δu = 1 in the meshed domain of a .bpm file, u = 0 on
// its boundary, with P1 elements on a Dune::UGGrid<3> whose boundary is phi
// (bpm/dune/uggrid_from_bpm.h), solved by CG with dune-istl's AMG on levels 0..K of
// uniform or adaptive (residual estimator, red-green) refinement. Reports per level the
// torsion functional J = ∫u, the volume, inverted tets and the smallest dihedral angle,
// the numbers of the paper's §3 experiment (bench/RESULTS.md, "Solvers: DUNE torsion").
//
//   bpm-torsion FILE.bpm --levels K [--flat] [--adaptive [--reference-j J --until-error E]] [--json]
//
// An example of using bpm from a DUNE program, not a bpm tool: it is built with the tests
// when DUNE and UG are found (examples/dune/CMakeLists.txt).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include <dune/common/parallel/mpihelper.hh>
#include <dune/geometry/referenceelements.hh>
#include <dune/grid/uggrid.hh>
#include <dune/istl/bcrsmatrix.hh>
#include <dune/istl/bvector.hh>
#include <dune/istl/operators.hh>
#include <dune/istl/paamg/amg.hh>
#include <dune/istl/preconditioners.hh>
#include <dune/istl/solvers.hh>

#include "bpm/bpm_file.h"
#include "bpm/dune/uggrid_adapt.h"
#include "bpm/dune/uggrid_from_bpm.h"
#include "bpm/dune/uggrid_refinement_rules.h"
#include "bpm/dune/uggrid_repair.h"
#include "bpm/errors.h"
#include "bpm/phi_evaluation.h"
#include "bpm/predicates.h"
#include "bpm/tetmesh.h"
#include "bpm/tetmesh_smooth.h"
#include "common/tool_main.h"

namespace {

// bpm's Vec3 operators (Vec3 is a std::array, so argument-dependent lookup misses them).
using bpm::operator+;
using bpm::operator-;
using bpm::operator*;
using Grid = bpm::dune::UGGrid3;
using Matrix = Dune::BCRSMatrix<Dune::FieldMatrix<double, 1, 1>>;
using Vector = Dune::BlockVector<Dune::FieldVector<double, 1>>;

bpm::Vec3 to_vec3(const Dune::FieldVector<double, 3>& x) { return {x[0], x[1], x[2]}; }

struct LevelReport {
    int level = 0;
    long tets = 0, vertices = 0, unknowns = 0;
    double J = 0, volume = 0;
    std::vector<double> region_volumes;
    long inverted = 0;
    double min_dihedral_degrees = 180;
    double max_boundary_offset = 0;  // max |x - phi(parameter point)| over boundary vertices
    long inverted_before_repair = 0;  // with UG's new boundary vertices at phi
    long held_back = 0;               // boundary vertices the repair kept short of phi
    long smoothed = 0;                // interior vertices the repair's smoothing moved
    long retreated = 0;               // boundary vertices the repair moved back towards their edge midpoints
    long slid = 0;                    // boundary vertices the repair moved along the surface (new parameter points)
    long reset = 0;                   // earlier boundary vertices put back to midpoints (repair_uggrid)
    long inverted_after_reset = 0;    // tets still inverted when the repair starts (after the reset): should be 0
    long rules_kept = 0;              // bpm::dune::uggrid_refinement_rules_kept() during this refinement
    long marked = 0;      // adaptive: elements marked for this level's refinement
    int adapts = 0;       // adaptive: UG adapt() calls of this step (one per level UG refines, bpm/dune/uggrid_adapt.h)
    long superseded = 0;  // adaptive: marked leaves an earlier adapt() of this step had replaced
    int cg_iterations = 0;
    bool cg_converged = false;
    double seconds = 0;
};

long count_inverted(const Grid& grid) {
    long inverted = 0;
    for (const auto& element : elements(grid.leafGridView())) {
        const auto g = element.geometry();
        if (bpm::orient3d(to_vec3(g.corner(0)), to_vec3(g.corner(1)), to_vec3(g.corner(2)), to_vec3(g.corner(3))) != 1)
            ++inverted;
    }
    return inverted;
}

// Region id of a leaf element: that of its level-0 ancestor.
template <class Element>
int32_t region_of(const Element& element, const bpm::dune::UGGridFromBpm& built, const Grid& grid) {
    auto e = element;
    while (e.level() > 0) e = e.father();
    return built.level0_element_region[grid.levelIndexSet(0).index(e)];
}

// Solves -Δu = 1, u = 0 on the boundary, on the leaf grid; fills J, the unknowns and the
// solution's per-element gradient (for the estimator).
void solve_torsion(const Grid& grid, LevelReport& report, std::vector<Dune::FieldVector<double, 3>>& gradients) {
    const auto view = grid.leafGridView();
    const auto& index = view.indexSet();
    const size_t n = static_cast<size_t>(view.size(3));

    std::vector<char> on_boundary(n, 0);
    const auto& tet = Dune::referenceElement<double, 3>(Dune::GeometryTypes::tetrahedron);
    for (const auto& element : elements(view)) {
        if (!element.hasBoundaryIntersections()) continue;
        for (const auto& is : intersections(view, element)) {
            if (!is.boundary()) continue;
            for (int c = 0; c < 3; ++c)
                on_boundary[index.subIndex(element, tet.subEntity(is.indexInInside(), 1, c, 3), 3)] = 1;
        }
    }

    Matrix A(n, n, 15, 0.5, Matrix::implicit);
    Vector b(n), u(n);
    b = 0.0;
    u = 0.0;
    gradients.assign(static_cast<size_t>(view.size(0)), Dune::FieldVector<double, 3>(0.0));
    std::vector<std::array<Dune::FieldVector<double, 3>, 4>> basis_gradients(static_cast<size_t>(view.size(0)));
    for (const auto& element : elements(view)) {
        const auto geometry = element.geometry();
        // Gradients of the barycentric coordinates: rows of the inverse Jacobian (P1).
        const auto jit = geometry.jacobianInverseTransposed({0.25, 0.25, 0.25});
        std::array<Dune::FieldVector<double, 3>, 4> g;
        const std::array<Dune::FieldVector<double, 3>, 4> ref{
            Dune::FieldVector<double, 3>{-1, -1, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        for (int i = 0; i < 4; ++i) jit.mv(ref[i], g[i]);
        basis_gradients[index.index(element)] = g;
        const double volume = geometry.volume();
        std::array<size_t, 4> dof;
        for (int i = 0; i < 4; ++i) dof[i] = index.subIndex(element, i, 3);
        for (int i = 0; i < 4; ++i) {
            if (on_boundary[dof[i]]) continue;
            b[dof[i]] += volume / 4.0;
            for (int j = 0; j < 4; ++j)
                if (!on_boundary[dof[j]]) A.entry(dof[i], dof[j]) += volume * (g[i] * g[j]);
        }
    }
    // u = 0 on the boundary: identity rows, no couplings (symmetric, for CG).
    for (size_t i = 0; i < n; ++i)
        if (on_boundary[i]) A.entry(i, i) = 1.0;
    A.compress();

    long unknowns = 0;
    for (char c : on_boundary) unknowns += !c;
    report.unknowns = unknowns;

    using Operator = Dune::MatrixAdapter<Matrix, Vector, Vector>;
    using Smoother = Dune::SeqSSOR<Matrix, Vector, Vector>;
    using Criterion = Dune::Amg::CoarsenCriterion<Dune::Amg::SymmetricCriterion<Matrix, Dune::Amg::FirstDiagonal>>;
    Operator op(A);
    Criterion criterion(15, 2000);
    criterion.setDefaultValuesIsotropic(3);
    criterion.setDebugLevel(0);
    Dune::Amg::SmootherTraits<Smoother>::Arguments smoother_args;
    smoother_args.iterations = 1;
    smoother_args.relaxationFactor = 1.0;
    Dune::Amg::AMG<Operator, Vector, Smoother> amg(op, criterion, smoother_args);
    Dune::CGSolver<Vector> cg(op, amg, 1e-10, 1000, 0);
    Dune::InverseOperatorResult result;
    Vector rhs = b;
    cg.apply(u, rhs, result);
    report.cg_iterations = result.iterations;
    report.cg_converged = result.converged;

    double J = 0;
    for (const auto& element : elements(view)) {
        const auto i = index.index(element);
        double sum = 0;
        Dune::FieldVector<double, 3> grad(0.0);
        for (int c = 0; c < 4; ++c) {
            const double uc = u[index.subIndex(element, c, 3)];
            sum += uc;
            grad.axpy(uc, basis_gradients[i][c]);
        }
        J += element.geometry().volume() * sum / 4.0;
        gradients[i] = grad;
    }
    report.J = J;
}

// Geometry of the leaf grid: counts, volumes, inverted tets, dihedral angles, and how far
// boundary vertices are from phi of their parameter points.
void measure(const Grid& grid, const bpm::dune::UGGridFromBpm& built, const bpm::dune::BoundaryParameterPoints& params,
             const bpm::PhiEvaluator& phi, int regions, LevelReport& report) {
    const auto view = grid.leafGridView();
    report.tets = view.size(0);
    report.vertices = view.size(3);
    report.region_volumes.assign(static_cast<size_t>(regions), 0.0);
    for (const auto& element : elements(view)) {
        const auto geometry = element.geometry();
        std::array<bpm::Vec3, 4> x;
        for (int i = 0; i < 4; ++i) x[i] = to_vec3(geometry.corner(i));
        // DUNE's reference tetrahedron (0, e1, e2, e3) is positively oriented, and UG
        // keeps the orientation of the coarse elements in their children.
        const bool inverted = bpm::orient3d(x[0], x[1], x[2], x[3]) != 1;
        report.inverted += inverted;
        const double v = bpm::dot(bpm::cross(x[1] - x[0], x[2] - x[0]), x[3] - x[0]) / 6.0;
        report.volume += v;
        report.region_volumes[static_cast<size_t>(region_of(element, built, grid) - 1)] += v;
        // Unsigned, as bpm-mesh reports (TetMeshStats): an inverted tetrahedron counts with
        // the angles of its mirror image (tet_min_dihedral_degrees is negative for it).
        const double angle = inverted ? bpm::tet_min_dihedral_degrees(x[1], x[0], x[2], x[3])
                                      : bpm::tet_min_dihedral_degrees(x[0], x[1], x[2], x[3]);
        report.min_dihedral_degrees = std::min(report.min_dihedral_degrees, angle);
    }
    for (const auto& vertex : vertices(view)) {
        const bpm::SurfacePoint* p = params.find(grid.globalIdSet().id(vertex));
        if (!p) continue;
        const bpm::Vec3 target = phi.evaluate(p->triangle, p->barycentric).position;
        report.max_boundary_offset =
            std::max(report.max_boundary_offset, bpm::distance(target, to_vec3(vertex.geometry().corner(0))));
    }
}

// Residual estimator for P1 and f = 1: eta_T^2 = h_T^2 |T| + 1/2 sum over interior faces F
// of T of h_F |F| [grad u . n]^2. Returns the elements with the largest eta holding half of
// the total (Dörfler, theta = 0.5), largest first.
std::vector<Grid::LeafGridView::Codim<0>::Entity> select_by_estimator(
    const Grid& grid, const std::vector<Dune::FieldVector<double, 3>>& gradients) {
    const auto view = grid.leafGridView();
    const auto& index = view.indexSet();
    std::vector<double> eta2(static_cast<size_t>(view.size(0)), 0.0);
    std::vector<Grid::LeafGridView::Codim<0>::Entity> by_index(eta2.size());
    for (const auto& element : elements(view)) {
        const auto geometry = element.geometry();
        double h = 0;
        for (int i = 0; i < 4; ++i)
            for (int j = i + 1; j < 4; ++j) h = std::max(h, (geometry.corner(i) - geometry.corner(j)).two_norm());
        const auto i = index.index(element);
        by_index[i] = element;
        eta2[i] += h * h * geometry.volume();
        for (const auto& is : intersections(view, element)) {
            if (!is.neighbor()) continue;
            const auto face = is.geometry();
            double hf = 0;
            for (int a = 0; a < 3; ++a)
                for (int c = a + 1; c < 3; ++c) hf = std::max(hf, (face.corner(a) - face.corner(c)).two_norm());
            Dune::FieldVector<double, 3> jump = gradients[i];
            jump -= gradients[index.index(is.outside())];
            const double normal_jump = jump * is.centerUnitOuterNormal();
            eta2[i] += 0.5 * hf * face.volume() * normal_jump * normal_jump;
        }
    }
    std::vector<size_t> order(eta2.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return eta2[a] > eta2[b]; });
    double total = 0;
    for (double e : eta2) total += e;
    std::vector<Grid::LeafGridView::Codim<0>::Entity> selected;
    double sum = 0;
    for (size_t k : order) {
        if (sum >= 0.5 * total) break;
        selected.push_back(by_index[k]);
        sum += eta2[k];
    }
    return selected;
}

std::string json_string(const std::string& text) {
    std::string out = "\"";
    for (char c : text) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out + "\"";
}

std::string json_number(double x) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.10g", x);
    return buffer;
}

}  // namespace

int main(int argc, char** argv) {
    Dune::MPIHelper::instance(argc, argv);

    CLI::App app{"Torsion problem -Δu = 1, u = 0 on the boundary, on a UGGrid built from a .bpm tet mesh whose "
                 "boundary refines through phi; reports J = ∫u, volume and element quality per level."};
    std::string input;
    int levels = 2;
    bool flat = false, adaptive = false, json = false, no_repair = false, no_smooth = false, flat_interfaces = false,
         no_retreat = false, no_slide = false;
    double reference_j = 0, until_error = 0;
    app.add_option("INPUT", input, ".bpm file with a tet mesh (bpm-mesh)")->required();
    app.add_option("--levels", levels, "Refinement steps K: levels 0..K are solved (uniform: K <= 8)")
        ->check(CLI::Range(0, 40));
    app.add_flag("--flat", flat, "Refine without phi: new boundary vertices at plain edge midpoints");
    app.add_flag("--adaptive", adaptive, "Refine locally by a residual estimator (red-green) instead of uniformly");
    app.add_flag("--no-repair", no_repair,
                 "Leave UG's new boundary vertices at phi (no bpm::repair_boundary; elements may invert)");
    app.add_flag("--flat-interfaces", flat_interfaces,
                 "Leave new vertices on interfaces between regions at edge midpoints (UG's own refinement); "
                 "by default the repair moves them towards phi like boundary vertices");
    app.add_flag("--no-smooth", no_smooth, "Repair without interior smoothing (only boundary vertices move)");
    app.add_flag("--no-retreat", no_retreat,
                 "Repair without its retreat step (no boundary vertex moves back towards its edge midpoint "
                 "to widen a thin tetrahedron)");
    app.add_flag("--no-slide", no_slide,
                 "Repair without its slide step (no boundary vertex moves along the surface, changing its "
                 "parameter point, to widen a thin tetrahedron)");
    app.add_flag("--json", json, "Print the report as JSON on standard output (progress stays on standard error)");
    auto* reference_option =
        app.add_option("--reference-j", reference_j, "Reference value of J (for --until-error)")->check(CLI::PositiveNumber);
    app.add_option("--until-error", until_error,
                   "With --adaptive: stop after the first level whose |J - J_ref| / J_ref is at most this fraction "
                   "(--levels stays the limit)")
        ->check(CLI::PositiveNumber)
        ->needs(reference_option);
    // The tools' runner (tools/common): `bpm-torsion: error: FILE: message` and the exit
    // codes of README.md (3 for a missing or unusable file, 2 for a bad command line).
    // Before, a missing file said "bpm-torsion: cannot open: No such file or directory"
    // (which file?) with exit 1, an unknown option exited 106, and --version was unknown.
    const std::string tool = "bpm-torsion";
    bpm::tools::add_version_flag(app, tool);
    return bpm::tools::run(tool, argc, argv, app, [&]() -> int {
    if (!adaptive && levels > 8)  // each uniform level has 8 times the tets of the one before
        throw CLI::ValidationError("--levels", std::to_string(levels) + " without --adaptive: at most 8 uniform levels");
    try {
        const bpm::BpmFile file = bpm::read_bpm(input);
        if (!file.tetmesh) throw bpm::InputError(input, "the .bpm file has no tet mesh (/tetmesh): run bpm-mesh on it first");
        auto phi = std::make_shared<const bpm::PhiEvaluator>(file.param);
        auto built = bpm::dune::make_uggrid(file, phi, flat ? bpm::dune::BoundaryGeometry::Flat
                                                             : bpm::dune::BoundaryGeometry::Phi);
        Grid& grid = *built.grid;
        bpm::dune::BoundaryParameterPoints params(built, file.param.coarse, !flat_interfaces);
        const int regions = file.tetmesh->num_regions();
        const std::vector<double> original_volumes = bpm::region_volumes_on_original(file.param, *file.tetmesh);

        std::vector<LevelReport> reports;
        std::vector<Dune::FieldVector<double, 3>> gradients;
        int reached_error = -1;  // --until-error: the level that reached it
        int64_t rules_kept_before = bpm::dune::uggrid_refinement_rules_kept();
        bpm::BoundaryRepairOptions repair_options;
        repair_options.smooth = !no_smooth;
        repair_options.retreat = !no_retreat;
        repair_options.slide = !no_slide;
        for (int level = 0; level <= levels; ++level) {
            const auto start = std::chrono::steady_clock::now();
            LevelReport report;
            report.level = level;
            // After every adapt()/globalRefine(1): parameter points of the new boundary vertices,
            // then the repair (before the next adapt() refines the repaired grid).
            auto after_refinement = [&]() {
                const auto added = params.update(grid);
                if (flat) return;
                report.inverted_before_repair += count_inverted(grid);
                if (no_repair) return;
                int64_t reset = 0;
                const bpm::BoundaryRepairResult r = bpm::dune::repair_uggrid(grid, params, added, *phi, repair_options, &reset);
                report.reset += reset;
                report.inverted_after_reset += r.inverted_before;
                report.held_back += r.held_back;
                report.smoothed += r.smoothed_vertices;
                report.retreated += r.retreated;
                report.slid += r.slid;
            };
            if (level > 0) {
                if (adaptive) {
                    const auto marks = select_by_estimator(grid, gradients);
                    const bpm::dune::UGGridAdaptResult adapted = bpm::dune::adapt_uggrid(grid, marks, after_refinement);
                    report.marked = adapted.marked;
                    report.adapts = adapted.adapts;
                    report.superseded = adapted.superseded;
                } else {
                    grid.globalRefine(1);
                    after_refinement();
                }
            }
            report.rules_kept = bpm::dune::uggrid_refinement_rules_kept() - rules_kept_before;
            rules_kept_before += report.rules_kept;
            solve_torsion(grid, report, gradients);
            measure(grid, built, params, *phi, regions, report);
            report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            reports.push_back(report);
            std::cerr << "level " << level << ": " << report.tets << " tets, J = " << report.J
                          << ", volume = " << report.volume << ", inverted " << report.inverted << " (" << report.inverted_before_repair
                          << " before repair, " << report.held_back << " held back, " << report.reset << " reset), min dihedral "
                          << report.min_dihedral_degrees << " deg, CG " << report.cg_iterations << " it"
                          << (adaptive && level > 0 ? ", marked " + std::to_string(report.marked) + " in " +
                                                          std::to_string(report.adapts) + " adapt calls"
                                                    : std::string())
                          << ", " << report.seconds << " s" << std::endl;
            if (adaptive && until_error > 0 && std::abs(report.J - reference_j) <= until_error * reference_j) {
                reached_error = level;
                break;
            }
        }

        if (json) {
            std::ostringstream out;
            out << "{\"input\": \"" << input << "\", \"boundary\": \"" << (flat ? "flat" : "phi")
                << "\", \"refinement\": \"" << (adaptive ? "adaptive" : "global") << "\", \"repair\": " << (flat || no_repair ? "false" : "true")
                << ", \"smooth\": " << (flat || no_repair || no_smooth ? "false" : "true")
                << ", \"retreat\": " << (flat || no_repair || no_retreat ? "false" : "true")
                << ", \"slide\": " << (flat || no_repair || no_slide ? "false" : "true")
                << ", \"interfaces\": \"" << (flat || no_repair || flat_interfaces ? "flat" : "phi") << "\""
                << ", \"interface_faces\": " << params.interface_faces()
                << ", \"original_region_volumes\": [";
            for (size_t r = 0; r < original_volumes.size(); ++r) out << (r ? ", " : "") << json_number(original_volumes[r]);
            out << "], \"region_names\": [";
            // The material name of each region where the file has materials (spec/tetmesh.md), else "region r".
            const bpm::TetMesh& mesh = *file.tetmesh;
            for (int r = 1; r <= regions; ++r) {
                std::string name = "region " + std::to_string(r);
                if (static_cast<size_t>(r) <= mesh.region_material.size()) {
                    const int32_t m = mesh.region_material[static_cast<size_t>(r - 1)];
                    if (m >= 1 && static_cast<size_t>(m) <= mesh.material_names.size() &&
                        !mesh.material_names[static_cast<size_t>(m - 1)].empty())
                        name = mesh.material_names[static_cast<size_t>(m - 1)] + " (region " + std::to_string(r) + ")";
                }
                out << (r > 1 ? ", " : "") << json_string(name);
            }
            out << "]";
            if (until_error > 0)
                out << ", \"reference_j\": " << json_number(reference_j) << ", \"until_error\": " << json_number(until_error)
                    << ", \"until_error_reached_at\": " << reached_error;
            out << ", \"levels\": [";
            for (size_t k = 0; k < reports.size(); ++k) {
                const LevelReport& r = reports[k];
                out << (k ? ",\n  " : "\n  ") << "{\"level\": " << r.level << ", \"tets\": " << r.tets
                    << ", \"vertices\": " << r.vertices << ", \"unknowns\": " << r.unknowns
                    << ", \"J\": " << json_number(r.J) << ", \"volume\": " << json_number(r.volume)
                    << ", \"region_volumes\": [";
                for (size_t i = 0; i < r.region_volumes.size(); ++i)
                    out << (i ? ", " : "") << json_number(r.region_volumes[i]);
                out << "], \"inverted\": " << r.inverted
                    << ", \"min_dihedral_degrees\": " << json_number(r.min_dihedral_degrees)
                    << ", \"max_boundary_offset\": " << json_number(r.max_boundary_offset)
                    << ", \"inverted_before_repair\": " << r.inverted_before_repair
                    << ", \"held_back\": " << r.held_back << ", \"smoothed\": " << r.smoothed << ", \"retreated\": " << r.retreated << ", \"slid\": " << r.slid << ", \"reset\": " << r.reset
                    << ", \"inverted_after_reset\": " << r.inverted_after_reset
                    << ", \"rules_kept\": " << r.rules_kept << ", \"marked\": " << r.marked
                    << ", \"adapts\": " << r.adapts << ", \"superseded\": " << r.superseded
                    << ", \"cg_iterations\": " << r.cg_iterations
                    << ", \"cg_converged\": " << (r.cg_converged ? "true" : "false")
                    << ", \"seconds\": " << json_number(r.seconds) << "}";
            }
            out << "\n]}\n";
            std::cout << out.str();
        }
    } catch (const Dune::Exception& e) {
        throw bpm::AlgorithmError(std::string("DUNE: ") + e.what());
    }
    return 0;
    });
}
