// Splits of level-0 tetrahedra with a surface corner (tetmesh/tet_split.h): internal, so
// tested here; the real-mesh cases run TetGen (skipped without it).
#include <algorithm>
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/predicates.h"
#include "bpm/tet_refine.h"
#include "bpm/tetmesh.h"
#include "test_support.h"
#include "tetmesh/conforming_mesh_checks.h"
#include "tetmesh/tet_split.h"
#include "tetmesh/tetmesh_internal.h"

using namespace bpm;
using namespace bpm::test;

namespace {

double volume(const std::vector<Vec3>& x, const std::vector<Tet>& tets) {
    double v = 0;
    for (const Tet& t : tets) v += detail::signed_volume(x[t[0]], x[t[1]], x[t[2]], x[t[3]]);
    return v;
}

int64_t with_surface_corner(const std::vector<Tet>& tets, const std::vector<Tri>& faces) {
    const auto edges = detail::surface_edges(faces);
    return std::count_if(tets.begin(), tets.end(), [&](const Tet& t) { return detail::has_surface_corner(t, edges); });
}

// Tetrahedra whose four corners are on S (their vertices have parameter points).
int64_t all_corners_on_s(const TetMesh& m) {
    int64_t n = 0;
    for (const Tet& t : m.tetrahedra)
        n += std::all_of(t.begin(), t.end(), [&](int32_t v) { return m.vertex_parameter_points[v].valid(); });
    return n;
}

}  // namespace

TEST_CASE("tet_split: a bipyramid's tetrahedra each have two faces on S, the axis is split", "[tetmesh][tet_split]") {
    // Ring r0..r4 around the axis from n (north) to s (south): five tetrahedra (n, s, r_i,
    // r_i+1), each with the faces (n, r_i, r_i+1) and (s, r_i+1, r_i) on S, so r_i has three
    // edges on S. The only edge not on S is the axis.
    std::vector<Vec3> x{{0, 0, 1}, {0, 0, -1}};
    const int k = 5;
    for (int i = 0; i < k; ++i) x.push_back({std::cos(2 * M_PI * i / k), std::sin(2 * M_PI * i / k), 0.1 * (i % 2)});
    std::vector<Tet> tets;
    for (int i = 0; i < k; ++i) {
        Tet t{0, 1, 2 + i, 2 + (i + 1) % k};
        if (orient3d(x[t[0]], x[t[1]], x[t[2]], x[t[3]]) < 0) std::swap(t[2], t[3]);
        tets.push_back(t);
    }
    std::vector<int32_t> regions(tets.size(), 3);
    const std::vector<Tri> faces = outer_faces(tets);
    const auto hull = hull_of(tets);
    const double v0 = volume(x, tets);
    REQUIRE(with_surface_corner(tets, faces) == k);

    const detail::TetSplitResult r = detail::split_surface_corners(x, tets, regions, faces);
    CHECK(r.found == k);
    CHECK(r.edge_splits == 1);
    CHECK(r.centroid_splits == 0);
    CHECK(r.left == 0);
    REQUIRE(x.size() == 2 + k + 1);
    CHECK(x.back() == Vec3{0, 0, 0});  // the axis's midpoint
    CHECK(tets.size() == size_t(2 * k));
    CHECK(std::all_of(regions.begin(), regions.end(), [](int32_t g) { return g == 3; }));
    CHECK(with_surface_corner(tets, faces) == 0);
    check_valid(x, tets, hull, faces);
    CHECK(volume(x, tets) == Approx(v0).epsilon(1e-14));
}

TEST_CASE("tet_split: a tetrahedron with all six edges on S gets its centroid", "[tetmesh][tet_split]") {
    std::vector<Vec3> x{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    std::vector<Tet> tets{{0, 1, 2, 3}};
    std::vector<int32_t> regions{1};
    const std::vector<Tri> faces = outer_faces(tets);
    const auto hull = hull_of(tets);
    const detail::TetSplitResult r = detail::split_surface_corners(x, tets, regions, faces);
    CHECK(r.found == 1);
    CHECK(r.edge_splits == 0);
    CHECK(r.centroid_splits == 1);
    CHECK(r.left == 0);
    CHECK(tets.size() == 4);
    CHECK(regions == std::vector<int32_t>(4, 1));
    CHECK(with_surface_corner(tets, faces) == 0);
    check_valid(x, tets, hull, faces);
}

TEST_CASE("tet_split: no level-0 tetrahedron of the femur has a surface corner, and refinement makes no tetrahedron "
          "with four corners on S",
          "[tetmesh][tet_split][real]") {
    // Femur at 10 %: TetGen, the flips and the insertions leave 167 tetrahedra with a corner
    // whose three edges are on S (95 with two faces on S); their red corner children, at
    // every level, have four corners on S, which phi flattens (deal.II level 3: 4.48 degrees).
    REQUIRE_TETGEN();
    const Parametrization* femur = test_support::simplified_femur();
    if (!femur) {
        WARN("femur.off missing: real-mesh case skipped");
        return;
    }
    TetMeshOptions with, without;
    without.split_surface_corners = false;
    TetMesh a, b;
    const TetMeshResult ra = generate_tetmesh(*femur, with, Context{}, a);
    const TetMeshResult rb = generate_tetmesh(*femur, without, Context{}, b);
    REQUIRE(find_tetmesh_inconsistency(a, femur->coarse).empty());
    CHECK(with_surface_corner(b.tetrahedra, b.faces) > 0);
    CHECK(with_surface_corner(a.tetrahedra, a.faces) == 0);
    CHECK(ra.surface_corner_splits > 0);
    CHECK(rb.surface_corner_splits == 0);
    CHECK(a.faces == b.faces);
    CHECK(a.face_patches == b.face_patches);
    check_valid(a.vertices, a.tetrahedra, hull_of(b.tetrahedra), a.faces);
    const TetMeshStats sa = tetmesh_stats(a), sb = tetmesh_stats(b);
    CHECK(sa.inverted == 0);
    CHECK(sa.region_volumes[0] == Approx(sb.region_volumes[0]).epsilon(1e-12));
    CHECK(sa.min_dihedral_degrees >= sb.min_dihedral_degrees);  // 10.6; 8.87 without the splits
    for (int32_t v = femur->coarse.num_vertices(); v < a.num_vertices(); ++v) {
        CHECK(a.vertex_coarse_vertex[v] == -1);
        CHECK(!a.vertex_parameter_points[v].valid());
    }
    // Two levels of red refinement through phi (as the solvers refine: no flips; those of
    // refine_tetmesh make 9 such tetrahedra at level 2 here): tetrahedra with four corners on
    // S only below tetrahedra with a surface corner (687 without the splits).
    TetRefineOptions ro;
    ro.levels = 2;
    ro.flip = false;
    TetMesh fa, fb;
    refine_tetmesh(*femur, a, ro, Context{}, fa);
    refine_tetmesh(*femur, b, ro, Context{}, fb);
    CHECK(all_corners_on_s(fb) > 0);
    CHECK(all_corners_on_s(fa) == 0);
}
