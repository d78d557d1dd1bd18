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
#include "bpm/tetmesh_smooth.h"
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

// A cube of `res` x `res` quads per face whose faces are dented: each original vertex that
// is not a coarse vertex moves along the normal of its face to 0.5 - depth * (x - 0.5)
// (depth < 0: past the centre plane). Moving new boundary vertices all the way would
// invert elements.
Parametrization dented_cube(int res, double depth) {
    const Surface cube = fixtures::cube(res);
    Parametrization p = fixtures::refined_parametrization(cube);
    for (int32_t v = cube.num_vertices(); v < p.original.num_vertices(); ++v) {
        Vec3& x = p.original.vertices[v];
        int axis = 0;
        for (int k = 1; k < 3; ++k)
            if (std::fabs(x[k] - 0.5) > std::fabs(x[axis] - 0.5)) axis = k;
        x[axis] = 0.5 + depth * (x[axis] - 0.5);
    }
    fixtures::recompute_images(p);
    return p;
}

double min_dihedral(const TetMesh& m) { return tetmesh_stats(m).min_dihedral_degrees; }

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
        const SurfacePoint& q = m.vertex_parameter_points[v];
        if (!q.valid()) continue;
        const Vec3 x = phi.evaluate(q.triangle, q.barycentric).position;
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
            o.flip = false;  // exactly red refinement (flips change the count)
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
                CHECK(fine.vertex_parameter_points[v].valid() == (on_faces.count(v) == 1));
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
    o.repair.smooth = false;
    TetMesh one, three;
    o.levels = 1;
    refine_tetmesh(p, coarse, o, {}, one);
    o.levels = 3;
    refine_tetmesh(p, coarse, o, {}, three);
    // Children of level 1 already show every class; levels 2 and 3 add no new shapes.
    CHECK(tetmesh_stats(three).min_dihedral_degrees == Approx(tetmesh_stats(one).min_dihedral_degrees).epsilon(1e-9));
    CHECK(tetmesh_stats(three).max_dihedral_degrees == Approx(tetmesh_stats(one).max_dihedral_degrees).epsilon(1e-9));
}

TEST_CASE("tet_refine: the first level cuts every octahedron along its best diagonal, whatever the corner order",
          "[tet_refine]") {
    REQUIRE_TETGEN();
    // A box 3 x 1 x 0.5: TetGen's tetrahedra are not symmetric, so the three inner diagonals
    // of their octahedra give children of different shapes.
    Surface box = fixtures::cube(2);
    for (Vec3& x : box.vertices) x = Vec3{3 * x[0], x[1], 0.5 * x[2]};
    const Parametrization p = fixtures::identity_parametrization(box);
    const TetMesh coarse = mesh_of(p);
    TetRefineOptions o;
    o.move_to_surface = false;
    o.repair.smooth = false;
    o.levels = 1;
    // The same tetrahedra with their corners cycled (even permutations: orientation kept):
    // Bey's rule alone would cut M02 -- M13 of each order, three different diagonals.
    double worst[3];
    for (int cycle = 0; cycle < 3; ++cycle) {
        TetMesh input = coarse;
        for (Tet& t : input.tetrahedra)
            for (int k = 0; k < cycle; ++k) t = Tet{t[0], t[2], t[3], t[1]};
        TetMesh fine;
        refine_tetmesh(p, input, o, {}, fine);
        CHECK(count_inverted(fine) == 0);
        worst[cycle] = min_dihedral(fine);
    }
    INFO("worst child angle per corner order: " << worst[0] << ", " << worst[1] << ", " << worst[2]);
    CHECK(worst[1] == Approx(worst[0]).epsilon(1e-12));
    CHECK(worst[2] == Approx(worst[0]).epsilon(1e-12));
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
    const Parametrization p = dented_cube(1, -0.3);
    const TetMesh coarse = mesh_of(p);

    TetRefineOptions o;
    o.levels = 1;
    o.repair.min_volume_fraction = 0;  // the paper's rule: positive volume only
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
            if (const SurfacePoint& q = naive.vertex_parameter_points[v]; q.valid())
                naive.vertices[v] = phi.evaluate(q.triangle, q.barycentric).position;
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
    CHECK(back.tetmesh->vertex_parameter_points == fine.vertex_parameter_points);
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
    o.levels = 1;
    o.repair.min_dihedral_degrees = -1;
    CHECK_THROWS_AS(refine_tetmesh(p, coarse, o, {}, fine), OptionError);
    o.repair.min_dihedral_degrees = 5;
    o.repair.boundary_steps = 0;
    CHECK_THROWS_AS(refine_tetmesh(p, coarse, o, {}, fine), OptionError);
    o.repair.boundary_steps = 1;
    o.repair.smoothing.sweeps = -1;
    CHECK_THROWS_AS(refine_tetmesh(p, coarse, o, {}, fine), OptionError);
}

// --- interior smoothing (bpm/tetmesh_smooth.h) --------------------------------------

namespace {

// A cube whose faces sag inwards between the coarse vertices: moving the new boundary
// vertices onto it squashes the tetrahedra next to the boundary (into slivers where only
// positive volume is asked for). Sagging to 0.6 of the distance from the centre: at 0.7 the
// children of the best inner diagonal (refine_tetmesh's first level) stayed at 3.3 degrees.
Parametrization sagging_cube() { return bent(fixtures::cube(2), {0.5, 0.5, 0.5}, 0.6); }

TetMesh plain_mesh_of(const Parametrization& p) {
    TetMesh m;
    TetMeshOptions o;
    o.smooth = false;
    generate_tetmesh(p, o, Context{}, m);
    return m;
}


// The setup the smoothing tests share: the sagging cube, its TetGen mesh (not smoothed),
// and refinements of that mesh.
struct SaggingCube {
    Parametrization p = sagging_cube();
    TetMesh coarse = plain_mesh_of(p);

    // refine_tetmesh of the coarse mesh with `o`; its result into *result if asked for.
    TetMesh refine(const TetRefineOptions& o, TetRefineResult* result = nullptr) const {
        TetMesh fine;
        const TetRefineResult r = refine_tetmesh(p, coarse, o, {}, fine);
        if (result) *result = r;
        return fine;
    }
    // Plain red refinement: no vertex moved onto the surface, none smoothed (the children
    // keep Bey's shapes: no slivers).
    TetMesh plain_red(int levels) const {
        TetRefineOptions o;
        o.levels = levels;
        o.move_to_surface = false;
        o.repair.smooth = false;
        o.flip = false;
        return refine(o);
    }
};

}  // namespace

TEST_CASE("tet_smooth: the signed minimum dihedral angle", "[tet_refine][tet_smooth]") {
    const Vec3 o{0, 0, 0}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
    CHECK(tet_min_dihedral_degrees(o, x, y, z) == Approx(std::acos(1 / std::sqrt(3.0)) * 180 / 3.14159265358979323846));
    CHECK(tet_min_dihedral_degrees(o, x, z, y) < 0);          // inverted
    CHECK(tet_min_dihedral_degrees(o, x, y, {1, 1, 0}) == 0);  // flat
    // tetmesh_stats measures with the same function: equal on a real (positive) mesh
    REQUIRE_TETGEN();
    const TetMesh m = SaggingCube().coarse;
    double low = 180;
    for (const Tet& t : m.tetrahedra)
        low = std::min(low,
                       tet_min_dihedral_degrees(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]], m.vertices[t[3]]));
    CHECK(low == min_dihedral(m));
}

TEST_CASE("tet_smooth: smoothing the interior never inverts, raises the worst angle, and keeps S fixed",
          "[tet_refine][tet_smooth]") {
    REQUIRE_TETGEN();
    const SaggingCube cube;
    // Red refinement with the boundary moved onto the sagging faces as far as volumes stay
    // positive (the paper's rule), not smoothed.
    TetRefineOptions o;
    o.levels = 1;
    o.repair.smooth = false;
    o.repair.min_volume_fraction = 0;
    o.repair.min_dihedral_degrees = 0;
    const TetMesh moved = cube.refine(o);
    const TetMesh plain = cube.plain_red(1);
    const double before = min_dihedral(moved);
    INFO("plain red refinement " << min_dihedral(plain) << " degrees, boundary moved " << before);
    REQUIRE(before < 1);  // the move made slivers
    REQUIRE(min_dihedral(plain) > 10);
    REQUIRE(count_inverted(moved) == 0);

    TetMesh smoothed = moved;
    const TetSmoothResult r = smooth_tetmesh(smoothed, TetSmoothOptions{});
    const double after = min_dihedral(smoothed);
    INFO("smoothed " << after << " degrees, " << r.moved_vertices << " vertices moved");
    CHECK(count_inverted(smoothed) == 0);
    CHECK(after > before);
    // (the smoother compares pseudo-angles and converts its extremes back with asin)
    CHECK(r.min_dihedral_before_degrees == Approx(before).epsilon(1e-9).margin(1e-5));
    CHECK(r.min_dihedral_after_degrees == Approx(after).epsilon(1e-9).margin(1e-5));
    CHECK(r.moved_vertices > 0);
    int64_t interior_moved = 0;
    for (int32_t v = 0; v < moved.num_vertices(); ++v) {
        if (moved.vertex_parameter_points[v].valid()) {
            INFO("boundary vertex " << v);
            CHECK(smoothed.vertices[v] == moved.vertices[v]);  // bit for bit
        } else {
            interior_moved += smoothed.vertices[v] != moved.vertices[v];
        }
    }
    CHECK(interior_moved == r.moved_vertices);
    // Nothing else changes.
    CHECK(smoothed.tetrahedra == moved.tetrahedra);
    CHECK(smoothed.faces == moved.faces);
    CHECK(tetmesh_stats(smoothed).region_volumes[0] == Approx(tetmesh_stats(moved).region_volumes[0]).epsilon(1e-12));
    // A second run starts from a smoothed mesh and cannot make the worst element worse.
    TetMesh again = smoothed;
    smooth_tetmesh(again, TetSmoothOptions{});
    CHECK(min_dihedral(again) >= after);
    CHECK(count_inverted(again) == 0);

    TetSmoothOptions bad;
    bad.sweeps = -1;
    CHECK_THROWS_AS(smooth_tetmesh(again, bad), OptionError);
    bad = TetSmoothOptions{};
    bad.target_degrees = 0;
    CHECK_THROWS_AS(smooth_tetmesh(again, bad), OptionError);
}

TEST_CASE("tet_refine: smoothing during refinement beats smoothing off, with the boundary on phi",
          "[tet_refine][tet_smooth]") {
    REQUIRE_TETGEN();
    const SaggingCube cube;
    const Parametrization& p = cube.p;
    TetRefineOptions on;
    on.levels = 2;
    on.flip = false;  // smoothing alone (flips change the tetrahedra)
    TetRefineOptions off = on;
    off.repair.smooth = false;
    TetRefineResult ra, rb;
    const TetMesh a = cube.refine(on, &ra), b = cube.refine(off, &rb);
    INFO("smoothed " << min_dihedral(a) << " degrees, not smoothed " << min_dihedral(b));
    CHECK(min_dihedral(a) > min_dihedral(b));
    CHECK(ra.inverted == 0);
    CHECK(count_inverted(a) == 0);
    // Same connectivity and parameter positions; boundary vertices at phi except the
    // remedied ones, and smoothing lets no more of them stay off S0.
    CHECK(a.tetrahedra == b.tetrahedra);
    CHECK(a.vertex_parameter_points == b.vertex_parameter_points);
    CHECK(count_off_surface(p, a) == ra.remedied_vertices);
    CHECK(ra.remedied_vertices <= rb.remedied_vertices);
    // The per-level report describes the mesh.
    REQUIRE(ra.levels.size() == 2);
    const TetRefineLevel& last = ra.levels.back();
    CHECK(last.min_dihedral_degrees == Approx(min_dihedral(a)).epsilon(1e-9).margin(1e-5));
    int64_t below10 = 0;  // (not 8: the default remedy stops vertices at exactly 8 degrees)
    for (const Tet& t : a.tetrahedra)
        below10 +=
            tet_min_dihedral_degrees(a.vertices[t[0]], a.vertices[t[1]], a.vertices[t[2]], a.vertices[t[3]]) < 10;
    CHECK(last.below_10_degrees == below10);
    CHECK(last.below_10_degrees == tetmesh_stats(a).below_10_degrees);
    CHECK(last.off_surface_vertices == ra.remedied_vertices);
    CHECK(last.smoothed_vertices > 0);
    CHECK(rb.levels.back().smoothed_vertices == 0);
}

TEST_CASE("tet_refine: the remedy's angle bound keeps slivers from forming at the boundary",
          "[tet_refine][tet_smooth]") {
    REQUIRE_TETGEN();
    const SaggingCube cube;
    TetRefineOptions o;
    o.levels = 1;
    o.repair.min_volume_fraction = 0;
    o.flip = false;  // the remedy and smoothing alone
    REQUIRE(min_dihedral(cube.plain_red(1)) > 10);
    for (bool smooth : {false, true}) {
        INFO("smoothing " << smooth);
        o.repair.smooth = smooth;
        // Each move of a boundary vertex keeps the tetrahedra around it at min(bound, what
        // they had), starting from plain red refinement; smoothing never lowers the minimum.
        o.repair.min_dihedral_degrees = 5;
        TetRefineResult r;
        const TetMesh bounded = cube.refine(o, &r);
        CHECK(min_dihedral(bounded) >= 5 - 1e-6);
        CHECK(count_inverted(bounded) == 0);
        CHECK(count_off_surface(cube.p, bounded) == r.remedied_vertices);
        o.repair.min_dihedral_degrees = 0;  // positive volume only: slivers where nothing smooths them
        const TetMesh unbounded = cube.refine(o);
        CHECK(count_inverted(unbounded) == 0);
        if (!smooth) CHECK(min_dihedral(unbounded) < 1);
    }
}
