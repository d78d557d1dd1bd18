// The sheet guard (simplify/sheet_guard.h) on a junction edge whose replaced triangle has
// no area: its apex lies on the edge's line, so it stands between no two sheets, and the
// wedge test would accept a new apex anywhere (the nearest kept sheets "before" and
// "after" came out as one). Input that passed validate_surface has no such triangle; the
// guard refuses instead of trusting that.
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
