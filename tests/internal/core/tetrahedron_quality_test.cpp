// The one implementation of dihedral angles (core/tetrahedron_quality.h): the values and
// edge order on the corner tetrahedron, the sign for inverted tetrahedra, what flat and
// degenerate tetrahedra give, small angles measured accurately (where acos of a normalised
// dot product loses half the digits), and pseudo-angles that rank like the angles.
#include <cmath>

#include <catch2/catch.hpp>

#include "bpm/geometry.h"
#include "bpm/predicates.h"
#include "core/tetrahedron_quality.h"

using namespace bpm;
using namespace bpm::detail;

namespace {

constexpr double kPi = 3.14159265358979323846;
const Vec3 o{0, 0, 0}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};

}  // namespace

TEST_CASE("dihedral angles: the corner tetrahedron, edges in the order 01 02 03 12 13 23", "[internal][core][dihedral]") {
    double a[6];
    dihedral_angles(o, x, y, z, a);
    // Edges at the right-angled corner: 90 degrees; the others acos(1/sqrt(3)) = 54.7356.
    const double corner = std::acos(1 / std::sqrt(3.0));
    CHECK(a[0] == Approx(kPi / 2));
    CHECK(a[1] == Approx(kPi / 2));
    CHECK(a[2] == Approx(kPi / 2));
    CHECK(a[3] == Approx(corner));
    CHECK(a[4] == Approx(corner));
    CHECK(a[5] == Approx(corner));
    CHECK(min_dihedral(o, x, y, z) == Approx(corner));
    CHECK(min_dihedral_degrees(o, x, y, z) == Approx(54.7356).epsilon(1e-6));
}

TEST_CASE("dihedral angles: an inverted tetrahedron has the negated angles of its mirror image",
          "[internal][core][dihedral]") {
    REQUIRE(orient3d(o, x, y, z) == 1);
    REQUIRE(orient3d(x, o, y, z) == -1);
    double positive[6], inverted[6];
    dihedral_angles(o, x, y, z, positive);
    dihedral_angles(x, o, y, z, inverted);  // corners 0 and 1 swapped: edges 02<->12, 03<->13
    const int mirror[6] = {0, 3, 4, 1, 2, 5};
    for (int e = 0; e < 6; ++e) CHECK(inverted[e] == Approx(-positive[mirror[e]]));
    CHECK(min_dihedral_degrees(x, o, y, z) == Approx(-90));  // every inverted tetrahedron ranks below 0
}

TEST_CASE("dihedral angles: flat and degenerate tetrahedra", "[internal][core][dihedral]") {
    double a[6];
    // A flat square: its four sides 0, its two diagonals (02 and 13) pi; never -0.
    dihedral_angles(o, x, {1, 1, 0}, y, a);
    const double expected[6] = {0, kPi, 0, 0, kPi, 0};
    for (int e = 0; e < 6; ++e) {
        CHECK(a[e] == expected[e]);
        CHECK(!std::signbit(a[e]));
    }
    CHECK(min_dihedral(o, x, {1, 1, 0}, y) == 0);
    // A point inside a triangle: the triangle's edges 0, the edges to the point pi.
    dihedral_angles(o, {3, 0, 0}, {0, 3, 0}, {1, 1, 0}, a);
    const double inside[6] = {0, 0, kPi, 0, kPi, kPi};
    for (int e = 0; e < 6; ++e) CHECK(a[e] == inside[e]);
    // Coincident and collinear corners (faces of zero area): 0, as the pseudo-angles.
    dihedral_angles(o, o, x, y, a);
    for (double v : a) CHECK(v == 0);
    dihedral_angles(o, x, {2, 0, 0}, {3, 0, 0}, a);
    for (double v : a) CHECK(v == 0);
    dihedral_pseudo_angles(o, x, {2, 0, 0}, {3, 0, 0}, a);
    for (double v : a) CHECK(v == 0);
}

TEST_CASE("dihedral angles: a thin wedge's small angle to full relative precision", "[internal][core][dihedral]") {
    // Faces (a, b, c) and (a, b, d) meet at edge ab (edge 0) at exactly theta.
    for (double theta : {1e-3, 1e-6, 1e-9}) {
        double a[6];
        dihedral_angles(o, x, {0.5, 1, 0}, {0.5, std::cos(theta), std::sin(theta)}, a);
        INFO("theta = " << theta);
        CHECK(a[0] == Approx(theta).epsilon(1e-12));
        CHECK(min_dihedral(o, x, {0.5, 1, 0}, {0.5, std::cos(theta), std::sin(theta)}) == a[0]);
    }
}

TEST_CASE("dihedral pseudo-angles rank like the angles and convert back", "[internal][core][dihedral]") {
    const Vec3 tets[][4] = {{o, x, y, z}, {x, o, y, z}, {o, x, y, {0.2, 0.3, 1e-4}}, {o, x, y, {5, 5, 0.1}},
                            {o, x, y, {0.3, 0.3, -2}}};
    for (const auto& t : tets) {
        double angle[6], pseudo[6];
        dihedral_angles(t[0], t[1], t[2], t[3], angle);
        dihedral_pseudo_angles(t[0], t[1], t[2], t[3], pseudo);
        for (int e = 0; e < 6; ++e) {
            CHECK(pseudo[e] > -2);
            CHECK(pseudo[e] < 2);
            CHECK(radians_from_pseudo(pseudo[e]) == Approx(angle[e]).margin(1e-9));
            CHECK(pseudo_from_radians(angle[e]) == Approx(pseudo[e]).margin(1e-12));
            for (int f = 0; f < 6; ++f)
                if (angle[e] < angle[f] - 1e-12) CHECK(pseudo[e] < pseudo[f]);
        }
        CHECK(radians_from_pseudo(min_dihedral_pseudo(t[0], t[1], t[2], t[3])) ==
              Approx(min_dihedral(t[0], t[1], t[2], t[3])).margin(1e-9));
    }
}
