// The wedge guard (simplify/wedge_guard.h) on a junction edge of three sheets: a new
// triangle may not fold onto a neighbouring sheet (noisy label images had junction wedges
// of 1e-13 degrees, and bpm-mesh the same smallest dihedral angle), a wedge already
// thinner than the floor may stay or widen, a crease of two triangles has its own floor,
// and a removal along a feature line a -- v -- b compares the new edge a -- b with the
// thinner of the wedges at a -- v and v -- b, which it replaces.
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/surface.h"
#include "simplify/coarse_mesh.h"
#include "simplify/wedge_guard.h"

using namespace bpm;
using namespace bpm::detail;

namespace {
// The point at `degrees` around the x axis from +y, at distance 1 from it, above x = 0.5.
Vec3 around_x(double degrees) {
    const double r = degrees * M_PI / 180;
    return {0.5, std::cos(r), std::sin(r)};
}
int32_t triangle_with(const CoarseMesh& mesh, int32_t v) {
    for (int32_t t = 0; t < mesh.triangle_capacity(); ++t)
        if (mesh.alive(t) && (mesh.triangle(t)[0] == v || mesh.triangle(t)[1] == v || mesh.triangle(t)[2] == v))
            return t;
    return -1;
}
}  // namespace

TEST_CASE("wedge guard: smallest wedge around an edge", "[internal][simplify][junctions]") {
    const Vec3 a{0, 0, 0}, b{1, 0, 0};
    CHECK(smallest_wedge_degrees(a, b, {around_x(0)}) == 360.0);
    CHECK(smallest_wedge_degrees(a, b, {around_x(0), around_x(90), around_x(200)}) == Approx(90.0));
    CHECK(smallest_wedge_degrees(a, b, {around_x(10), around_x(350)}) == Approx(20.0));
    CHECK(smallest_wedge_degrees(b, a, {around_x(10), around_x(350)}) == Approx(20.0));  // either direction
    CHECK(smallest_wedge_degrees(a, b, {around_x(30), around_x(30.5), around_x(180)}) == Approx(0.5));
}

TEST_CASE("wedge guard: a new sheet may not fold onto its neighbour at a junction edge",
          "[internal][simplify][junctions]") {
    // Edge 0-1 along x with three sheets at 0, 120 and 240 degrees (apexes 2, 3, 4), and
    // apexes to replace sheet 2 with: 5 at 119.5 degrees (0.5 from sheet 3), 6 at 60, and
    // 7 at 242 (2 degrees past sheet 4: inside the wedge of 3 and 4, order kept).
    Surface s;
    s.vertices = {{0, 0, 0},      {1, 0, 0},     around_x(0),  around_x(120),
                  around_x(240), around_x(119.5), around_x(60), around_x(238)};
    s.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    s.patches = {0, 1, 2};
    CoarseMesh mesh(s);
    mesh.mark_feature_edges(180.0);
    REQUIRE(mesh.is_feature_edge(0, 1));
    const int32_t sheet = triangle_with(mesh, 2);
    REQUIRE(sheet >= 0);
    WedgeScratch scratch;
    CHECK(keeps_feature_wedges(mesh, {sheet}, {Tri{0, 1, 6}}, -1, -1, -1, scratch));   // 60 degrees wide
    CHECK_FALSE(keeps_feature_wedges(mesh, {sheet}, {Tri{0, 1, 5}}, -1, -1, -1, scratch));  // 0.5
    CHECK(keeps_feature_wedges(mesh, {sheet}, {Tri{0, 1, 5}}, -1, -1, -1, scratch, 0.0, 0.0));  // guard off
}

TEST_CASE("wedge guard: a wedge thinner than the floor may stay or widen, not get thinner",
          "[internal][simplify][junctions]") {
    // Sheets at 0, 120 and 240 + 3 degrees apart from a fourth at 243: a 3-degree wedge.
    Surface s;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, around_x(0), around_x(120), around_x(240), around_x(243),
                  around_x(244), around_x(241.5), around_x(60)};
    s.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {1, 0, 5}};
    s.patches = {0, 1, 2, 3};
    CoarseMesh mesh(s);
    mesh.mark_feature_edges(180.0);
    const int32_t thin = triangle_with(mesh, 5), other = triangle_with(mesh, 2);
    REQUIRE(thin >= 0);
    WedgeScratch scratch;
    CHECK(keeps_feature_wedges(mesh, {thin}, {Tri{1, 0, 6}}, -1, -1, -1, scratch));        // 3 -> 4 degrees
    CHECK_FALSE(keeps_feature_wedges(mesh, {thin}, {Tri{1, 0, 7}}, -1, -1, -1, scratch));  // 3 -> 1.5
    // Changing another sheet leaves the 3-degree wedge as it was: not refused for it.
    CHECK(keeps_feature_wedges(mesh, {other}, {Tri{0, 1, 8}}, -1, -1, -1, scratch));
}

TEST_CASE("wedge guard: a crease of two triangles has the lower floor", "[internal][simplify]") {
    // A fold along 0-1: sheets at 0 and 90 degrees, a crease (feature edge at 60 degrees).
    Surface s;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, around_x(0), around_x(90), around_x(6), around_x(3)};
    s.triangles = {{0, 1, 2}, {1, 0, 3}};
    s.patches = {0, 0};
    CoarseMesh mesh(s);
    mesh.mark_feature_edges(60.0);
    REQUIRE(mesh.is_feature_edge(0, 1));
    const int32_t t = triangle_with(mesh, 3);
    REQUIRE(t >= 0);
    WedgeScratch scratch;
    CHECK(keeps_feature_wedges(mesh, {t}, {Tri{1, 0, 4}}, -1, -1, -1, scratch));        // 6 >= 5
    CHECK_FALSE(keeps_feature_wedges(mesh, {t}, {Tri{1, 0, 5}}, -1, -1, -1, scratch));  // 3 < 5
}

namespace {

// A junction line a = 0, v = 1, b = 2 along x (v at the origin) with three sheets: the
// half-disk j is (a, v, p_j) and (v, b, q_j), p_j at `at_av[j]` degrees around x (above
// x = -0.5), q_j at `at_vb[j]` (above x = 0.5). The removal of v replaces the six by
// (a, b, r_j), r_j at `after[j]` degrees (above x = 0). Whether the wedge guard lets it.
bool line_removal_keeps_wedges(const std::vector<double>& at_av, const std::vector<double>& at_vb,
                               const std::vector<double>& after) {
    const auto point = [](double x, double degrees) {
        const double r = degrees * M_PI / 180;
        return Vec3{x, std::cos(r), std::sin(r)};
    };
    Surface s;
    s.vertices = {{-1, 0, 0}, {0, 0, 0}, {1, 0, 0}};
    std::vector<Tri> added;
    for (size_t j = 0; j < 3; ++j) {
        const int32_t p = int32_t(s.vertices.size());
        s.vertices.push_back(point(-0.5, at_av[j]));
        s.vertices.push_back(point(0.5, at_vb[j]));
        s.vertices.push_back(point(0, after[j]));
        s.triangles.push_back({0, 1, p});
        s.triangles.push_back({1, 2, p + 1});
        s.patches.insert(s.patches.end(), 2, int32_t(j));
        added.push_back({0, 2, p + 2});
    }
    CoarseMesh mesh(s);
    mesh.mark_feature_edges(180.0);
    REQUIRE(mesh.is_feature_edge(0, 1));
    REQUIRE(mesh.is_feature_edge(1, 2));
    std::vector<int32_t> removed;
    for (int32_t t = 0; t < mesh.triangle_capacity(); ++t)
        if (mesh.alive(t)) removed.push_back(t);
    WedgeScratch scratch;
    return keeps_feature_wedges(mesh, removed, added, 0, 1, 2, scratch);
}

}  // namespace

TEST_CASE("wedge guard: along a feature line the wedge before is the thinner of a -- v and v -- b",
          "[internal][simplify][junctions]") {
    // Both old wedges below the 15-degree floor: 3 degrees at one of a -- v, v -- b and 10
    // at the other. A new wedge of 6 degrees at a -- b is no thinner than the thinner (3):
    // let pass, either way round (a guard that read only a -- v, or only v -- b, refuses
    // one of the two); 2 degrees is thinner than both: refused.
    const std::vector<double> thin = {0, 120, 123}, wider = {0, 120, 130};
    CHECK(line_removal_keeps_wedges(thin, wider, {0, 120, 126}));
    CHECK(line_removal_keeps_wedges(wider, thin, {0, 120, 126}));
    CHECK_FALSE(line_removal_keeps_wedges(thin, wider, {0, 120, 122}));
    CHECK_FALSE(line_removal_keeps_wedges(wider, thin, {0, 120, 122}));
    // Wide enough after (20 degrees): let pass without a look at before.
    CHECK(line_removal_keeps_wedges(thin, thin, {0, 120, 140}));
}
