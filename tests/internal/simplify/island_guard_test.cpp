// The island guard (simplify/island_guard.h): a removal whose old and new triangles enclose
// a vertex of another component is refused, one that does not is let pass; with one
// component the guard is off. The removal here is the apex of a pyramid flattened onto its
// base (removed: the four sides; added: the base's two triangles), the island a small
// tetrahedron under the apex, a feature-line removal (two half-disks) with the island in
// one half-disk's swept volume, and two sheets whose swept volumes nest (their union's
// parity cancels: each sheet is tested alone).
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/surface.h"
#include "core/triangle_grid.h"
#include "simplify/coarse_mesh.h"
#include "simplify/island_guard.h"

using namespace bpm;
using namespace bpm::detail;

namespace {

// Pyramid: base square (0..3) at z = 0, apex 4 at height 1 (only the sides are triangles:
// an open surface, which the guard does not need closed), and a tetrahedron (5..8)
// around `island`.
Surface pyramid_and_tetrahedron(const Vec3& island) {
    Surface s;
    s.vertices = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {0, 0, 1}};
    const double r = 0.05;
    for (const Vec3& d : {Vec3{r, r, r}, Vec3{r, -r, -r}, Vec3{-r, r, -r}, Vec3{-r, -r, r}})
        s.vertices.push_back({island[0] + d[0], island[1] + d[1], island[2] + d[2]});
    s.triangles = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}, {5, 6, 7}, {5, 8, 6}, {5, 7, 8}, {6, 8, 7}};
    s.patches.assign(s.triangles.size(), 0);
    return s;
}

TriangleGrid grid_of(const CoarseMesh& mesh) {
    TriangleGrid grid(0.5, TriangleGrid::Frame::of_box({-10, -10, -10}, {10, 10, 10}));
    const auto& x = mesh.positions();
    for (int32_t t = 0; t < mesh.triangle_capacity(); ++t)
        if (mesh.alive(t)) grid.insert(t, x[mesh.triangle(t)[0]], x[mesh.triangle(t)[1]], x[mesh.triangle(t)[2]]);
    return grid;
}

std::vector<int32_t> triangles_at(const CoarseMesh& mesh, int32_t v) {
    std::vector<int32_t> out;
    for (int32_t t = 0; t < mesh.triangle_capacity(); ++t)
        if (mesh.alive(t) && (mesh.triangle(t)[0] == v || mesh.triangle(t)[1] == v || mesh.triangle(t)[2] == v))
            out.push_back(t);
    return out;
}

}  // namespace

TEST_CASE("island guard: flattening a pyramid over an island is refused, elsewhere it passes",
          "[internal][simplify][islands]") {
    const std::vector<Tri> base = {{0, 1, 2}, {0, 2, 3}};
    IslandGuard::Scratch scratch;
    {
        const Surface s = pyramid_and_tetrahedron({0.1, 0.1, 0.3});  // under the apex
        CoarseMesh mesh(s);
        const IslandGuard guard(mesh);
        REQUIRE(guard.active());
        CHECK(guard.components() == 2);
        const TriangleGrid grid = grid_of(mesh);
        CHECK(guard.sweeps_island(mesh, grid, mesh.triangle_capacity(), 4, -1, -1, triangles_at(mesh, 4), base, scratch));
        // The same found among the triangles the grid does not index yet.
        const TriangleGrid empty(0.5, TriangleGrid::Frame::of_box({-10, -10, -10}, {10, 10, 10}));
        CHECK(guard.sweeps_island(mesh, empty, 0, 4, -1, -1, triangles_at(mesh, 4), base, scratch));
    }
    for (const Vec3& outside : {Vec3{0.1, 0.1, -0.3}, Vec3{0.8, 0.8, 0.5}, Vec3{3, 0, 0.3}}) {
        const Surface s = pyramid_and_tetrahedron(outside);  // below the base, beside a side, far
        CoarseMesh mesh(s);
        const IslandGuard guard(mesh);
        const TriangleGrid grid = grid_of(mesh);
        CHECK_FALSE(guard.sweeps_island(mesh, grid, mesh.triangle_capacity(), 4, -1, -1, triangles_at(mesh, 4), base,
                                        scratch));
    }
    {
        // One component: off.
        Surface s = pyramid_and_tetrahedron({0.1, 0.1, 0.3});
        s.triangles.resize(4);
        s.patches.resize(4);
        CoarseMesh mesh(s);
        const IslandGuard guard(mesh);
        CHECK_FALSE(guard.active());
    }
}

TEST_CASE("island guard: along a feature line each half-disk is a closed surface of its own",
          "[internal][simplify][islands]") {
    // The line a = 0, v = 1, b = 2 along x; half-disk 1 above (apex 3 lifted in +z), half-disk
    // 2 below (apex 4); the removal of v replaces each by the triangle (a, b, apex). Each
    // half-disk's swept volume is the flat tetrahedron a, v, b, apex (closed by (a, v, b)).
    // The line is bent at v (v above the line a -- b by 0.4) so that the volumes are not flat.
    Surface s;
    s.vertices = {{-1, 0, 0}, {0, 0.4, 0}, {1, 0, 0}, {0, 1, 1}, {0, 1, -1}};
    s.triangles = {{0, 1, 3}, {1, 2, 3}, {1, 0, 4}, {2, 1, 4}};
    const size_t island = s.vertices.size();
    const double r = 0.02;
    // Inside the half-disk above: near the centroid of a, v, b, apex 3.
    const Vec3 c{0, 0.35, 0.25};
    for (const Vec3& d : {Vec3{r, r, r}, Vec3{r, -r, -r}, Vec3{-r, r, -r}, Vec3{-r, -r, r}})
        s.vertices.push_back({c[0] + d[0], c[1] + d[1], c[2] + d[2]});
    const int32_t i = int32_t(island);
    s.triangles.insert(s.triangles.end(), {{i, i + 1, i + 2}, {i, i + 3, i + 1}, {i, i + 2, i + 3}, {i + 1, i + 3, i + 2}});
    s.patches.assign(s.triangles.size(), 0);
    CoarseMesh mesh(s);
    const IslandGuard guard(mesh);
    const TriangleGrid grid = grid_of(mesh);
    IslandGuard::Scratch scratch;
    const std::vector<Tri> added = {{0, 2, 3}, {2, 0, 4}};
    CHECK(guard.sweeps_island(mesh, grid, mesh.triangle_capacity(), 1, 0, 2, triangles_at(mesh, 1), added, scratch));
    // Without the line (all triangles one surface) the parity would see the same here; the
    // next case is the one the grouping is for.
}

TEST_CASE("island guard: nested swept volumes of two sheets do not cancel", "[internal][simplify][islands]") {
    // Two half-disks on the same side of the line a = 0, v = 1, b = 2 (v bent up by 0.4 in
    // y): sheet 1 with apex 3 at (0, 1, 1), sheet 2 with apex 4 at (0, 1, 2). The island
    // lies in both swept volumes (each the tetrahedron a, v, b, apex: the one of apex 3 lies
    // inside the one of apex 4 near the line): the union's parity is even, each sheet's odd.
    Surface s;
    s.vertices = {{-1, 0, 0}, {0, 0.4, 0}, {1, 0, 0}, {0, 1, 1}, {0, 1, 2}, {0, 1, -1}};
    s.triangles = {{0, 1, 3}, {1, 2, 3}, {0, 1, 4}, {1, 2, 4}, {1, 0, 5}, {2, 1, 5}};
    const int32_t i = int32_t(s.vertices.size());
    const double r = 0.01;
    const Vec3 c{0, 0.36, 0.12};  // close to the line a -- v -- b, inside both tetrahedra
    for (const Vec3& d : {Vec3{r, r, r}, Vec3{r, -r, -r}, Vec3{-r, r, -r}, Vec3{-r, -r, r}})
        s.vertices.push_back({c[0] + d[0], c[1] + d[1], c[2] + d[2]});
    s.triangles.insert(s.triangles.end(), {{i, i + 1, i + 2}, {i, i + 3, i + 1}, {i, i + 2, i + 3}, {i + 1, i + 3, i + 2}});
    s.patches.assign(s.triangles.size(), 0);
    CoarseMesh mesh(s);
    const IslandGuard guard(mesh);
    const TriangleGrid grid = grid_of(mesh);
    IslandGuard::Scratch scratch;
    const std::vector<Tri> added = {{0, 2, 3}, {0, 2, 4}, {2, 0, 5}};
    CHECK(guard.sweeps_island(mesh, grid, mesh.triangle_capacity(), 1, 0, 2, triangles_at(mesh, 1), added, scratch));
}
