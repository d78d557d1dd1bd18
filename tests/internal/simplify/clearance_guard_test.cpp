// The clearance guard (simplify/clearance_guard.h): a new triangle may not hover just above
// another sheet (noisy 48^3 at --ratio 0.2: a new coarse edge 2.8e-6 from another, and
// bpm-mesh's smallest dihedral angle 4.4e-6 degrees); the exact intersection test lets any
// positive gap pass.
#include <cmath>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/surface.h"
#include "core/triangle_grid.h"
#include "simplify/clearance_guard.h"
#include "simplify/coarse_mesh.h"

using namespace bpm;
using namespace bpm::detail;

TEST_CASE("clearance guard: relative clearance of two triangles", "[internal][simplify]") {
    const std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0},            // a flat triangle
                                 {0.2, 0.2, 1e-4}, {1.2, 0.2, 1e-4}, {0.2, 1.2, 1e-4},  // one 1e-4 above it
                                 {0.2, 0.2, 0.5}, {1, 1, 0}, {-1, -1, 0.2}};
    CHECK(relative_clearance(x, {0, 1, 2}, {3, 4, 5}) == Approx(1e-4 / std::sqrt(2.0)));
    CHECK(relative_clearance(x, {0, 1, 2}, {6, 3, 4}) == Approx(1e-4 / std::sqrt(2.0)));  // an edge near it
    // One common vertex: the edges opposite it count, not the vertex itself ...
    CHECK(relative_clearance(x, {0, 1, 2}, {0, 6, 8}) > 0.05);
    // ... and an edge from it lying almost in the other triangle's plane, across its
    // opposite edge, is a thin fold (z 1e-4 at x + y = 1.4: 7e-5 above edge 1-2).
    CHECK(relative_clearance(x, {0, 1, 2}, {0, 6, 4}) < 1e-4);
    // A common edge: the wedge guard's business.
    CHECK(relative_clearance(x, {0, 1, 2}, {1, 7, 2}) == std::numeric_limits<double>::infinity());
}

namespace {
// A mesh of `s` with every triangle in a grid of unit cells. The scene keeps its own copy
// of `s`: the mesh reads its positions from there.
struct Scene {
    explicit Scene(Surface s) : surface(std::move(s)), mesh(surface), grid(1.0) {
        mesh.alive_triangles(alive);
        for (int32_t t : alive) {
            const Tri& c = mesh.triangle(t);
            grid.insert(t, surface.vertices[c[0]], surface.vertices[c[1]], surface.vertices[c[2]]);
        }
    }
    // Not copied or moved: a copy's mesh would read the other scene's positions.
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;
    Surface surface;
    CoarseMesh mesh;
    TriangleGrid grid;
    std::vector<int32_t> alive;
};

// Two separate sheets: A, a triangle at z = 0 (patch 0, longest edge 4 sqrt 2), and B, a
// pair at z = 0.5 (patch 1) to be replaced by triangles 3 4 7 and 3 7 5 with a corner
// 7 = (1, 1, corner_height) pulled down towards A (or by 3 4 5, kept at 0.5).
Surface sheet_over_sheet(double corner_height) {
    Surface s;
    s.vertices = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0},                     // sheet A
                  {0, 0, 0.5}, {2, 0, 0.5}, {0, 2, 0.5}, {1, 1, 0.5},  // sheet B
                  {1, 1, corner_height}};                              // 7
    s.triangles = {{0, 1, 2}, {3, 4, 6}, {3, 6, 5}};
    s.patches = {0, 1, 1};
    return s;
}
// Sheet B's triangles.
std::vector<int32_t> sheet_b(const Scene& scene) { return {scene.alive.begin() + 1, scene.alive.end()}; }
}  // namespace

TEST_CASE("clearance guard: a new triangle hovering over another sheet is refused", "[internal][simplify]") {
    // Corner 7 1e-5 above A.
    Scene scene(sheet_over_sheet(1e-5));
    const std::vector<int32_t> removed = sheet_b(scene);
    std::vector<TriangleGrid::Entry> scratch;
    CHECK(keeps_clearance(scene.mesh, scene.grid, removed, {Tri{3, 4, 5}}, {}, 4.0, scratch));  // 0.5 above A
    CHECK_FALSE(keeps_clearance(scene.mesh, scene.grid, removed, {Tri{3, 4, 7}, Tri{3, 7, 5}}, {}, 4.0, scratch));
    CHECK(keeps_clearance(scene.mesh, scene.grid, removed, {Tri{3, 4, 7}, Tri{3, 7, 5}}, {}, 4.0, scratch, 0.0));  // off
}

TEST_CASE("clearance guard: on two or more patches a vertex 0.7 % above another sheet is refused", "[internal][simplify]") {
    // Noisy 48^3 at --ratio 0.2 with the corner-wedge guard: bpm-mesh's smallest angle
    // (1.36 degrees) on a triangle with a corner of another sheet 0.7 % of its longest
    // edge above it, which the floor of one patch (0.1 %) lets pass.
    Scene scene(sheet_over_sheet(0.04));  // 0.71 % above A
    const std::vector<int32_t> removed = sheet_b(scene);
    const std::vector<Tri> added = {Tri{3, 4, 7}, Tri{3, 7, 5}};
    std::vector<TriangleGrid::Entry> scratch;
    CHECK(keeps_clearance(scene.mesh, scene.grid, removed, added, {}, 6.0, scratch, kClearanceFloor));
    CHECK_FALSE(keeps_clearance(scene.mesh, scene.grid, removed, added, {}, 6.0, scratch, kMultiPatchClearanceFloor));
}

TEST_CASE("clearance guard: two new triangles of one removal may not hover over each other", "[internal][simplify]") {
    // A removal along a junction line makes a fan per sheet; two fans' triangles share at
    // most a corner, and the intersection test lets any gap between them pass. Old: two
    // triangles at v = 0 far apart; new: a flat triangle and one whose far edge runs
    // 1e-5 above it (relative 2.5e-6).
    Surface s;
    s.vertices = {{0, 0, 0},   {4, 0, 0},   {0, 4, 0},                    // 0 1 2: flat
                  {1, 1, 1e-5}, {2, 1, 1e-5},                             // 3 4: just above
                  {0, 0, 3},   {1, 0, 3},   {0, 0, -3}, {1, 0, -3}};      // 5 6 7 8: the old sheets
    s.triangles = {{0, 5, 6}, {0, 7, 8}};
    s.patches = {0, 1};
    Scene scene(s);
    std::vector<TriangleGrid::Entry> scratch;
    const std::vector<int32_t> removed = scene.alive;
    CHECK_FALSE(keeps_clearance(scene.mesh, scene.grid, removed, {Tri{0, 1, 2}, Tri{0, 3, 4}}, {}, 5.0, scratch));
    // Lifted to 0.5 the pair is clear.
    s.vertices[3][2] = s.vertices[4][2] = 0.5;
    Scene clear(s);
    CHECK(keeps_clearance(clear.mesh, clear.grid, removed, {Tri{0, 1, 2}, Tri{0, 3, 4}}, {}, 5.0, scratch));
}

TEST_CASE("clearance guard: the star's old contacts count where the new triangles do not reach", "[internal][simplify]") {
    // A peak v = 0 at height 10 over the square 1 2 3 4, its tip 0.004 below a small
    // triangle O (relative 4e-4: closer than the floor already); removing v puts the new
    // square 0.002 above a small triangle P (relative 7e-4). The removal makes nothing
    // closer than the star was (7e-4 >= 4e-4), so it passes, although O lies far beyond
    // the new triangles.
    Surface s;
    s.vertices = {{0, 0, 10},                                              // 0: v
                  {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0},          // 1-4: the link
                  {-0.1, -0.1, 10.004}, {0.1, -0.1, 10.004}, {0, 0.1, 10.004},  // 5-7: O
                  {-0.1, -0.1, -0.002}, {0.1, -0.1, -0.002}, {0, 0.1, -0.002}};  // 8-10: P
    s.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}, {5, 6, 7}, {8, 10, 9}};
    s.patches = {0, 0, 0, 0, 1, 2};
    Scene scene(s);
    std::vector<int32_t> removed;
    for (int32_t t : scene.alive)
        if (scene.mesh.triangle(t)[0] == 0 || scene.mesh.triangle(t)[1] == 0 || scene.mesh.triangle(t)[2] == 0)
            removed.push_back(t);
    REQUIRE(removed.size() == 4);
    std::vector<TriangleGrid::Entry> scratch;
    CHECK(keeps_clearance(scene.mesh, scene.grid, removed, {Tri{1, 2, 3}, Tri{1, 3, 4}}, {}, 11.0, scratch));
    // Without O the star was clear, and the removal is refused.
    s.vertices[5][2] = s.vertices[6][2] = s.vertices[7][2] = 12;
    Scene far(s);
    CHECK_FALSE(keeps_clearance(far.mesh, far.grid, removed, {Tri{1, 2, 3}, Tri{1, 3, 4}}, {}, 11.0, scratch));
}

TEST_CASE("clearance guard: its filters keep the exact decision at any floor", "[internal][simplify]") {
    // keeps_clearance measures only the pairs (and parts of pairs) that its box and
    // separating-axis bounds do not put beyond the floor: at a floor just above the exact
    // smallest relative clearance it must refuse, at that clearance itself accept (bit
    // for bit: the outputs may not change). Random triangles near a new one, with and
    // without a common corner, some thin.
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int refused = 0, thin = 0;
    for (int scene = 0; scene < 400; ++scene) {
        Surface s;
        const auto point = [&](double spread) {
            return Vec3{spread * unit(random), spread * unit(random), spread * unit(random)};
        };
        for (int i = 0; i < 3; ++i) s.vertices.push_back(point(1.0));  // the new triangle: 0 1 2
        const bool flat = scene % 4 == 0;  // all in one plane (the new triangle's fans are often flat)
        if (flat)
            for (Vec3& p : s.vertices) p[2] = 0.5;
        for (int t = 0; t < 6; ++t) {
            const int32_t base = int32_t(s.vertices.size());
            Vec3 c = point(1.4);
            for (int i = 0; i < 3; ++i) {
                Vec3 p = c + Vec3{0.6 * unit(random) - 0.3, 0.6 * unit(random) - 0.3, 0.6 * unit(random) - 0.3};
                if (flat) p[2] = 0.5;
                s.vertices.push_back(p);
            }
            if (t == 5) {  // a sliver: its third corner on the first edge, lifted by 1e-6
                Vec3& p = s.vertices[size_t(base + 2)];
                p = 0.5 * (s.vertices[size_t(base)] + s.vertices[size_t(base + 1)]);
                p[2] += 1e-6;
                ++thin;
            }
            Tri tri{base, base + 1, base + 2};
            if (t % 3 == 1) tri[0] = int32_t(t % 2 == 0 ? 0 : 1);  // a common corner with the new triangle
            s.triangles.push_back(tri);
            s.patches.push_back(1);
        }
        CoarseMesh mesh(s);
        TriangleGrid grid(0.5);
        std::vector<int32_t> alive;
        mesh.alive_triangles(alive);
        double longest = 0;
        for (int32_t t : alive) {
            const Tri& c = mesh.triangle(t);
            grid.insert(t, s.vertices[c[0]], s.vertices[c[1]], s.vertices[c[2]]);
            for (int i = 0; i < 3; ++i) longest = std::max(longest, distance(s.vertices[c[i]], s.vertices[c[(i + 1) % 3]]));
        }
        const Tri added{0, 1, 2};
        double smallest = std::numeric_limits<double>::infinity();
        for (int32_t t : alive) smallest = std::min(smallest, relative_clearance(s.vertices, added, mesh.triangle(t)));
        if (!(smallest > 0) || !std::isfinite(smallest)) continue;
        std::vector<TriangleGrid::Entry> scratch;
        CHECK(keeps_clearance(mesh, grid, {}, {added}, {}, longest, scratch, smallest));
        CHECK_FALSE(keeps_clearance(mesh, grid, {}, {added}, {}, longest, scratch,
                                    std::nextafter(smallest, std::numeric_limits<double>::infinity())));
        ++refused;
    }
    CHECK(refused > 300);
    CHECK(thin > 0);
}
