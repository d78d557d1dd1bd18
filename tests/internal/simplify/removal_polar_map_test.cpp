// polar_map (simplify/polar_map.h): the fan's polygon in the plane.
#include <catch2/catch.hpp>

#include "bpm/predicates.h"
#include "removal_test_fans.h"
#include "simplify/polar_map.h"

using namespace bpm;
using namespace bpm::detail;

namespace {

Fan fan_of(std::vector<int32_t> link, bool closed) {
    Fan fan;
    fan.closed = closed;
    fan.link = std::move(link);
    const int32_t ntri = closed ? int32_t(fan.link.size()) : int32_t(fan.link.size()) - 1;
    for (int32_t i = 0; i < ntri; ++i) fan.triangles.push_back(i);
    return fan;
}

bool strictly_convex(const std::vector<Vec2>& q) {
    const int32_t n = static_cast<int32_t>(q.size());
    for (int32_t i = 0; i < n; ++i)
        if (orient2d(q[mod(i - 1, n)], q[i], q[mod(i + 1, n)]) <= 0) return false;
    return true;
}

}  // namespace

TEST_CASE("removal polar map: a flat regular hexagon maps onto itself", "[simplify][removal]") {
    const Surface s = removal_test::hexagon_fan();
    PolarMap map;
    std::string why;
    REQUIRE(polar_map(s.vertices, 0, fan_of({1, 2, 3, 4, 5, 6}, true), 1.0, map, why));
    CHECK_FALSE(map.cocircular);
    REQUIRE(map.q.size() == 6);
    for (int k = 0; k < 6; ++k) {
        CHECK(map.q[k][0] == Approx(s.vertices[k + 1][0]).margin(1e-12));
        CHECK(map.q[k][1] == Approx(s.vertices[k + 1][1]).margin(1e-12));
    }
}

TEST_CASE("removal polar map: a cone opens to 2 pi with z^alpha radii", "[simplify][removal]") {
    // Centre lifted: the angles at v sum to less than 2 pi, alpha > 1.
    const Surface s = removal_test::fan_surface({0, 60, 120, 180, 240, 300}, {1, 1, 1, 1, 1, 1}, true, 1.0);
    PolarMap map;
    std::string why;
    REQUIRE(polar_map(s.vertices, 0, fan_of({1, 2, 3, 4, 5, 6}, true), 2.0, map, why));
    CHECK_FALSE(map.cocircular);
    CHECK(map.phi[3] == Approx(M_PI));  // symmetric: the opposite corner at pi
    const double alpha = 2.0 * M_PI / (6.0 * map.theta[0]);
    CHECK(alpha > 1.0);
    CHECK(norm(Vec3{map.q[0][0], map.q[0][1], 0.0}) == Approx(std::pow(std::sqrt(2.0) / 2.0, alpha)));
    CHECK(strictly_convex(map.q));
}

TEST_CASE("removal polar map: a non-convex star goes onto the circle", "[simplify][removal]") {
    const Surface s = removal_test::dented_fan();
    PolarMap map;
    std::string why;
    REQUIRE(polar_map(s.vertices, 0, fan_of({1, 2, 3, 4, 5, 6}, true), 1.0, map, why));
    CHECK(map.cocircular);
    CHECK(strictly_convex(map.q));
    CHECK_FALSE(strictly_convex(map.q_polar));  // where the polar map put them
    for (const Vec2& p : map.q) CHECK(p[0] * p[0] + p[1] * p[1] == Approx(1.0));
    CHECK(map.q_polar[3][0] == Approx(-0.3));
}

TEST_CASE("removal polar map: a half-disk keeps its ends on the x axis", "[simplify][removal]") {
    const Surface s = removal_test::half_disk_fan();
    PolarMap map;
    std::string why;
    REQUIRE(polar_map(s.vertices, 0, fan_of({1, 2, 3, 4, 5}, false), 0.5, map, why));
    CHECK_FALSE(map.cocircular);
    CHECK(map.q[0][0] == 2.0);  // radius 1 over the scale 0.5
    CHECK(map.q[0][1] == 0.0);
    CHECK(map.q[4][0] == -2.0);
    CHECK(map.q[4][1] == 0.0);
    CHECK(map.q[2][0] == Approx(0.0).margin(1e-12));
    CHECK(map.q[2][1] == Approx(2.0));
}

TEST_CASE("removal polar map: a degenerate fan triangle is refused", "[simplify][removal]") {
    Surface s = removal_test::hexagon_fan();
    s.vertices[2] = s.vertices[1];  // triangle (0, 1, 2) has no angle at 0
    PolarMap map;
    std::string why;
    CHECK_FALSE(polar_map(s.vertices, 0, fan_of({1, 2, 3, 4, 5, 6}, true), 1.0, map, why));
    CHECK(why == "degenerate triangle in the star");
}

TEST_CASE("removal polar map: a sharp cone tip gives finite corners (r^alpha overflowed)", "[simplify][removal]") {
    // Total angle at v about 0.01 rad: alpha = 2 pi / 0.01 ~ 630, and r^alpha of corners
    // a few times radius_scale away was inf (q inf or NaN, sorted by the ear cutting).
    for (const int n : {6, 80}) {
        Surface s;
        s.vertices.push_back({0, 0, 0});
        const double rho = 0.01 / (2 * M_PI);
        std::vector<int32_t> link;
        for (int i = 0; i < n; ++i) {
            const double a = 2 * M_PI * i / n;
            s.vertices.push_back({rho * std::cos(a), rho * std::sin(a), i == 2 ? 0.5 : 1.0});
            link.push_back(i + 1);
        }
        double scale = 0;
        for (int i = 0; i < n; ++i) scale += distance(s.vertices[size_t(i + 1)], s.vertices[size_t((i + 1) % n + 1)]) / n;
        PolarMap map;
        std::string why;
        const bool ok = polar_map(s.vertices, 0, fan_of(link, true), scale, map, why);
        INFO("n = " << n << ", ok = " << ok << ", why = " << why);
        for (const auto* q : {&map.q, &map.q_polar})
            for (const Vec2& p : *q) {
                CHECK(std::isfinite(p[0]));
                CHECK(std::isfinite(p[1]));
            }
    }
}
