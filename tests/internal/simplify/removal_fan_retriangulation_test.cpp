// retriangulate_fan (simplify/fan_retriangulation.h): ear cutting of a fan's polygon.
#include <algorithm>

#include <catch2/catch.hpp>

#include "bpm/predicates.h"
#include "removal_test_fans.h"
#include "simplify/coarse_mesh.h"
#include "simplify/fan_retriangulation.h"

using namespace bpm;
using namespace bpm::detail;

namespace {

struct Retriangulated {
    bool ok = false;
    std::string why;
    PolarMap map;
    FanTriangulation tri;
};

Retriangulated retriangulate(const CoarseMesh& mesh, const std::vector<std::array<int32_t, 2>>& forbidden = {}) {
    std::vector<Fan> fans;
    StarScratch star;
    bool crease_line = false;
    Retriangulated r;
    REQUIRE(classify_star(mesh, 0, false, fans, crease_line, r.why, star) != VertexClass::Feature);
    REQUIRE(polar_map(mesh.positions(), 0, fans[0], 1.0, r.map, r.why));
    EarScratch ears;
    r.ok = retriangulate_fan(mesh, fans[0], r.map, forbidden, r.tri, ears, r.why);
    return r;
}

bool has_diagonal(const FanTriangulation& tri, int32_t a, int32_t b) {
    for (const auto& d : tri.diagonals)
        if ((d[0] == a && d[1] == b) || (d[0] == b && d[1] == a)) return true;
    return false;
}

// n - 2 counter-clockwise triangles that cover the polygon (their areas add up).
void check_triangulates(const Retriangulated& r) {
    const int32_t n = static_cast<int32_t>(r.map.q.size());
    REQUIRE(r.tri.triangles.size() == size_t(n - 2));
    CHECK(r.tri.diagonals.size() == size_t(n - 3));
    CHECK(r.tri.aspects.size() == r.tri.triangles.size());
    double area = 0.0, polygon = 0.0;
    for (const auto& t : r.tri.triangles) {
        CHECK(orient2d(r.map.q[t[0]], r.map.q[t[1]], r.map.q[t[2]]) > 0);
        area += cross(r.map.q[t[1]] - r.map.q[t[0]], r.map.q[t[2]] - r.map.q[t[0]]);
    }
    for (int32_t i = 1; i + 1 < n; ++i) polygon += cross(r.map.q[i] - r.map.q[0], r.map.q[i + 1] - r.map.q[0]);
    CHECK(area == Approx(polygon));
}

}  // namespace

TEST_CASE("removal retriangulation: a regular hexagon gives four triangles", "[simplify][removal]") {
    const Surface s = removal_test::hexagon_fan();
    CoarseMesh mesh(s);
    const Retriangulated r = retriangulate(mesh);
    REQUIRE(r.ok);
    check_triangulates(r);
    for (double a : r.tri.aspects) CHECK(std::isfinite(a));
    // Forbidding the first diagonal makes another one first.
    const auto first = r.tri.diagonals[0];
    const Retriangulated other = retriangulate(mesh, {first});
    REQUIRE(other.ok);
    check_triangulates(other);
    CHECK_FALSE(has_diagonal(other.tri, first[0], first[1]));
}

TEST_CASE("removal retriangulation: existing edges are never diagonals", "[simplify][removal]") {
    Surface s = removal_test::hexagon_fan();
    // Elsewhere on the surface, the link vertices 1 and 3 (corners 0 and 2) already share an edge.
    s.vertices.push_back({0.0, 3.0, 1.0});
    s.triangles.push_back({1, 3, 7});
    s.patches.push_back(0);
    CoarseMesh mesh(s);
    const Retriangulated r = retriangulate(mesh);
    REQUIRE(r.ok);
    check_triangulates(r);
    CHECK_FALSE(has_diagonal(r.tri, 0, 2));

    // A square whose both diagonals exist cannot be retriangulated.
    Surface square = removal_test::fan_surface({0, 90, 180, 270}, {1, 1, 1, 1}, true);
    square.vertices.push_back({0.0, 0.0, 2.0});
    square.vertices.push_back({0.0, 0.0, -2.0});
    square.triangles.push_back({1, 3, 5});
    square.triangles.push_back({2, 4, 6});
    square.patches.resize(square.triangles.size(), 0);
    CoarseMesh blocked(square);
    const Retriangulated none = retriangulate(blocked);
    CHECK_FALSE(none.ok);
    CHECK(none.why == "no admissible retriangulation (topology condition)");
}

TEST_CASE("removal retriangulation: a non-convex star does not fold over its reflex corner",
          "[simplify][removal]") {
    const Surface s = removal_test::dented_fan();
    CoarseMesh mesh(s);
    const Retriangulated r = retriangulate(mesh);
    REQUIRE(r.ok);
    REQUIRE(r.map.cocircular);
    check_triangulates(r);
    // Corner 3 (vertex 4) is reflex in the polar map: its ear (2, 3, 4) would overlap the
    // rest of the star. Every new triangle is counter-clockwise where the polar map put
    // the corners, too.
    for (const auto& t : r.tri.triangles) {
        CHECK_FALSE((t[0] == 2 && t[1] == 3 && t[2] == 4));
        CHECK(orient2d(r.map.q_polar[t[0]], r.map.q_polar[t[1]], r.map.q_polar[t[2]]) > 0);
    }
}

TEST_CASE("removal retriangulation: a half-disk gets its new feature edge as a side", "[simplify][removal]") {
    const Surface s = removal_test::half_disk_fan();
    CoarseMesh mesh(s);
    mesh.mark_feature_edges(60.0);
    const Retriangulated r = retriangulate(mesh);
    REQUIRE(r.ok);
    check_triangulates(r);
    // The side from corner 4 back to corner 0 is the new edge, never a diagonal.
    CHECK_FALSE(has_diagonal(r.tri, 0, 4));
}

TEST_CASE("removal retriangulation: a dead end of the greedy ears falls back to another triangulation",
          "[simplify][removal]") {
    // After a retry forbade both diagonals of the quadrilateral the first two ears leave
    // (seen on a regular lattice, where original edges run along both: a flat face of a
    // gmsh box), the ear cutting had no ear left; other triangulations avoid both.
    const Surface s = removal_test::hexagon_fan();
    CoarseMesh mesh(s);
    const Retriangulated r = retriangulate(mesh);
    REQUIRE(r.ok);
    const int32_t n = static_cast<int32_t>(r.map.q.size());
    REQUIRE(n == 6);
    std::vector<int32_t> left;
    for (int32_t i = 0; i < n; ++i)
        if (i != r.tri.triangles[0][1] && i != r.tri.triangles[1][1]) left.push_back(i);
    REQUIRE(left.size() == 4);
    const std::vector<std::array<int32_t, 2>> forbidden{{left[0], left[2]}, {left[1], left[3]}};
    const Retriangulated other = retriangulate(mesh, forbidden);
    REQUIRE(other.ok);
    check_triangulates(other);
    for (const auto& f : forbidden) CHECK_FALSE(has_diagonal(other.tri, f[0], f[1]));
    for (double a : other.tri.aspects) CHECK(std::isfinite(a));
    // Forbidding every diagonal leaves nothing.
    std::vector<std::array<int32_t, 2>> all;
    for (int32_t a = 0; a < n; ++a)
        for (int32_t b = a + 2; b < n; ++b)
            if (!(a == 0 && b == n - 1)) all.push_back({a, b});
    CHECK_FALSE(retriangulate(mesh, all).ok);
}
