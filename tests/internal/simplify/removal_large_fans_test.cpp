// Large fans: the centre of a CAD disc fanned into hundreds or thousands of slivers
// (simplify/fan_retriangulation.h triangulation_aspect_lower_bound, VertexRemover's early
// refusal, classify_star's walk of a large star). Such a centre is re-ranked each time one
// of its corners goes; a full plan of it is O(n^2) (the ear cutting), and a run of a
// cylinder with two fan caps of 3000 corners took 77 s of CPU instead of 7.
#include <algorithm>
#include <string>

#include <catch2/catch.hpp>

#include "removal_test_fans.h"
#include "simplifier_state_fixture.h"
#include "simplify/fan_retriangulation.h"
#include "simplify/removal_cost.h"
#include "simplify/star_fans.h"

using namespace bpm;
using namespace bpm::detail;

namespace {

// A flat disc of radius 1 fanned from its centre (vertex 0) into n triangles; `wobble`
// moves every third rim vertex inwards by that fraction (an irregular rim).
Surface fan_disc(int n, double wobble = 0.0) {
    std::vector<double> angles, radii;
    for (int k = 0; k < n; ++k) {
        angles.push_back(360.0 * k / n);
        radii.push_back(k % 3 == 1 ? 1.0 - wobble : 1.0);
    }
    return removal_test::fan_surface(angles, radii, true);
}

double worst_of(const FanTriangulation& tri) { return *std::max_element(tri.aspects.begin(), tri.aspects.end()); }

}  // namespace

TEST_CASE("removal large fans: the lower bound is below the retriangulation's worst triangle", "[simplify][removal]") {
    for (const int n : {5, 12, 100, 301})
        for (const double wobble : {0.0, 0.02, 0.3}) {
            CAPTURE(n, wobble);
            const Surface disc = fan_disc(n, wobble);
            CoarseMesh mesh(disc);  // keeps a reference to the positions
            std::vector<Fan> fans;
            StarScratch star;
            bool crease_line = false;
            std::string why;
            REQUIRE(classify_star(mesh, 0, false, fans, crease_line, why, star) == VertexClass::Regular);
            REQUIRE(fans[0].corners() == n);
            PolarMap map;
            REQUIRE(polar_map(mesh.positions(), 0, fans[0], 1.0, map, why));
            FanTriangulation tri;
            EarScratch ears;
            REQUIRE(retriangulate_fan(mesh, fans[0], map, {}, tri, ears, why));
            const double bound = triangulation_aspect_lower_bound(mesh.positions(), fans[0]);
            CHECK(bound >= 2.0);
            CHECK(bound <= worst_of(tri) * (1.0 + 1e-12));
        }
}

TEST_CASE("removal large fans: a regular n-gon's bound is far above its fan's slivers", "[simplify][removal]") {
    // Every triangulation of a regular n-gon has ears of R/r about n^2 / pi^2; the fan's own
    // triangles have about n / (2 pi).
    const Surface disc = fan_disc(3000);
    CoarseMesh mesh(disc);
    std::vector<Fan> fans;
    StarScratch star;
    bool crease_line = false;
    std::string why;
    REQUIRE(classify_star(mesh, 0, false, fans, crease_line, why, star) == VertexClass::Regular);
    double worst_old = 0.0;
    for (int32_t t : fans[0].triangles) worst_old = std::max(worst_old, mesh.aspect(t));
    CHECK(worst_old == Approx(3000 / (2 * M_PI)).epsilon(0.01));
    CHECK(triangulation_aspect_lower_bound(mesh.positions(), fans[0]) > 100 * worst_old);
}

TEST_CASE("removal large fans: a large star is walked in link order", "[simplify][removal]") {
    // More than 64 triangles: classify_star looks the triangles up in a sorted list.
    for (const int n : {64, 65, 1000}) {
        CAPTURE(n);
        const Surface disc = fan_disc(n);
        CoarseMesh mesh(disc);
        std::vector<Fan> fans;
        StarScratch star;
        bool crease_line = false;
        std::string why;
        REQUIRE(classify_star(mesh, 0, false, fans, crease_line, why, star) == VertexClass::Regular);
        REQUIRE(fans.size() == 1);
        REQUIRE(fans[0].corners() == n);
        // From the smallest triangle id, counter-clockwise: triangle k is (0, k + 1, k + 2).
        for (int k = 0; k < n; ++k) {
            CHECK(fans[0].link[size_t(k)] == k + 1);
            CHECK(fans[0].triangles[size_t(k)] == k);
        }
    }
}

TEST_CASE("removal large fans: a centre no retriangulation can pass is refused unplanned", "[simplify][removal]") {
    // 300 corners: every retriangulation has a triangle of R/r > 3000 where the fan has 48.
    const Surface disc = fan_disc(300);
    test::LiveState state(disc);
    VertexRemover remover(state.mesh, state.embedding, state.sign, state.no_normals, state.no_ridges);
    SimplifyOptions options;
    RemovalPlan plan;
    std::string why;
    // Without the limit: planned (O(n^2)), and refused only by its cost. (A cheap plan: the
    // full one fails in the transfer, on triangles this thin.)
    remover.plan(0, false, plan);
    REQUIRE(plan.valid);
    CHECK(plan.worst_new_aspect > 3000);
    CHECK(std::isinf(removal_cost(plan, options, 2.0, CostBasis::Plan, why)));
    CHECK(why == kShapeLimitReason);
    // With it (as the simplifier sets it): refused before the retriangulation, for the
    // same reason, cheap plans and full ones alike.
    remover.set_aspect_limit(options.max_aspect_ratio);
    for (const bool validate : {false, true}) {
        remover.plan(0, validate, plan);
        CHECK_FALSE(plan.valid);
        CHECK_FALSE(plan.estimated);  // no retriangulation was made
        CHECK(plan.reason == kShapeLimitReason);
        CHECK(std::isinf(removal_cost(plan, options, 2.0, CostBasis::Plan, why)));
        CHECK(why == kShapeLimitReason);
    }
    // A rim vertex (a small star) is planned as before.
    remover.plan(1, true, plan);
    CHECK(plan.estimated);
}

TEST_CASE("removal large fans: below the limit a large centre is planned as before", "[simplify][removal]") {
    // A 70-gon disc with a limit far above every retriangulation: the same plan as without one.
    const Surface disc = fan_disc(70, 0.02);
    test::LiveState state(disc);
    VertexRemover plain(state.mesh, state.embedding, state.sign, state.no_normals, state.no_ridges);
    VertexRemover limited(state.mesh, state.embedding, state.sign, state.no_normals, state.no_ridges);
    limited.set_aspect_limit(1e9);
    for (const bool validate : {false, true}) {
        RemovalPlan a, b;
        plain.plan(0, validate, a);
        limited.plan(0, validate, b);
        CHECK(a.estimated);
        CHECK(a.valid == b.valid);
        CHECK(a.reason == b.reason);
        CHECK(a.new_triangles == b.new_triangles);
        CHECK(a.worst_new_aspect == b.worst_new_aspect);
    }
}

TEST_CASE("removal large fans: a square rim with collinear corners is triangulated", "[simplify][removal]") {
    // A square face fanned from its centre (bench/make_fan_box.py): 4 x 20 rim corners,
    // 19 of every 20 on a straight side. The polar map cannot make it strictly convex; the
    // ears of its own polygon go first, and none may be a straight corner.
    std::vector<double> angles, radii;
    const int m = 20;
    for (int side = 0; side < 4; ++side)
        for (int k = 0; k < m; ++k) {
            const double t = double(k) / m - 0.5;  // along the side, from -0.5
            const double x = side == 0 ? t : side == 1 ? 0.5 : side == 2 ? -t : -0.5;
            const double y = side == 0 ? -0.5 : side == 1 ? t : side == 2 ? 0.5 : -t;
            angles.push_back(std::atan2(y, x) * 180.0 / M_PI);
            radii.push_back(std::hypot(x, y));
        }
    const Surface square = removal_test::fan_surface(angles, radii, true);
    CoarseMesh mesh(square);
    std::vector<Fan> fans;
    StarScratch star;
    bool crease_line = false;
    std::string why;
    REQUIRE(classify_star(mesh, 0, false, fans, crease_line, why, star) == VertexClass::Regular);
    PolarMap map;
    REQUIRE(polar_map(mesh.positions(), 0, fans[0], 1.0, map, why));
    CHECK(map.cocircular);  // the corners on a circle, the polar map's polygon for the ears
    FanTriangulation tri;
    EarScratch ears;
    REQUIRE(retriangulate_fan(mesh, fans[0], map, {}, tri, ears, why));
    CHECK(tri.triangles.size() == size_t(4 * m - 2));
    for (double a : tri.aspects) CHECK(std::isfinite(a));  // no three corners on one side
    CHECK(worst_of(tri) >= triangulation_aspect_lower_bound(mesh.positions(), fans[0]));
}
