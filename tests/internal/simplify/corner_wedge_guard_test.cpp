// The corner-wedge guard (simplify/corner_wedge_guard.h): a new triangle may not lie onto
// another one at their common corner (noisy 48^3 at --ratio 0.2: 0.29 degrees apart, past
// the clearance floor, and bpm-mesh's smallest dihedral angle 0.34 degrees).
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/surface.h"
#include "simplify/coarse_mesh.h"
#include "simplify/corner_wedge_guard.h"

using namespace bpm;
using namespace bpm::detail;

TEST_CASE("corner wedge guard: the angle of two triangles at their common corner", "[internal][simplify]") {
    const double h = 0.02;
    const std::vector<Vec3> x = {{0, 0, 0},  {2, 0, 0},  {0, 2, 0},     // 0 1 2: flat, sector x, y >= 0
                                 {3, -1, h}, {-1, 3, h},                // 3 4: a sector over it, z = h (x + y) / 2
                                 {0, -2, 0}, {-2, 0, 0},                // 5 6: the flat fan's far side
                                 {1, 1, 1}, {2, -1, 0}};
    // 0 - 1 lies in the plane of (0, 3, 4) but h below it: angle atan(h / 2) ...
    CHECK(corner_wedge_degrees(x, {0, 1, 2}, {0, 3, 4}) == Approx(std::atan(h / 2) * 180 / M_PI).epsilon(1e-3));
    CHECK(corner_wedge_degrees(x, {0, 3, 4}, {0, 1, 2}) == Approx(corner_wedge_degrees(x, {0, 1, 2}, {0, 3, 4})));
    // ... two triangles of a flat fan that are not neighbours: none ...
    CHECK(corner_wedge_degrees(x, {0, 1, 2}, {0, 5, 6}) == 90.0);
    // ... a steep one over the sector: its angle ...
    CHECK(corner_wedge_degrees(x, {0, 1, 2}, {0, 7, 8}) > 10.0);
    // ... a common edge or none: not a corner wedge.
    CHECK(corner_wedge_degrees(x, {0, 1, 2}, {1, 2, 7}) == 90.0);
    CHECK(corner_wedge_degrees(x, {0, 1, 2}, {3, 4, 7}) == 90.0);
}

namespace {
// A flat triangle 0 1 2 (patch 0) and the star of v = 5 over it (patch 1), whose link
// 0 3 4 becomes the new triangle (0, 3, 4) at z = h (x + y) / 2; v at height `v_height`.
Surface star_over_triangle(double h, double v_height) {
    Surface s;
    s.vertices = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {3, -1, h}, {-1, 3, h}, {0.6, 0.6, v_height}};
    s.triangles = {{0, 1, 2}, {0, 3, 5}, {3, 4, 5}, {4, 0, 5}};
    s.patches = {0, 1, 1, 1};
    return s;
}
std::vector<int32_t> star_of_5(const CoarseMesh& mesh) {
    std::vector<int32_t> alive, star;
    mesh.alive_triangles(alive);
    for (int32_t t : alive)
        for (int32_t c : mesh.triangle(t))
            if (c == 5) star.push_back(t);
    return star;
}
}  // namespace

TEST_CASE("corner wedge guard: a new triangle laid onto another at their common corner is refused", "[internal][simplify]") {
    // The old star stands 1 above the flat triangle: its corner wedges with it are wide.
    // The new triangle lies 0.57 degrees over it (h = 0.02; its far edge 0.4 % of the size
    // away: the clearance floor lets it pass).
    const Surface s = star_over_triangle(0.02, 1.0);
    CoarseMesh mesh(s);
    const std::vector<int32_t> removed = star_of_5(mesh);
    REQUIRE(removed.size() == 3);
    CHECK_FALSE(keeps_corner_wedges(mesh, removed, {Tri{0, 3, 4}}));
    CHECK(keeps_corner_wedges(mesh, removed, {Tri{0, 3, 4}}, 0.0));  // off (--min-ridge-angle 0)
    // At h = 0.5 it stands 14 degrees off: passes.
    const Surface wide = star_over_triangle(0.5, 1.0);
    CoarseMesh wide_mesh(wide);
    CHECK(keeps_corner_wedges(wide_mesh, star_of_5(wide_mesh), {Tri{0, 3, 4}}));
}

TEST_CASE("corner wedge guard: a star that was that thin already may stay so", "[internal][simplify]") {
    // v 0.005 above the flat triangle (its edge 0 - 5 0.34 degrees from it): the new
    // triangle at 0.57 degrees is no thinner than that.
    const Surface s = star_over_triangle(0.02, 0.005);
    CoarseMesh mesh(s);
    CHECK(keeps_corner_wedges(mesh, star_of_5(mesh), {Tri{0, 3, 4}}));
}

TEST_CASE("corner wedge guard: off on a surface of one patch", "[internal][simplify]") {
    Surface s = star_over_triangle(0.02, 1.0);
    s.patches = {0, 0, 0, 0};
    CoarseMesh mesh(s);
    CHECK(keeps_corner_wedges(mesh, star_of_5(mesh), {Tri{0, 3, 4}}));
}
