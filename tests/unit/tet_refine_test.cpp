// Tests of bpm/tet_refine.h: red refinement of TetGen meshes with boundary vertices moved
// onto the original surface through phi, and the lambda remedy of Krause & Sander §3.3.

#include <catch2/catch.hpp>

#include "test_support.h"
#include <cmath>
#include <cstdlib>
#include <set>

#include "bpm/bpm_file.h"
#include "bpm/errors.h"
#include "bpm/phi_evaluation.h"
#include "bpm/predicates.h"
#include "bpm/tet_refine.h"
#include "bpm/tetmesh.h"
#include "fixtures_surfaces.h"

using namespace bpm;

namespace {


TetMesh mesh_of(const Parametrization& p) {
    TetMesh m;
    generate_tetmesh(p, TetMeshOptions{}, Context{}, m);
    return m;
}

// refined_parametrization(coarse) with every original vertex that is not a coarse vertex
// moved radially from `centre` by `factor` (> 1 bulges out, < 1 pulls in): phi stays a
// bijective PL map onto the moved original surface.
Parametrization bent(const Surface& coarse, const Vec3& centre, double factor) {
    Parametrization p = fixtures::refined_parametrization(coarse);
    for (int32_t v = coarse.num_vertices(); v < p.original.num_vertices(); ++v)
        p.original.vertices[v] = centre + factor * (p.original.vertices[v] - centre);
    fixtures::recompute_images(p);
    return p;
}

int64_t count_inverted(const TetMesh& m) {
    int64_t n = 0;
    for (const Tet& t : m.tetrahedra)
        n += orient3d(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]], m.vertices[t[3]]) != 1;
    return n;
}

// Boundary vertices not exactly at phi of their parameter position.
int64_t count_off_surface(const Parametrization& p, const TetMesh& m, double* max_gap = nullptr) {
    PhiEvaluator phi(p);
    int64_t off = 0;
    double gap = 0;
    for (int32_t v = 0; v < m.num_vertices(); ++v) {
        if (m.vertex_parameter_triangle[v] < 0) continue;
        const Vec3 x = phi.evaluate(m.vertex_parameter_triangle[v], m.vertex_parameter_barycentric[v]).position;
        if (x != m.vertices[v]) {
            ++off;
            gap = std::max(gap, distance(x, m.vertices[v]));
        }
    }
    if (max_gap) *max_gap = gap;
    return off;
}

}  // namespace

TEST_CASE("tet_refine: red refinement multiplies elements by 8 and faces by 4, keeping volumes", "[tet_refine]") {
    REQUIRE_TETGEN();
    for (const Surface& s : {fixtures::two_cubes(), fixtures::octants()}) {
        const Parametrization p = fixtures::identity_parametrization(s);
        const TetMesh coarse = mesh_of(p);
        const TetMeshStats before = tetmesh_stats(coarse);
        for (int k = 0; k <= 2; ++k) {
            INFO("levels " << k);
            TetMesh fine;
            TetRefineOptions o;
            o.levels = k;
            const TetRefineResult r = refine_tetmesh(p, coarse, o, {}, fine);
            REQUIRE(find_tetmesh_inconsistency(fine, p.coarse).empty());
            CHECK(fine.num_tetrahedra() == coarse.num_tetrahedra() * (1 << (3 * k)));
            CHECK(fine.faces.size() == coarse.faces.size() * (size_t(1) << (2 * k)));
            CHECK(fine.level == k);
            CHECK(r.inverted == 0);
            CHECK(count_inverted(fine) == 0);
            CHECK(r.remedied_vertices == 0);  // phi = identity: nothing moves
            const TetMeshStats after = tetmesh_stats(fine);
            REQUIRE(after.region_volumes.size() == before.region_volumes.size());
            for (size_t i = 0; i < before.region_volumes.size(); ++i)
                CHECK(after.region_volumes[i] == Approx(before.region_volumes[i]).epsilon(1e-12));
            // regions and ancestors are inherited
            if (k > 0)
                for (size_t t = 0; t < fine.tetrahedra.size(); ++t)
                    CHECK(fine.regions[t] == coarse.regions[fine.tet_ancestor[t]]);
            // the vertices on S are exactly those of the faces
            std::set<int32_t> on_faces;
            for (const Tri& f : fine.faces) on_faces.insert(f.begin(), f.end());
            for (int32_t v = 0; v < fine.num_vertices(); ++v)
                CHECK((fine.vertex_parameter_triangle[v] >= 0) == (on_faces.count(v) == 1));
            CHECK(count_off_surface(p, fine) == 0);
        }
    }
}

TEST_CASE("tet_refine: Bey's rule keeps the shape classes (min dihedral angle stable)", "[tet_refine]") {
    REQUIRE_TETGEN();
    const Parametrization p = fixtures::identity_parametrization(fixtures::cube(2));
    const TetMesh coarse = mesh_of(p);
    TetRefineOptions o;
    o.move_to_surface = false;
    TetMesh one, three;
    o.levels = 1;
    refine_tetmesh(p, coarse, o, {}, one);
    o.levels = 3;
    refine_tetmesh(p, coarse, o, {}, three);
    // Children of level 1 already show every class; levels 2 and 3 add no new shapes.
    CHECK(tetmesh_stats(three).min_dihedral_degrees == Approx(tetmesh_stats(one).min_dihedral_degrees).epsilon(1e-9));
    CHECK(tetmesh_stats(three).max_dihedral_degrees == Approx(tetmesh_stats(one).max_dihedral_degrees).epsilon(1e-9));
}

TEST_CASE("tet_refine: boundary vertices move onto a curved original surface", "[tet_refine]") {
    REQUIRE_TETGEN();
    const Surface cube = fixtures::cube(2);
    const Parametrization p = bent(cube, {0.5, 0.5, 0.5}, 1.1);  // bulging out: convex, no inversions
    const TetMesh coarse = mesh_of(p);
    TetMesh fine;
    TetRefineOptions o;
    o.levels = 2;
    const TetRefineResult r = refine_tetmesh(p, coarse, o, {}, fine);
    CHECK(count_inverted(fine) == 0);
    CHECK(r.inverted == 0);
    CHECK(count_off_surface(p, fine) == r.remedied_vertices);
    CHECK(r.remedied_vertices == 0);
    // The refined volume approaches the volume enclosed by the original surface.
    const double original = region_volumes_on_original(p, fine)[0];
    const double coarse_volume = tetmesh_stats(coarse).region_volumes[0];
    const double fine_volume = tetmesh_stats(fine).region_volumes[0];
    CHECK(coarse_volume == Approx(1.0));
    CHECK(original > 1.0);
    CHECK(std::fabs(fine_volume - original) < 0.5 * std::fabs(coarse_volume - original));
    // level 1 already reaches every original vertex of this phi: the volume is exact.
    CHECK(fine_volume == Approx(original).epsilon(1e-9));
}

TEST_CASE("tet_refine: the lambda remedy keeps every tetrahedron positive at a concave surface", "[tet_refine]") {
    REQUIRE_TETGEN();
    const Surface cube = fixtures::cube(1);
    // Dent every face deeply: each original vertex that is not a coarse vertex moves along
    // the normal of its face, past the centre plane. Moving new boundary vertices all the
    // way would invert elements.
    Parametrization p = fixtures::refined_parametrization(cube);
    for (int32_t v = cube.num_vertices(); v < p.original.num_vertices(); ++v) {
        Vec3& x = p.original.vertices[v];
        int axis = 0;
        for (int k = 1; k < 3; ++k)
            if (std::fabs(x[k] - 0.5) > std::fabs(x[axis] - 0.5)) axis = k;
        x[axis] = 0.5 - 0.3 * (x[axis] - 0.5);
    }
    fixtures::recompute_images(p);
    const TetMesh coarse = mesh_of(p);

    TetRefineOptions o;
    o.levels = 1;
    o.min_volume_fraction = 0;  // the paper's rule: positive volume only
    TetMesh fine;
    const TetRefineResult r = refine_tetmesh(p, coarse, o, {}, fine);
    CHECK(count_inverted(fine) == 0);
    CHECK(r.inverted == 0);
    CHECK(r.remedied_vertices > 0);
    double gap = 0;
    // exactly the remedied vertices are off the original surface, and by the reported distance
    CHECK(count_off_surface(p, fine, &gap) == r.remedied_vertices);
    CHECK(gap == Approx(r.max_remedy_distance).epsilon(1e-12));
    CHECK(r.max_remedy_distance > 0);
    CHECK(r.min_phi_fraction < 1);
    CHECK(r.levels.at(0).remedied_vertices == r.remedied_vertices);

    // Moving them all the way would invert tetrahedra (so the remedy was needed).
    {
        TetMesh naive;
        TetRefineOptions flat;
        flat.levels = 1;
        flat.move_to_surface = false;
        refine_tetmesh(p, coarse, flat, {}, naive);
        PhiEvaluator phi(p);
        for (int32_t v = coarse.num_vertices(); v < naive.num_vertices(); ++v)
            if (naive.vertex_parameter_triangle[v] >= 0)
                naive.vertices[v] =
                    phi.evaluate(naive.vertex_parameter_triangle[v], naive.vertex_parameter_barycentric[v]).position;
        CHECK(count_inverted(naive) > 0);
    }

    // With the default volume margin: still no inversion, at least as many remedied.
    TetRefineOptions d;
    d.levels = 2;
    TetMesh fine2;
    const TetRefineResult r2 = refine_tetmesh(p, coarse, d, {}, fine2);
    CHECK(count_inverted(fine2) == 0);
    CHECK(count_off_surface(p, fine2) == r2.remedied_vertices);
    CHECK(tetmesh_stats(fine2).min_dihedral_degrees > 0);
}

TEST_CASE("tet_refine: multi-material meshes keep their regions and interface faces", "[tet_refine]") {
    REQUIRE_TETGEN();
    const Parametrization p = bent(fixtures::cylinder_wedges(12, 2), {0, 0, 1}, 1.05);
    const TetMesh coarse = mesh_of(p);
    TetMesh fine;
    TetRefineOptions o;
    o.levels = 2;
    const TetRefineResult r = refine_tetmesh(p, coarse, o, {}, fine);
    CHECK(count_inverted(fine) == 0);
    CHECK(fine.num_regions() == 3);
    CHECK(count_off_surface(p, fine) == r.remedied_vertices);
    // The regions still tile: the total volume equals the sum over regions of the volume
    // enclosed by the original surface.
    const auto original = region_volumes_on_original(p, fine);
    const auto st = tetmesh_stats(fine);
    for (size_t i = 0; i < original.size(); ++i) CHECK(st.region_volumes[i] == Approx(original[i]).epsilon(1e-9));
    // The refined mesh goes into a .bpm file and comes back with its level and ancestry.
    BpmFile file;
    file.param = p;
    file.tetmesh = fine;
    const BpmFile back = read_bpm_from_memory(write_bpm_to_memory(file), "mem");
    REQUIRE(back.tetmesh.has_value());
    CHECK(back.tetmesh->level == 2);
    CHECK(back.tetmesh->tet_ancestor == fine.tet_ancestor);
    CHECK(back.tetmesh->vertices == fine.vertices);
    CHECK(back.tetmesh->vertex_parameter_barycentric == fine.vertex_parameter_barycentric);
    // Refining the refined mesh again continues from its parameter positions.
    TetMesh finer;
    TetRefineOptions one;
    one.levels = 1;
    const TetRefineResult r3 = refine_tetmesh(p, *back.tetmesh, one, {}, finer);
    CHECK(finer.level == 3);
    CHECK(count_inverted(finer) == 0);
    CHECK(count_off_surface(p, finer) >= r3.remedied_vertices);
    // Options are checked.
    o.levels = -1;
    CHECK_THROWS_AS(refine_tetmesh(p, coarse, o, {}, fine), OptionError);
}
