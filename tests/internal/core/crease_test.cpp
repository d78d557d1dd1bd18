// The crease test (core/crease.h) that the simplifier, the smoother and bpm-info share: a
// hinge of two triangles folded by a known angle is a crease exactly when the fold is more
// than the feature angle, whichever way either triangle is stored; degenerate triangles and
// a feature angle of 180 degrees give no crease.
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "core/crease.h"

using namespace bpm;
using namespace bpm::detail;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Edge 0-1 along x; triangle (0, 1, 2) in the plane z = 0 (normal +z), triangle (1, 0, 3)
// folded up about the edge by `fold_degrees` (0: flat, the two normals equal). Vertex 4
// lies on the edge's line (a degenerate triangle (1, 0, 4)).
std::vector<Vec3> hinge(double fold_degrees) {
    const double a = fold_degrees * kPi / 180.0;
    return {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -std::cos(a), std::sin(a)}, {2, 0, 0}};
}

}  // namespace

TEST_CASE("crease test: an edge is a crease where the normals are more than the feature angle apart",
          "[internal][core][crease]") {
    const CreaseTest test(60.0);
    CHECK(test.finds_creases());
    CHECK_FALSE(test.is_crease(hinge(0), {0, 1, 2}, {1, 0, 3}, 0, 1));
    CHECK_FALSE(test.is_crease(hinge(59), {0, 1, 2}, {1, 0, 3}, 0, 1));
    CHECK(test.is_crease(hinge(61), {0, 1, 2}, {1, 0, 3}, 0, 1));
    CHECK(test.is_crease(hinge(179), {0, 1, 2}, {1, 0, 3}, 1, 0));
    // Folding the other way (down) is as sharp.
    CHECK(test.is_crease(hinge(-61), {0, 1, 2}, {1, 0, 3}, 0, 1));
    // Strictly more: a flat pair at feature angle 0 is no crease.
    CHECK_FALSE(CreaseTest(0.0).is_crease(hinge(0), {0, 1, 2}, {1, 0, 3}, 0, 1));
}

TEST_CASE("crease test: the stored orientation of either triangle does not change the answer",
          "[internal][core][crease]") {
    const CreaseTest test(60.0);
    for (const Tri t0 : {Tri{0, 1, 2}, Tri{1, 0, 2}, Tri{2, 1, 0}})
        for (const Tri t1 : {Tri{1, 0, 3}, Tri{0, 1, 3}, Tri{3, 1, 0}}) {
            // A flat pair stored with one triangle turned over has opposite normals: still flat.
            CHECK_FALSE(test.is_crease(hinge(0), t0, t1, 0, 1));
            CHECK_FALSE(test.is_crease(hinge(30), t0, t1, 0, 1));
            CHECK(test.is_crease(hinge(90), t0, t1, 0, 1));
        }
}

TEST_CASE("crease test: degenerate triangles and a feature angle of 180 degrees give no crease",
          "[internal][core][crease]") {
    const CreaseTest test(10.0);
    CHECK_FALSE(test.is_crease(hinge(0), {0, 1, 2}, {1, 0, 4}, 0, 1));
    CHECK_FALSE(test.is_crease(hinge(0), {1, 0, 4}, {0, 1, 2}, 0, 1));
    const CreaseTest none(180.0);
    CHECK_FALSE(none.finds_creases());
    // Two triangles folded flat onto each other: their unit normals' dot product may round
    // below -1 = cos(180 degrees); 180 still means none.
    CHECK_FALSE(none.is_crease(hinge(180), {0, 1, 2}, {1, 0, 3}, 0, 1));
    CHECK_FALSE(none.is_crease(hinge(179.9), {0, 1, 2}, {1, 0, 3}, 0, 1));
}

TEST_CASE("ridge angle: 180 minus the fold, either way, whichever way the triangles are stored",
          "[internal][core][crease]") {
    // hinge(f): the normals are f degrees apart, so the wedge the two triangles make is 180 - f.
    CHECK(ridge_angle_degrees(hinge(0), {0, 1, 2}, {1, 0, 3}, 0, 1) == Approx(180.0));
    CHECK(ridge_angle_degrees(hinge(90), {0, 1, 2}, {1, 0, 3}, 0, 1) == Approx(90.0));
    CHECK(ridge_angle_degrees(hinge(163), {0, 1, 2}, {1, 0, 3}, 0, 1) == Approx(17.0));
    // A concave fold is as sharp as the convex one (the thin wedge is then outside).
    CHECK(ridge_angle_degrees(hinge(-163), {0, 1, 2}, {1, 0, 3}, 0, 1) == Approx(17.0));
    for (const Tri t0 : {Tri{0, 1, 2}, Tri{1, 0, 2}})
        for (const Tri t1 : {Tri{1, 0, 3}, Tri{0, 1, 3}})
            CHECK(ridge_angle_degrees(hinge(150), t0, t1, 1, 0) == Approx(30.0));
    // A degenerate triangle has no normal: no ridge.
    CHECK(ridge_angle_degrees(hinge(150), {0, 1, 2}, {1, 0, 4}, 0, 1) == 180.0);
}

TEST_CASE("crease test: an input sliver thinner than 1e-10 has no direction, a thicker one keeps it",
          "[internal][core][crease][sliver]") {
    // Vertex 4 is 1e-13 off the line of edge 0-1, below it in z: triangle (1, 0, 4) has a
    // normal that rounding of a snapped vertex decides (here it points along -y, 90 degrees
    // from triangle (0, 1, 2)'s). Its edges made creases at random, its corners crease
    // corners, and the simplifier kept the sliver (a gmsh cylinder: R/r 1.2e30).
    std::vector<Vec3> p = hinge(0);
    p[4] = {0.5, 0, -1e-13};
    const CreaseTest test(60.0);
    CHECK_FALSE(test.is_crease(p, {0, 1, 2}, {1, 0, 4}, 0, 1));
    CHECK(ridge_angle_degrees(p, {0, 1, 2}, {1, 0, 4}, 0, 1) == 180.0);
    // 1e-9 of the edge: a real (if thin) triangle, whose fold counts.
    p[4] = {0.5, 0, -1e-9};
    CHECK(test.is_crease(p, {0, 1, 2}, {1, 0, 4}, 0, 1));
    CHECK(ridge_angle_degrees(p, {0, 1, 2}, {1, 0, 4}, 0, 1) == Approx(90.0));
}
