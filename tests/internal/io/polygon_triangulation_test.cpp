// The ear clipper of the triangulate-polygons repair (io/polygon_triangulation.h), tested
// directly: what it promises is the face's area and orientation kept, and a refusal (never
// a guess) for polygons that are not simple seen along their normal.
#include <cmath>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/geometry.h"
#include "io/polygon_triangulation.h"

using namespace bpm;
using bpm::detail::triangulate_polygon;

namespace {

Vec3 area_vector(const std::vector<Vec3>& v, const std::vector<Tri>& tris) {
    Vec3 sum{0, 0, 0};
    for (const Tri& t : tris) sum = sum + 0.5 * cross(v[t[1]] - v[t[0]], v[t[2]] - v[t[0]]);
    return sum;
}

}  // namespace

TEST_CASE("polygon triangulation: a convex quad gives two triangles of its orientation", "[internal][io]") {
    const std::vector<Vec3> v{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    std::vector<Tri> out;
    std::string why;
    REQUIRE(triangulate_polygon(v, {0, 1, 2, 3}, out, why));
    REQUIRE(out.size() == 2);
    const Vec3 a = area_vector(v, out);
    CHECK(a[2] == Approx(1.0));
    CHECK(std::abs(a[0]) + std::abs(a[1]) < 1e-15);
}

TEST_CASE("polygon triangulation: an L-shaped hexagon keeps its area, every triangle inside", "[internal][io]") {
    // Reflex corner at (1,1): a fan from corner 0 would cover the notch.
    const std::vector<Vec3> v{{0, 0, 5}, {2, 0, 5}, {2, 1, 5}, {1, 1, 5}, {1, 2, 5}, {0, 2, 5}};
    std::vector<Tri> out;
    std::string why;
    REQUIRE(triangulate_polygon(v, {0, 1, 2, 3, 4, 5}, out, why));
    REQUIRE(out.size() == 4);
    CHECK(area_vector(v, out)[2] == Approx(3.0));
    for (const Tri& t : out) {
        const Vec3 n = cross(v[t[1]] - v[t[0]], v[t[2]] - v[t[0]]);
        CHECK(n[2] > 0);  // no triangle flipped: each one is inside the polygon
        const Vec3 c = (1.0 / 3.0) * (v[t[0]] + v[t[1]] + v[t[2]]);
        CHECK_FALSE((c[0] > 1 && c[1] > 1));  // none over the notch
    }
}

TEST_CASE("polygon triangulation: a clockwise face stays clockwise", "[internal][io]") {
    const std::vector<Vec3> v{{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};
    std::vector<Tri> out;
    std::string why;
    REQUIRE(triangulate_polygon(v, {0, 1, 2, 3}, out, why));
    CHECK(area_vector(v, out)[2] == Approx(-1.0));
}

TEST_CASE("polygon triangulation: a self-crossing (bow-tie) polygon is refused and out is unchanged",
          "[internal][io]") {
    const std::vector<Vec3> v{{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}};
    std::vector<Tri> out{{7, 8, 9}};
    std::string why;
    CHECK_FALSE(triangulate_polygon(v, {0, 1, 2, 3}, out, why));
    CHECK(!why.empty());
    REQUIRE(out.size() == 1);
    CHECK(out[0] == Tri{7, 8, 9});
}
