// Tests of the deal.II adapter (bpm/dealii/), built and run against deal.II's Debug
// library with the example (-DBPM_WITH_DEALII=ON), so deal.II's own assertions run too.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>

#include <deal.II/base/exceptions.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "bpm/dealii/global_refinement.h"
#include "bpm/dealii/triangulation_from_bpm.h"
#include "bpm/tetmesh.h"
#include "fixtures_phi.h"
#include "fixtures_surfaces.h"

using namespace bpm;
using namespace bpm::dealii;

namespace {

BpmFile with_tetmesh(Parametrization p) {
    BpmFile f;
    f.param = std::move(p);
    TetMesh m;
    generate_tetmesh(f.param, TetMeshOptions{}, Context{}, m);
    f.tetmesh = std::move(m);
    return f;
}

// Octahedron whose phi maps onto a bumpy sphere (tests/unit/fixtures_phi.h).
const BpmFile& octahedron() {
    static const BpmFile f = with_tetmesh(test::make_subdivided_octahedron(3));
    return f;
}

// Two unit cubes sharing a square (regions 1 and 2, an interface on S), with the original
// surface's non-coarse vertices pushed out radially from (0.5, 0.5, 0.5): phi bends the
// interface too.
const BpmFile& two_cubes() {
    static const BpmFile f = [] {
        const Surface coarse = fixtures::two_cubes(2);
        Parametrization p = fixtures::refined_parametrization(coarse);
        const Vec3 centre{0.5, 0.5, 0.5};
        for (int32_t v = coarse.num_vertices(); v < p.original.num_vertices(); ++v)
            p.original.vertices[v] = centre + 1.1 * (p.original.vertices[v] - centre);
        fixtures::recompute_images(p);
        return with_tetmesh(std::move(p));
    }();
    return f;
}

// Vertices on S (of the adapter's faces on S) whose position is not exactly phi of their
// parameter point.
int64_t vertices_off_phi(const BpmTriangulation& mesh) {
    const std::vector<SurfacePoint> p = mesh.vertex_parameter_points();
    const auto& v = mesh.triangulation().get_vertices();
    int64_t off = 0, on_s = 0;
    for (size_t i = 0; i < p.size(); ++i) {
        if (!p[i].valid()) continue;
        ++on_s;
        if (to_vec3(v[i]) != mesh.boundary()->phi().evaluate(p[i].triangle, p[i].barycentric).position) ++off;
    }
    REQUIRE(on_s > 0);
    return off;
}

double volume(const BpmTriangulation& mesh) {
    double v = 0;
    for (double r : tetmesh_stats(mesh.cells_as_tetmesh()).region_volumes) v += r;
    return v;
}

}  // namespace

TEST_CASE("dealii_local_refinement_of_simplices_is_refused") {
    ::dealii::deal_II_exceptions::disable_abort_on_exception();
    BpmTriangulation mesh(octahedron(), BoundaryMode::Phi);
    auto& tria = mesh.triangulation();
    SECTION("one cell flagged") {
        tria.begin_active()->set_refine_flag();
        REQUIRE_THROWS_WITH(execute_refinement(mesh), Catch::Contains("only globally") && Catch::Contains("1 of"));
    }
    SECTION("nothing flagged") { REQUIRE_THROWS_AS(execute_refinement(mesh), OptionError); }
    SECTION("every cell flagged is global refinement") {
        for (const auto& cell : tria.active_cell_iterators()) cell->set_refine_flag();
        const GlobalRefineResult r = execute_refinement(mesh);
        CHECK(r.cells == 8 * static_cast<int64_t>(octahedron().tetmesh->tetrahedra.size()));
        SECTION("and after it, local refinement is refused again") {
            tria.last_active()->set_refine_flag();
            REQUIRE_THROWS_AS(execute_refinement(mesh), OptionError);
        }
    }
}

TEST_CASE("dealii_triangulation_keeps_the_tet_mesh_numbering_and_regions") {
    const BpmFile& f = two_cubes();
    BpmTriangulation mesh(f, BoundaryMode::Phi);
    const TetMesh m = mesh.to_tetmesh();
    CHECK(m.vertices == f.tetmesh->vertices);
    CHECK(m.tetrahedra == f.tetmesh->tetrahedra);
    CHECK(m.regions == f.tetmesh->regions);
    CHECK(m.vertex_parameter_points == f.tetmesh->vertex_parameter_points);
    CHECK(m.faces.size() == f.tetmesh->faces.size());
    CHECK(find_tetmesh_inconsistency(m, f.param.coarse).empty());
    // MappingFE asserts that every entity of a cell has the cell's manifold id: between
    // refinements, all ids are flat.
    for (const auto& cell : mesh.triangulation().active_cell_iterators())
        for (const unsigned k : cell->face_indices()) CHECK(cell->face(k)->manifold_id() == ::dealii::numbers::flat_manifold_id);
}

TEST_CASE("dealii_flat_refinement_keeps_the_coarse_volume_and_inverts_nothing") {
    BpmTriangulation mesh(octahedron(), BoundaryMode::Flat);
    const double v0 = volume(mesh);
    const int64_t faces0 = static_cast<int64_t>(octahedron().tetmesh->faces.size());
    for (int level = 1; level <= 2; ++level) {
        const GlobalRefineResult r = refine_global(mesh);
        CHECK(r.inverted == 0);
        CHECK(r.surface_faces == faces0 << (2 * level));
        CHECK(std::abs(volume(mesh) - v0) <= 1e-12 * v0);
    }
}

TEST_CASE("dealii_new_vertices_on_edges_of_S_go_through_phi_not_only_those_on_faces") {
    // Without the repair every vertex on S, the new ones on the edges of faces on S
    // included, is exactly at phi: with the manifold id on the faces only, deal.II 9.4
    // splits those edges flat.
    for (const BpmFile* f : {&octahedron(), &two_cubes()}) {
        BpmTriangulation mesh(*f, BoundaryMode::Phi);
        GlobalRefineOptions o;
        o.repair = false;
        for (int level = 1; level <= 2; ++level) {
            const GlobalRefineResult r = refine_global(mesh, o);
            CHECK(r.phi_fallbacks == 0);
            CHECK(vertices_off_phi(mesh) == 0);
        }
        CHECK(find_tetmesh_inconsistency(mesh.to_tetmesh(), f->param.coarse).empty());
    }
}

TEST_CASE("dealii_interfaces_between_regions_follow_phi_and_stay_conforming") {
    const BpmFile& f = two_cubes();
    BpmTriangulation flat(f, BoundaryMode::Flat), phi(f, BoundaryMode::Phi);
    GlobalRefineOptions o;
    o.repair = false;
    refine_global(flat, o);
    refine_global(phi, o);
    // Vertices on the interface (on S, not on the outer boundary): some moved off the flat
    // square x = 1 by phi. Same numbering in both (same refinement).
    std::set<unsigned> outer;
    for (const auto& cell : phi.triangulation().active_cell_iterators())
        for (const unsigned k : cell->face_indices())
            if (cell->face(k)->at_boundary())
                for (unsigned v = 0; v < 3; ++v) outer.insert(cell->face(k)->vertex_index(v));
    const std::vector<SurfacePoint> p = phi.vertex_parameter_points();
    int64_t interface = 0, moved = 0;
    for (unsigned i = 0; i < p.size(); ++i) {
        if (!p[i].valid() || outer.count(i)) continue;
        ++interface;
        moved += phi.triangulation().get_vertices()[i] != flat.triangulation().get_vertices()[i];
    }
    CHECK(interface > 0);
    CHECK(moved > 0);
    // Both regions keep their material ids, and the mesh stays a consistent tet mesh.
    std::set<unsigned> materials;
    for (const auto& cell : phi.triangulation().active_cell_iterators()) materials.insert(cell->material_id());
    CHECK(materials == std::set<unsigned>{1, 2});
    CHECK(find_tetmesh_inconsistency(phi.to_tetmesh(), f.param.coarse).empty());
}

TEST_CASE("dealii_refinement_with_repair_leaves_no_inverted_cell") {
    for (const BpmFile* f : {&octahedron(), &two_cubes()}) {
        BpmTriangulation mesh(*f, BoundaryMode::Phi);
        for (int level = 1; level <= 2; ++level) {
            const GlobalRefineResult r = refine_global(mesh);
            CHECK(r.repaired);
            CHECK(r.inverted == 0);
            CHECK(count_inverted_cells(mesh.triangulation()) == 0);
            // Held-back vertices are the only ones off phi.
            CHECK(vertices_off_phi(mesh) == r.repair.held_back);
        }
    }
}

TEST_CASE("dealii_plain_positions_are_the_midpoints_of_the_lines_the_vertices_were_made_on") {
    // Flat: right after a refinement every new vertex is where deal.II put it, its line's
    // midpoint; level-0 vertices are where they are.
    BpmTriangulation flat(two_cubes(), BoundaryMode::Flat);
    const size_t n0 = flat.triangulation().n_vertices();
    refine_global(flat);
    std::vector<Vec3> plain = flat.plain_positions();
    const TetMesh cells = flat.cells_as_tetmesh();
    REQUIRE(plain.size() == cells.vertices.size());
    CHECK(plain == cells.vertices);
    // Phi with the repair: vertices of both refinements have moved since; each plain
    // position is the midpoint of its line's ends where they are now.
    BpmTriangulation phi(two_cubes(), BoundaryMode::Phi);
    refine_global(phi);
    refine_global(phi);
    plain = phi.plain_positions();
    const auto& x = phi.triangulation().get_vertices();
    REQUIRE(plain.size() == x.size());
    for (size_t i = 0; i < n0; ++i) CHECK(plain[i] == to_vec3(x[i]));
    std::set<unsigned> mids;
    int64_t off = 0;
    for (const auto& cell : phi.triangulation().cell_iterators())
        for (unsigned l = 0; l < cell->n_lines(); ++l) {
            const auto line = cell->line(l);
            if (!line->has_children()) continue;
            const unsigned mid = line->child(0)->vertex_index(1);
            CHECK(plain[mid] == 0.5 * (to_vec3(x[line->vertex_index(0)]) + to_vec3(x[line->vertex_index(1)])));
            if (mids.insert(mid).second) off += plain[mid] != to_vec3(x[mid]);
        }
    CHECK(mids.size() == x.size() - n0);  // every new vertex is a line midpoint
    CHECK(off > 0);  // the repair moved some
}

TEST_CASE("dealii_refinement_repair_retreats_boundary_vertices_towards_their_midpoints") {
    // The repair gets the plain positions (bpm/boundary_repair.h step 5): with an angle
    // bound most cells near S miss, boundary vertices that reached phi at level 1 move back
    // towards their midpoints at level 2 where that widens the worst cell around them.
    // Without plain positions (before the adapter passed them) nothing retreats.
    for (const bool retreat : {true, false}) {
        BpmTriangulation mesh(two_cubes(), BoundaryMode::Phi);
        GlobalRefineOptions o;
        o.repair_options.min_dihedral_degrees = 25;
        o.repair_options.retreat = retreat;
        int64_t retreated = 0;
        for (int level = 1; level <= 2; ++level) {
            const GlobalRefineResult r = refine_global(mesh, o);
            CHECK(r.inverted == 0);
            CHECK(vertices_off_phi(mesh) == r.repair.held_back);  // retreated vertices are held back
            retreated += r.repair.retreated;
        }
        if (retreat) CHECK(retreated > 0);
        else CHECK(retreated == 0);
    }
}
