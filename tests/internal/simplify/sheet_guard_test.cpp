// The sheet guard (simplify/sheet_guard.h) on a junction edge whose replaced triangle has
// no area: its apex lies on the edge's line, so it stands between no two sheets, and the
// wedge test would accept a new apex anywhere (the nearest kept sheets "before" and
// "after" came out as one). Input that passed validate_surface has no such triangle; the
// guard refuses instead of trusting that.
#include <array>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/surface.h"
#include "simplify/coarse_mesh.h"
#include "simplify/sheet_guard.h"

using namespace bpm;
using namespace bpm::detail;

TEST_CASE("sheet guard: a replaced triangle without area is refused, not waved through",
          "[internal][simplify][junctions]") {
    // Edge 0-1 along x with three sheets (apexes +y, +z, -y) and a fourth triangle whose
    // apex 5 lies on the edge's line.
    Surface s;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, 0, 1}, {0.5, -1, 0}, {2, 0, 0}, {0.5, 0, -1}};
    s.triangles = {{0, 1, 2}, {0, 1, 3}, {0, 1, 4}, {0, 1, 5}};
    s.patches = {0, 1, 2, 3};
    CoarseMesh mesh(s);
    mesh.mark_feature_edges(180.0);
    REQUIRE(mesh.is_feature_edge(0, 1));
    int32_t flat = -1;
    for (int32_t t = 0; t < mesh.triangle_capacity(); ++t)
        if (mesh.alive(t) && (mesh.triangle(t)[0] == 5 || mesh.triangle(t)[1] == 5 || mesh.triangle(t)[2] == 5)) flat = t;
    REQUIRE(flat >= 0);
    std::vector<int32_t> scratch;
    // Its replacement with apex -z (between the -y and +y sheets, past none of them in
    // truth: but the old place is undefined, so no order can be said to be kept).
    CHECK_FALSE(keeps_sheet_order(mesh, {flat}, {Tri{0, 1, 6}}, scratch));
    // A proper triangle (apex +y) replaced inside its wedge (between -y... and +z) passes.
    int32_t up = -1;
    for (int32_t t = 0; t < mesh.triangle_capacity(); ++t)
        if (mesh.alive(t) && (mesh.triangle(t)[0] == 2 || mesh.triangle(t)[1] == 2 || mesh.triangle(t)[2] == 2)) up = t;
    REQUIRE(up >= 0);
    CHECK(keeps_sheet_order(mesh, {up}, {Tri{0, 1, 2}}, scratch));
}

// Along a feature line of three or more sheets, a removal whose old order around a -- v
// (or v -- b) is not defined, or whose new triangle at a -- b cannot be found in a
// half-disk, was let pass unguarded (the old order was skipped; the sheets were left
// empty, which keeps_line_sheet_order took for "nothing to compare"). Both are refused now.
TEST_CASE("sheet guard: a junction-line removal without a defined old order is refused",
          "[internal][simplify][junctions]") {
    // a = 0, v = 1, b = 2 along x. At a -- v the apexes 3 and 4 lie on one half-plane (+y):
    // undefined. At v -- b and at a -- b the three sheets turn +y, +z, -z alike.
    const std::vector<Vec3> x = {{0, 0, 0},   {1, 0, 0},  {2, 0, 0},    {0.5, 1, 0},   {0.5, 2, 0},
                                 {0.5, 0, 1}, {1.5, 1, 0}, {1.5, 0, 1}, {1.5, 0, -1}, {1, 1, 0.1},
                                 {1, 0.1, 1}, {1, 0.1, -1}};
    // Sheets: apexes at a -- v, at v -- b, and of the new triangle at a -- b.
    const std::vector<std::array<int32_t, 3>> undefined = {{3, 6, 9}, {4, 7, 10}, {5, 8, 11}};
    CHECK_FALSE(keeps_line_sheet_order(x, 0, 1, 2, undefined));
    // With a defined old order (apex 5 at +z for the second sheet, -z for the third) it passes.
    std::vector<Vec3> y = x;
    y[4] = {0.5, 0, 1};
    y[5] = {0.5, 0, -1};
    CHECK(keeps_line_sheet_order(y, 0, 1, 2, undefined));
}

TEST_CASE("sheet guard: a junction-line plan whose half-disk has no new triangle at a -- b is refused",
          "[internal][simplify][junctions]") {
    // Three half-disks from a = 0 to b = 2 around v = 1; the second one's new triangles
    // (links 0, 4, 5, 2) are (0, 4, 5) and (4, 2, 5): none has both a and b.
    std::vector<Fan> fans(3);
    fans[0].link = {0, 3, 2};
    fans[1].link = {0, 4, 5, 2};
    fans[2].link = {2, 6, 0};
    for (Fan& f : fans) f.closed = false;
    const std::vector<Tri> added = {{0, 3, 2}, {0, 4, 5}, {4, 2, 5}, {2, 6, 0}};
    std::vector<std::array<int32_t, 3>> sheets;
    const std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, 1, 0}, {0.7, 0, 1}, {1.3, 0, 1}, {1, 0, -1}};
    // Before: the sheets came back empty and the order check passed.
    CHECK_FALSE((line_sheets_of(0, 2, fans, added, sheets) && keeps_line_sheet_order(x, 0, 1, 2, sheets)));
    // The expected layout gives one entry per half-disk.
    const std::vector<Tri> proper = {{0, 3, 2}, {0, 4, 5}, {0, 5, 2}, {2, 6, 0}};
    REQUIRE(line_sheets_of(0, 2, fans, proper, sheets));
    CHECK(sheets.size() == 3);
    CHECK(sheets[1] == std::array<int32_t, 3>{4, 5, 5});
}
