// The island guard (simplify/island_guard.h): a removal whose old and new triangles enclose
// a vertex of another component is refused, one that does not is let pass; with one
// component the guard is off. The removal here is the apex of a pyramid flattened onto its
// base (removed: the four sides; added: the base's two triangles), the island a small
// tetrahedron under the apex, a feature-line removal (two half-disks) with the island in
// one half-disk's swept volume, and two sheets whose swept volumes nest (their union's
// parity cancels: each sheet is tested alone).
#include <cmath>
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

namespace {

// The line a = 0, v = 1, b = 2 along x with v bent up by 0.4 in y, a half-disk (v, a,
// apex), (v, b, apex) per apex, and a small tetrahedron around `island` (its triangles
// start at its two vertices above the island's centre in z: the guard tests one of
// those); the removal of v replaces each half-disk by (a, b, apex). All of it turned by
// `turn` (radians) about the x axis at the end.
struct LineRemoval {
    Surface s;
    std::vector<Tri> added;
};

LineRemoval half_disks(const std::vector<Vec3>& apexes, const Vec3& island, double r, double turn = 0) {
    LineRemoval x;
    x.s.vertices = {{-1, 0, 0}, {0, 0.4, 0}, {1, 0, 0}};
    for (const Vec3& p : apexes) {
        const int32_t k = int32_t(x.s.vertices.size());
        x.s.vertices.push_back(p);
        x.s.triangles.push_back({0, 1, k});
        x.s.triangles.push_back({1, 2, k});
        x.added.push_back({0, 2, k});
    }
    const int32_t i = int32_t(x.s.vertices.size());
    // i and i + 3 above the island's centre in z, i + 1 and i + 2 below.
    for (const Vec3& d : {Vec3{r, r, r}, Vec3{r, -r, -r}, Vec3{-r, r, -r}, Vec3{-r, -r, r}})
        x.s.vertices.push_back({island[0] + d[0], island[1] + d[1], island[2] + d[2]});
    x.s.triangles.insert(x.s.triangles.end(),
                         {{i, i + 1, i + 2}, {i, i + 3, i + 1}, {i, i + 2, i + 3}, {i + 3, i + 2, i + 1}});
    const double c = std::cos(turn), s = std::sin(turn);
    for (Vec3& p : x.s.vertices) p = {p[0], c * p[1] - s * p[2], s * p[1] + c * p[2]};
    x.s.patches.assign(x.s.triangles.size(), 0);
    return x;
}

bool sweeps(const LineRemoval& x) {
    CoarseMesh mesh(x.s);
    const IslandGuard guard(mesh);
    REQUIRE(guard.components() == 2);
    const TriangleGrid grid = grid_of(mesh);
    IslandGuard::Scratch scratch;
    return guard.sweeps_island(mesh, grid, mesh.triangle_capacity(), 1, 0, 2, triangles_at(mesh, 1), x.added, scratch);
}

}  // namespace

TEST_CASE("island guard: a crease whose two half-disks both enclose the island sweeps nothing",
          "[internal][simplify][islands]") {
    // Both half-disks above the line (apexes at 59 and 73 degrees from v in the (y, z)
    // plane, 45 and 63 from the new line a -- b): the thin wedge between them moves, the
    // island lies in both closed half-disks' volumes but outside the thin wedge before
    // (at 108 degrees from v) and after (at 18 degrees from a -- b). Refused while both
    // odd parities refused; a point is swept exactly when the two parities differ.
    CHECK_FALSE(sweeps(half_disks({{0, 1, 1}, {0, 1, 2}}, {0, 0.36, 0.12}, 0.01)));
    // Between the two: in the thin wedge after, not before (only the volume of the apex
    // at (0, 1, 2) holds it).
    CHECK(sweeps(half_disks({{0, 1, 1}, {0, 1, 2}}, {0, 0.5, 0.75}, 0.01)));
}

TEST_CASE("island guard: an island through the closing triangle (a, v, b) decides by the sheets, not by that triangle",
          "[internal][simplify][islands]") {
    // The island crosses the triangle (a, v, b) that closes each half-disk's volume (no
    // part of the surface): the vertex tested lies above it, inside every half-disk's
    // volume. Three half-disks all above the line (59, 73, 96 degrees from v; 45, 63, 84
    // from a -- b): the island lies in the wedge from the last to the first before (at 180
    // degrees from v) and after (at 0 from a -- b): nothing is swept. Turned by 45 degrees
    // about x so that the box of the old triangles holds the island (untouched, the box
    // ends at the plane of (a, v, b), and the island is no candidate).
    const double turn = std::atan(1.0);
    CHECK_FALSE(sweeps(half_disks({{0, 1, 1}, {0, 1, 2}, {0, 0.2, 2}}, {0, 0.2, 0}, 0.05, turn)));
    // A flat crease (half-disks above and below, the wedge holding +y between them): the
    // same island moves from the outer wedge (180 degrees from v) into the inner one
    // (0 degrees from a -- b): swept.
    CHECK(sweeps(half_disks({{0, 1, 1}, {0, 1, -1}}, {0, 0.2, 0}, 0.05)));
    CHECK(sweeps(half_disks({{0, 1, 1}, {0, 1, -1}}, {0, 0.2, 0}, 0.05, turn)));
}
