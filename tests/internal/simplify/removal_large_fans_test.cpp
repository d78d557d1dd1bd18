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

namespace {

// A square face of side 1 fanned from its centre (vertex 0) as bench/make_fan_box.py
// writes it: m rim corners per side, exactly on the side's line, counter-clockwise from
// (0, 0); `dent` moves every seventh rim vertex that far towards the centre (reflex
// corners: ears with other corners inside).
Surface square_fan(int m, double dent = 0.0) {
    Surface s;
    s.vertices.push_back({0.5, 0.5, 0.0});
    for (int side = 0; side < 4; ++side)
        for (int k = 0; k < m; ++k) {
            const double t = double(k) / m;
            const double x = side == 0 ? t : side == 1 ? 1.0 : side == 2 ? 1.0 - t : 0.0;
            const double y = side == 0 ? 0.0 : side == 1 ? t : side == 2 ? 1.0 : 1.0 - t;
            const int i = side * m + k;
            const double in = i % 7 == 3 ? dent : 0.0;
            s.vertices.push_back({x + in * (0.5 - x), y + in * (0.5 - y), 0.0});
        }
    const int32_t n = 4 * m;
    for (int32_t k = 1; k < n; ++k) s.triangles.push_back({0, k, k + 1});
    s.triangles.push_back({0, n, 1});
    s.patches.assign(s.triangles.size(), 0);
    return s;
}

struct SquareCut {
    bool ok = false;
    std::string why;
    FanTriangulation tri;
    int64_t work = 0;
};

SquareCut cut_square(const Surface& square, bool indexed = true,
                     const std::vector<std::array<int32_t, 2>>& forbidden = {}) {
    CoarseMesh mesh(square);
    std::vector<Fan> fans;
    StarScratch star;
    bool crease_line = false;
    SquareCut r;
    REQUIRE(classify_star(mesh, 0, false, fans, crease_line, r.why, star) == VertexClass::Regular);
    PolarMap map;
    REQUIRE(polar_map(mesh.positions(), 0, fans[0], 1.0, map, r.why));
    REQUIRE(map.cocircular);
    EarScratch ears;
    ears.indexed = indexed;
    r.ok = retriangulate_fan(mesh, fans[0], map, forbidden, r.tri, ears, r.why);
    r.work = ears.work;
    return r;
}

}  // namespace

TEST_CASE("removal large fans: a square rim of collinear corners is cut in O(n log n), not O(n^2)",
          "[simplify][removal]") {
    // The fan box's centres (bench/make_fan_box.py) pass the shape limit, so their plans are
    // made each time a rim vertex goes: the plain ear cutting scanned every corner for every
    // cut (about n^2 corner visits: 5 million at 4 x 401 corners).
    // (An odd number per side: with an even one the four zips from the square's corners
    // meet on three collinear corners, and the last triangle is degenerate.)
    const SquareCut small = cut_square(square_fan(101));
    const SquareCut large = cut_square(square_fan(401));
    REQUIRE(small.ok);
    REQUIRE(large.ok);
    CHECK(large.tri.triangles.size() == size_t(4 * 401 - 2));
    CAPTURE(small.work, large.work);
    CHECK(large.work < 20 * 4 * 401);  // 12 n now
    CHECK(large.work < 6 * small.work);  // 4 times the corners: 16 times the work if quadratic
}

TEST_CASE("removal large fans: the indexed ear cutting makes the plain scan's choices", "[simplify][removal]") {
    // Square rims with straight sides, odd and even (the even ones fail on their last
    // triangle), dented (ears with corners inside: the polar-ear test and its witnesses),
    // with diagonals forbidden, and with an existing edge between two rim vertices.
    for (const int m : {17, 40, 101})
        for (const double dent : {0.0, 0.01, 0.2}) {
            CAPTURE(m, dent);
            const Surface square = square_fan(m, dent);
            const SquareCut plain = cut_square(square, false);
            const SquareCut indexed = cut_square(square, true);
            CHECK(indexed.ok == plain.ok);
            CHECK(indexed.why == plain.why);
            CHECK(indexed.tri.triangles == plain.tri.triangles);
            CHECK(indexed.tri.aspects == plain.tri.aspects);
            CHECK(indexed.tri.diagonals == plain.tri.diagonals);
            if (!plain.ok) continue;
            CHECK(indexed.work < plain.work);
            // Forbid the first three diagonals the plain scan cut.
            std::vector<std::array<int32_t, 2>> forbidden(plain.tri.diagonals.begin(), plain.tri.diagonals.begin() + 3);
            const SquareCut plain_f = cut_square(square, false, forbidden);
            const SquareCut indexed_f = cut_square(square, true, forbidden);
            CHECK(indexed_f.ok == plain_f.ok);
            CHECK(indexed_f.why == plain_f.why);
            CHECK(indexed_f.tri.triangles == plain_f.tri.triangles);
            CHECK(indexed_f.tri.diagonals == plain_f.tri.diagonals);
            // An edge elsewhere between the ends of the first diagonal (link vertices are
            // corners + 1): that diagonal is blocked.
            Surface linked = square;
            const int32_t u = plain.tri.diagonals[0][0] + 1, w = plain.tri.diagonals[0][1] + 1;
            linked.vertices.push_back({0.5, 0.5, 1.0});
            linked.triangles.push_back({u, w, int32_t(linked.vertices.size() - 1)});
            linked.patches.push_back(0);
            const SquareCut plain_e = cut_square(linked, false);
            const SquareCut indexed_e = cut_square(linked, true);
            CHECK(indexed_e.ok == plain_e.ok);
            CHECK(indexed_e.why == plain_e.why);
            CHECK(indexed_e.tri.triangles == plain_e.tri.triangles);
            CHECK(indexed_e.tri.diagonals == plain_e.tri.diagonals);
        }
}
