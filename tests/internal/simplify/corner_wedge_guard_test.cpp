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

namespace {
// The star of v = 5 (patch 1) over a link 0 1 2 3 4 that folds back over itself: 0 1 2
// flat at z = 0, 3 high above it, and 4 back down over 0 1 2, `fold` degrees above its
// plane seen from 0; v = (0.8, 0.8, v_height). Removing v makes the fan 0 1 2, 0 2 3,
// 0 3 4, whose first and last triangles meet only at 0, 0 3 4 lying `fold` degrees over
// 0 1 2. A lid 1 6 7 (patch 0) over 0 1 2 at its corner 1, `lid` degrees above its plane.
Surface folded_star(double fold, double v_height, double lid) {
    const auto slope = [](double degrees) { return std::tan(degrees * M_PI / 180); };
    const auto at = [](double degrees) { return Vec3{std::cos(degrees * M_PI / 180), std::sin(degrees * M_PI / 180), 0}; };
    Surface s;
    s.vertices = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {1, 1, 2}, {2, 0.6, std::hypot(2, 0.6) * slope(fold)},
                  {0.8, 0.8, v_height},
                  Vec3{2, 0, slope(lid)} + at(150), Vec3{2, 0, slope(lid)} + at(165)};
    s.triangles = {{5, 0, 1}, {5, 1, 2}, {5, 2, 3}, {5, 3, 4}, {5, 4, 0}, {1, 6, 7}};
    s.patches = {1, 1, 1, 1, 1, 0};
    return s;
}
// What removing v makes (0 3 4 last: it is not the neighbour of 0 1 2 in the list).
const std::vector<Tri> kFoldedFan = {Tri{0, 1, 2}, Tri{0, 2, 3}, Tri{0, 3, 4}};
}  // namespace

TEST_CASE("corner wedge guard: two new triangles laid onto each other at their common corner are refused",
          "[internal][simplify]") {
    // The pairs among the new triangles count, not only new against old: the fan's 0 3 4
    // folds back over its 0 1 2. With v 0.07 above 0 1 2 the old star's own corner wedges
    // are 4.7 degrees or more, the lid stands 45 degrees off, and the new fan comes within
    // 2.3 (2.8 for the wider fold) degrees of old triangles at common corners, which do not
    // count (they go), so the floor decides: 0.25 degrees under it refused, 0.25 over it
    // passes.
    const double floor = kCornerWedgeFloorDegrees;
    const Surface thin = folded_star(floor - 0.25, 0.07, 45);
    REQUIRE(corner_wedge_degrees(thin.vertices, {0, 1, 2}, {0, 3, 4}) == Approx(floor - 0.25));
    CoarseMesh thin_mesh(thin);
    CHECK_FALSE(keeps_corner_wedges(thin_mesh, star_of_5(thin_mesh), kFoldedFan));
    const Surface wider = folded_star(floor + 0.25, 0.07, 45);
    REQUIRE(corner_wedge_degrees(wider.vertices, {0, 1, 2}, {0, 3, 4}) == Approx(floor + 0.25));
    CoarseMesh wider_mesh(wider);
    CHECK(keeps_corner_wedges(wider_mesh, star_of_5(wider_mesh), kFoldedFan));
}

TEST_CASE("corner wedge guard: a thin pair of two old triangles lowers the floor", "[internal][simplify]") {
    // v 3 below 0 1 2: its triangles 5 1 2 and 5 3 4 meet only at v, 2.15 degrees apart,
    // the old star's thinnest pair (against the lid: 15 degrees or more). The fan folds 20
    // degrees; its 0 1 2 lies under the lid at corner 1: the lid 0.05 degrees lower than
    // that old pair is refused, 0.05 higher passes, although both are under the floor.
    const double before = corner_wedge_degrees(folded_star(20, -3, 45).vertices, {5, 1, 2}, {5, 3, 4});
    REQUIRE(before == Approx(2.15).margin(0.01));
    const Surface lower = folded_star(20, -3, before - 0.05);
    REQUIRE(corner_wedge_degrees(lower.vertices, {0, 1, 2}, {1, 6, 7}) == Approx(before - 0.05));
    CoarseMesh lower_mesh(lower);
    CHECK_FALSE(keeps_corner_wedges(lower_mesh, star_of_5(lower_mesh), kFoldedFan));
    const Surface higher = folded_star(20, -3, before + 0.05);
    REQUIRE(corner_wedge_degrees(higher.vertices, {0, 1, 2}, {1, 6, 7}) == Approx(before + 0.05));
    CoarseMesh higher_mesh(higher);
    CHECK(keeps_corner_wedges(higher_mesh, star_of_5(higher_mesh), kFoldedFan));
}

TEST_CASE("corner wedge guard: off on a surface of one patch", "[internal][simplify]") {
    Surface s = star_over_triangle(0.02, 1.0);
    s.patches = {0, 0, 0, 0};
    CoarseMesh mesh(s);
    CHECK(keeps_corner_wedges(mesh, star_of_5(mesh), {Tri{0, 3, 4}}));
}
