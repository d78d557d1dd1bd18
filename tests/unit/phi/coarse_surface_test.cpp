// Points of the coarse surface across triangle boundaries: expressing a point of an edge
// or corner in the other triangles containing it, and midpoints of boundary edges of a
// refined grid, checked against geometry constructed independently in 3D (a hinge whose
// unfolding is known in closed form, a flat fan where unfolding is the identity), exact
// midpoints on a feature line, and the refusals (bow-tie vertex, an edge of three
// triangles at the fan's vertex, triangles sharing nothing).

#include <catch2/catch.hpp>
#include <cmath>
#include <stdexcept>

#include "bpm/coarse_surface.h"
#include "bpm/errors.h"

using namespace bpm;

namespace {

Vec3 position(const Surface& s, const SurfacePoint& p) {
    const Tri& t = s.triangles[static_cast<size_t>(p.triangle)];
    return barycentric_point(s.vertices[static_cast<size_t>(t[0])], s.vertices[static_cast<size_t>(t[1])],
                             s.vertices[static_cast<size_t>(t[2])], p.barycentric);
}

// Barycentric coordinates of x (in the plane of triangle t) in t.
SurfacePoint locate(const Surface& s, int32_t t, const Vec3& x) {
    const Tri& tri = s.triangles[static_cast<size_t>(t)];
    const Vec3 a = s.vertices[static_cast<size_t>(tri[0])], b = s.vertices[static_cast<size_t>(tri[1])],
               c = s.vertices[static_cast<size_t>(tri[2])];
    const Vec3 n = cross(b - a, c - a);
    const double area = dot(n, n);
    const double l1 = dot(cross(x - a, c - a), n) / area, l2 = dot(cross(b - a, x - a), n) / area;
    return {t, {1 - l1 - l2, l1, l2}};
}

Surface surface(std::vector<Vec3> v, std::vector<Tri> t) {
    Surface s;
    s.vertices = std::move(v);
    s.triangles = std::move(t);
    s.patches.assign(s.triangles.size(), 0);
    return s;
}

// Two triangles hinged at the x-axis: T0 in the plane z = 0 (y > 0), T1 turned down by
// `angle` about the edge; (0, -cos, sin) is T1's unit direction away from the edge.
Surface hinge(double angle) {
    return surface({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -std::cos(angle), std::sin(angle)}}, {{0, 1, 2}, {1, 0, 3}});
}

}  // namespace

TEST_CASE("a point on a shared edge or corner is expressed in every triangle containing it", "[coarse_surface]") {
    const Surface s = hinge(0.7);
    const CoarseSurface cs(s);
    // On edge (0, 1): corner 2 of T0 is zero.
    const SurfacePoint e{0, {0.25, 0.75, 0}};
    const auto in1 = cs.express_in(e, 1);
    REQUIRE(in1);
    CHECK(in1->triangle == 1);
    CHECK(in1->barycentric == Vec3{0.75, 0.25, 0});  // T1 = (1, 0, 3): exact permutation
    CHECK(distance(position(s, *in1), position(s, e)) == 0);
    // Corner 1 (vertex 1) of T0 is corner 0 of T1.
    const auto corner = cs.express_in({0, {0, 1, 0}}, 1);
    REQUIRE(corner);
    CHECK(corner->barycentric == Vec3{1, 0, 0});
    // Interior points and points on an edge T1 does not have stay in their triangle.
    CHECK_FALSE(cs.express_in({0, {0.2, 0.3, 0.5}}, 1));
    CHECK_FALSE(cs.express_in({0, {0.5, 0, 0.5}}, 1));
    CHECK(cs.express_in({0, {0.2, 0.3, 0.5}}, 0) == SurfacePoint{0, {0.2, 0.3, 0.5}});
    CHECK_THROWS_AS(cs.express_in({0, {1, 0, 0}}, 2), std::out_of_range);
    CHECK_THROWS_AS(cs.express_in({-1, {1, 0, 0}}, 0), std::out_of_range);
}

TEST_CASE("midpoint in one triangle is the average of the coordinates", "[coarse_surface]") {
    const Surface s = hinge(0.7);
    const CoarseSurface cs(s);
    const SurfacePoint m = cs.midpoint({1, {0.2, 0.3, 0.5}}, {1, {0.6, 0.2, 0.2}});
    CHECK(m.triangle == 1);
    CHECK(m.barycentric == Vec3{0.5 * (0.2 + 0.6), 0.5 * (0.3 + 0.2), 0.5 * (0.5 + 0.2)});
}

TEST_CASE("midpoint across a bent coarse edge is the midpoint in the unfolding", "[coarse_surface]") {
    for (const double angle : {0.0, 0.4, 1.2, 2.5}) {
        const Surface s = hinge(angle);
        const CoarseSurface cs(s);
        const Vec3 down{0, -std::cos(angle), std::sin(angle)};
        for (const auto& c : {std::array<double, 4>{0.4, 0.2, 0.6, 0.1}, std::array<double, 4>{0.5, 0.1, 0.5, 0.3},
                              std::array<double, 4>{0.3, 0.15, 0.35, 0.15}}) {
            // a at distance d1 from the edge above x1 in T0, b at distance d2 above x2 in T1;
            // unfolded, the edge is the x-axis, a = (x1, d1), b = (x2, -d2), and the
            // midpoint is ((x1 + x2) / 2, (d1 - d2) / 2).
            const double x1 = c[0], d1 = c[1], x2 = c[2], d2 = c[3];
            const SurfacePoint a = locate(s, 0, {x1, d1, 0});
            const SurfacePoint b = locate(s, 1, Vec3{x2, 0, 0} + d2 * down);
            const double xm = 0.5 * (x1 + x2), dm = 0.5 * (d1 - d2);
            const Vec3 expected = dm >= 0 ? Vec3{xm, dm, 0} : Vec3{xm, 0, 0} + (-dm) * down;
            INFO("angle " << angle << ", x1 " << x1 << ", d1 " << d1 << ", x2 " << x2 << ", d2 " << d2);
            for (const SurfacePoint& m : {cs.midpoint(a, b), cs.midpoint(b, a)}) {
                CHECK(distance(position(s, m), expected) < 1e-14);
                CHECK(m.barycentric[0] >= 0);
                CHECK(m.barycentric[1] >= 0);
                CHECK(m.barycentric[2] >= 0);
                CHECK(m.barycentric[0] + m.barycentric[1] + m.barycentric[2] == Approx(1).margin(1e-15));
                CHECK(m.triangle == (dm > 0 ? 0 : dm < 0 ? 1 : m.triangle));
            }
        }
    }
}

TEST_CASE("midpoint of two points on a feature line stays on it exactly", "[coarse_surface]") {
    // A fin: three sheets on edge (0, 1). The two points are on the edge but given in
    // different sheets' triangles.
    const Surface s = surface({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -0.5, 0.8}, {0.5, -0.5, -0.8}},
                              {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
    const CoarseSurface cs(s);
    const SurfacePoint a{0, {0.7, 0.3, 0}};   // vertex 0: 0.7, vertex 1: 0.3
    const SurfacePoint b{1, {0.4, 0.6, 0}};   // T1 = (1, 0, 3): vertex 1: 0.4, vertex 0: 0.6
    const SurfacePoint m = cs.midpoint(a, b);
    const Tri& t = s.triangles[static_cast<size_t>(m.triangle)];
    Vec3 by_vertex{0, 0, 0};  // coordinates at vertices 0, 1 and the third corner
    for (int k = 0; k < 3; ++k) by_vertex[t[k] == 0 ? 0 : t[k] == 1 ? 1 : 2] = m.barycentric[k];
    CHECK(by_vertex[2] == 0);
    CHECK(by_vertex[0] == 0.5 * (0.7 + 0.6));
    CHECK(by_vertex[1] == 0.5 * (0.3 + 0.4));
    // A point on the edge and one inside a sheet: the sheet's triangle contains both.
    const SurfacePoint inside{2, {0.2, 0.3, 0.5}};
    const SurfacePoint m2 = cs.midpoint(a, inside);
    CHECK(m2.triangle == 2);
    CHECK(distance(position(s, m2), 0.5 * (position(s, a) + position(s, inside))) < 1e-15);
}

TEST_CASE("midpoint across a vertex of a flat fan is the midpoint of the segment", "[coarse_surface]") {
    // A flat hexagon around vertex 0: unfolding is the identity, so the midpoint in the
    // parameter domain is the midpoint of the 3D segment, also when the two triangles
    // share only vertex 0.
    std::vector<Vec3> v{{0, 0, 0}};
    std::vector<Tri> t;
    for (int k = 0; k < 6; ++k) v.push_back({std::cos(k * M_PI / 3), std::sin(k * M_PI / 3), 0});
    for (int k = 0; k < 6; ++k) t.push_back({0, 1 + k, 1 + (k + 1) % 6});
    const Surface s = surface(v, t);
    const CoarseSurface cs(s);
    for (const int other : {2, 3, 4}) {
        const SurfacePoint a{0, {0.3, 0.3, 0.4}};
        const SurfacePoint b{other, {0.4, 0.35, 0.25}};
        const SurfacePoint m = cs.midpoint(a, b);
        INFO("triangles 0 and " << other);
        CHECK(distance(position(s, m), 0.5 * (position(s, a) + position(s, b))) < 1e-14);
        CHECK(std::min({m.barycentric[0], m.barycentric[1], m.barycentric[2]}) >= 0);
    }
}

TEST_CASE("midpoint refuses triangles joined only through a non-manifold vertex", "[coarse_surface]") {
    SECTION("bow-tie: two fans touch at vertex 0") {
        const Surface s = surface({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0.2}}, {{0, 1, 2}, {0, 3, 4}});
        const CoarseSurface cs(s);
        try {
            cs.midpoint({0, {0.2, 0.4, 0.4}}, {1, {0.2, 0.4, 0.4}});
            FAIL("no error");
        } catch (const AlgorithmError& e) {
            CHECK(std::string(e.what()).find("coarse vertex 0") != std::string::npos);
        }
    }
    SECTION("an edge of three triangles at the vertex") {
        const Surface s = surface({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0.1}, {0, 0, 1}, {-1, 1, 0}, {-1, -1, 0}},
                                  {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {0, 2, 5}, {0, 3, 6}});
        const CoarseSurface cs(s);
        try {
            cs.midpoint({3, {0.2, 0.4, 0.4}}, {4, {0.2, 0.4, 0.4}});
            FAIL("no error");
        } catch (const AlgorithmError& e) {
            CHECK(std::string(e.what()).find("has 3 triangles") != std::string::npos);
        }
    }
    SECTION("triangles sharing nothing") {
        const Surface s = surface({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 0, 0}, {6, 0, 0}, {5, 1, 0}},
                                  {{0, 1, 2}, {3, 4, 5}});
        const CoarseSurface cs(s);
        CHECK_THROWS_AS(cs.midpoint({0, {0.2, 0.4, 0.4}}, {1, {0.2, 0.4, 0.4}}), AlgorithmError);
        CHECK_THROWS_AS(cs.midpoint({0, {0.2, 0.4, 0.4}}, {2, {0.2, 0.4, 0.4}}), std::out_of_range);
    }
}
