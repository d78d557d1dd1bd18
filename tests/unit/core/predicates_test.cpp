#include <catch2/catch.hpp>

#include <limits>

#include "bpm/predicates.h"

using namespace bpm;

namespace {
const int kNone[3] = {-1, -1, -1};

bool improper(std::array<Vec3, 3> a, std::array<Vec3, 3> b, std::array<int, 3> shared = {-1, -1, -1}) {
    const int s[3] = {shared[0], shared[1], shared[2]};
    const bool ab = triangles_intersect_improperly(a.data(), b.data(), s);
    // The predicate must be symmetric: build the inverse mapping and swap the roles.
    int inv[3] = {-1, -1, -1};
    for (int i = 0; i < 3; ++i)
        if (shared[i] >= 0) inv[shared[i]] = i;
    const bool ba = triangles_intersect_improperly(b.data(), a.data(), inv);
    CHECK(ab == ba);
    return ab;
}
}  // namespace

TEST_CASE("orientation predicates are exact", "[predicates]") {
    CHECK(orient2d({0, 0}, {1, 0}, {0, 1}) == 1);
    CHECK(orient2d({0, 0}, {0, 1}, {1, 0}) == -1);
    CHECK(orient2d({0, 0}, {1, 1}, {2, 2}) == 0);
    // Nearly collinear points where naive floating point gets the sign wrong.
    const double e = std::numeric_limits<double>::epsilon();
    CHECK(orient2d({0.5, 0.5}, {12, 12}, {24, 24}) == 0);
    CHECK(orient2d({0.5, 0.5 + e}, {12, 12}, {24, 24}) != 0);
    CHECK(orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}) != 0);
    CHECK(orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.3, 0.3, 0}) == 0);
    CHECK(orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}) == -orient3d({0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}));
    CHECK(collinear3d({0, 0, 0}, {1, 1, 1}, {3, 3, 3}));
    CHECK_FALSE(collinear3d({0, 0, 0}, {1, 1, 1}, {3, 3, 3.0000000001}));
    CHECK(in_circle({0, 0}, {1, 0}, {0, 1}, {0.5, 0.5}) == 1);
    CHECK(in_circle({0, 0}, {1, 0}, {0, 1}, {1, 1}) == 0);
    CHECK(in_circle({0, 0}, {1, 0}, {0, 1}, {2, 2}) == -1);
}

TEST_CASE("disjoint triangles do not intersect", "[predicates]") {
    CHECK_FALSE(improper({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}, {{{0, 0, 1}, {1, 0, 1}, {0, 1, 1}}}));
    // coplanar, separated
    CHECK_FALSE(improper({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}, {{{2, 0, 0}, {3, 0, 0}, {2, 1, 0}}}));
    // coplanar, a hair apart along the hypotenuse
    CHECK_FALSE(improper({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}, {{{1, 0.0000001, 0}, {1, 1, 0}, {0.0000001, 1, 0}}}));
}

TEST_CASE("crossing triangles intersect", "[predicates]") {
    CHECK(improper({{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}}, {{{0.5, 0.5, -1}, {0.5, 0.5, 1}, {1.5, 0.2, 0}}}));
    // edge through face
    CHECK(improper({{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}}, {{{0.5, 0.5, -1}, {0.5, 0.5, 1}, {5, 5, 5}}}));
    // coplanar overlap without shared vertices
    CHECK(improper({{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}}, {{{0.5, 0.5, 0}, {3, 0.5, 0}, {0.5, 3, 0}}}));
}

TEST_CASE("touching without a shared vertex counts as an intersection", "[predicates]") {
    // a vertex of b on a vertex position of a, different indices
    CHECK(improper({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}, {{{0, 0, 0}, {-1, 0, 1}, {0, -1, 1}}}));
    // a vertex of b inside a
    CHECK(improper({{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}}, {{{0.5, 0.5, 0}, {0.5, 0.5, 1}, {1, 0.5, 1}}}));
    // edge on edge
    CHECK(improper({{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}}, {{{0.5, 0, 0}, {1.5, 0, 0}, {1, 0, 1}}}));
}

TEST_CASE("triangles sharing only a vertex", "[predicates]") {
    const std::array<Vec3, 3> a{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}};
    SECTION("apart") { CHECK_FALSE(improper(a, {{{0, 0, 0}, {-1, 0, 1}, {0, -1, 1}}}, {0, -1, -1})); }
    SECTION("coplanar, side by side") { CHECK_FALSE(improper(a, {{{0, 0, 0}, {0, -1, 0}, {1, -1, 0}}}, {0, -1, -1})); }
    SECTION("coplanar overlap") { CHECK(improper(a, {{{0, 0, 0}, {1, 0.2, 0}, {0.2, 1, 0}}}, {0, -1, -1})); }
    SECTION("coplanar, b inside a's angle but short") {
        CHECK(improper(a, {{{0, 0, 0}, {0.2, 0.1, 0}, {0.1, 0.2, 0}}}, {0, -1, -1}));
    }
    SECTION("coplanar, sharing the direction of an edge") {
        CHECK(improper(a, {{{0, 0, 0}, {0.5, 0, 0}, {0.5, -1, 0}}}, {0, -1, -1}));
    }
    SECTION("b's opposite edge pierces a") { CHECK(improper(a, {{{0, 0, 0}, {0.3, 0.3, -1}, {0.3, 0.3, 1}}}, {0, -1, -1})); }
    SECTION("b touches a's opposite edge") { CHECK(improper(a, {{{0, 0, 0}, {0.5, 0.5, 0}, {1, 1, 1}}}, {0, -1, -1})); }
    SECTION("b leans over a without touching") {
        CHECK_FALSE(improper(a, {{{0, 0, 0}, {0.3, 0.3, 0.1}, {0.3, 0.1, 0.2}}}, {0, -1, -1}));
    }
    SECTION("the shared vertex at different corners") {
        CHECK_FALSE(improper(a, {{{5, 5, 5}, {0, 0, 0}, {-1, 0, 1}}}, {1, -1, -1}));
        CHECK(improper(a, {{{0.3, 0.3, -1}, {0, 0, 0}, {0.3, 0.3, 1}}}, {1, -1, -1}));
    }
}

TEST_CASE("triangles sharing an edge", "[predicates]") {
    const std::array<Vec3, 3> a{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}};
    // b = (p, q, r) with a's corner 1 = b's corner 1 and a's corner 2 = b's corner 0
    SECTION("coplanar, unfolded") { CHECK_FALSE(improper(a, {{{0, 1, 0}, {1, 0, 0}, {1, 1, 0}}}, {-1, 1, 0})); }
    SECTION("coplanar, folded onto a") { CHECK(improper(a, {{{0, 1, 0}, {1, 0, 0}, {0.2, 0.2, 0}}}, {-1, 1, 0})); }
    SECTION("coplanar, folded and larger") { CHECK(improper(a, {{{0, 1, 0}, {1, 0, 0}, {-1, -1, 0}}}, {-1, 1, 0})); }
    SECTION("bent") { CHECK_FALSE(improper(a, {{{0, 1, 0}, {1, 0, 0}, {0.2, 0.2, 1}}}, {-1, 1, 0})); }
    SECTION("nearly folded but not coplanar") {
        CHECK_FALSE(improper(a, {{{0, 1, 0}, {1, 0, 0}, {0.2, 0.2, 1e-300}}}, {-1, 1, 0}));
    }
}

TEST_CASE("identical and degenerate triangles", "[predicates]") {
    const std::array<Vec3, 3> a{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}};
    CHECK(improper(a, a, {0, 1, 2}));
    CHECK(improper(a, {{a[1], a[2], a[0]}}, {2, 0, 1}));
    CHECK(improper(a, a));  // same positions, different vertices
    CHECK(improper(a, {{{5, 5, 5}, {6, 6, 6}, {7, 7, 7}}}));  // degenerate, far away: still reported
    (void)kNone;
}

TEST_CASE("orient3d's filter agrees with the exact predicate", "[predicates]") {
    // Random points, points on a plane (rounded, so nearly coplanar: the filter must
    // pass those to the exact predicate), tiny and huge coordinates, and exact ties.
    uint64_t state = 12345;
    auto next = [&] {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return double(state >> 11) * 0x1.0p-53 - 0.5;
    };
    int disagreements = 0, zeros = 0;
    for (int i = 0; i < 20000; ++i) {
        const double scale = i % 4 == 0 ? 1e-150 : (i % 4 == 1 ? 1e150 : (i % 4 == 2 ? 1.0 : 1e-300));
        Vec3 p[4];
        for (auto& q : p) q = {scale * next(), scale * next(), scale * next()};
        if (i % 3 == 0) {
            // d on the plane of a, b, c (up to rounding): a + s (b - a) + t (c - a)
            const double s = next(), t = next();
            for (int k = 0; k < 3; ++k) p[3][k] = p[0][k] + s * (p[1][k] - p[0][k]) + t * (p[2][k] - p[0][k]);
        }
        if (i % 7 == 0) p[3] = p[i % 3];  // a repeated point: exactly coplanar
        const int filtered = orient3d(p[0], p[1], p[2], p[3]);
        const int exact = orient3d_exact(p[0], p[1], p[2], p[3]);
        disagreements += filtered != exact;
        zeros += exact == 0;
    }
    CHECK(disagreements == 0);
    CHECK(zeros > 0);
    // d on the side the normal (b - a) x (c - a) = +z points to: +1, as CGAL::orientation.
    CHECK(orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}) == 1);
    CHECK(orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, -1}) == -1);
    CHECK(orient3d_exact({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}) == 1);
    CHECK(orient3d_exact({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, -1}) == -1);
}
