// Edge flips of the coarse surface with phi re-embedded (simplify/edge_flip.h): a cap
// needle is flipped, a feature edge never, a sliver edge of a closed surface is, phi
// stays bijective through flips of edges that carry original vertices and crossings,
// a flip refused by the error bound leaves phi as it was, and the guards a removal
// passes refuse flips too (a side of the quad folded by the ridge guard, a new triangle
// near another sheet by the clearance guard, one laid onto a triangle at a common
// corner by the corner-wedge guard).
#include <algorithm>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/check.h"
#include "core/crease.h"
#include "fixtures_surfaces.h"
#include "simplify/coarse_mesh.h"
#include "simplify/edge_flip.h"
#include "simplify/embedding.h"
#include "simplify/export_phi.h"
#include "simplify/intersection_test.h"
#include "simplify/clearance_guard.h"
#include "simplify/corner_wedge_guard.h"
#include "simplify/planning_pool.h"
#include "simplify/ridge_guard.h"
#include "simplify/vertex_removal.h"
#include "simplifier_state_fixture.h"

using namespace bpm;
using namespace bpm::detail;
using bpm::detail::test::LiveState;

namespace {

// Two triangles (a,b,c) (b,a,d) in the plane: (a,b,c) a cap (c close to a -- b).
Surface cap_pair() {
    Surface s;
    s.vertices = {{0, 0, 0}, {2, 0, 0}, {1, 0.02, 0}, {1, -1, 0}};
    s.triangles = {{0, 1, 2}, {1, 0, 3}};
    s.patches = {0, 0};
    return s;
}

// A closed box 2 x 2 x 1 whose top is two triangles bent up a little along the diagonal
// 4 -- 6 (a convex edge whose tetrahedron with its two triangles is a flat sliver).
Surface bent_box(double rise) {
    Surface s;
    s.vertices = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0},
                  {0, 0, 1 + rise}, {2, 0, 1}, {2, 2, 1 + rise}, {0, 2, 1}};
    s.triangles = {{0, 2, 1}, {0, 3, 2},                             // bottom (outward: -z)
                   {4, 5, 6}, {4, 6, 7},                             // top, diagonal 4 -- 6
                   {0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5},       // sides
                   {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
    s.patches.assign(s.triangles.size(), 0);
    return s;
}

// A cap (0,1,2) beside (1,0,3), and (2,1,4) across the cap's side 1 -- 2. The flip of
// 0 -- 1 (the cap's R/r 47 -> 5.8) turns the new triangle (3,1,2) onto (2,1,4): the
// ridge angle at the quad's side 1 -- 2 falls from 94 to 6.8 degrees, while its new
// edge 2 -- 3 has 162 (the ridges of 0 -- 1 and 1 -- 2 are 91 and 94: the test turns
// feature lines off).
Surface side_folding_quad() {
    Surface s;
    s.vertices = {{0, 0, 0}, {2, 0, 0}, {1.3, -0.1, 0.1}, {1.5, 2.7, 2.6}, {1.5, 0.9, 1.2}};
    s.triangles = {{0, 1, 2}, {1, 0, 3}, {2, 1, 4}};
    s.patches = {0, 0, 0};
    return s;
}

// A cap (0,1,2) bent up 45 degrees from (1,0,3) in the plane z = 0, and a small
// triangle (4,5,6) of its own 0.0005 above the ridge 2 -- 3 that the flip of 0 -- 1
// makes: relative clearance 0.00035 (of the new triangles' longest edge), from the old
// triangles 0.023 and 0.030.
Surface quad_under_a_sheet() {
    Surface s;
    // The new triangles meet at x = 1 along 2 -- 3, at height (0.05 + 0.05 y) / 1.05.
    const auto above_ridge = [](double x, double y) { return Vec3{x, y, (0.05 + 0.05 * y) / 1.05 + 0.0005}; };
    s.vertices = {{0, 0, 0}, {2, 0, 0}, {1, 0.05, 0.05}, {1, -1, 0},
                  above_ridge(0.99, -0.06), above_ridge(1.01, -0.06), above_ridge(1, -0.04)};
    s.triangles = {{0, 1, 2}, {1, 0, 3}, {4, 5, 6}};
    s.patches = {0, 0, 0};
    return s;
}

// A cap (0,1,2) bent up 50 degrees from (1,0,3) in the plane z = 0 (patch 0), and a
// triangle (3,4,5) of patch 1 at corner 3, 2 degrees above the plane of (0,3,2) that
// the flip of 0 -- 1 makes, inside its sector at 3 (6.6 degrees above (1,0,3)).
Surface quad_beside_a_corner() {
    Surface s;
    s.vertices = {{0, 0, 0}, {2, 0, 0}, {1, 0.1, 0.12}, {1, -1, 0}};
    const Vec3 d = s.vertices[3], to_a = s.vertices[0] - d, to_c = s.vertices[2] - d;
    const Vec3 normal = (1.0 / norm(cross(to_c, to_a))) * cross(to_c, to_a);  // up, away from the cap
    const double lift = std::tan(2.0 * M_PI / 180.0);
    // Two rays from 3 in the plane of (0,3,2), between 3 -> 2 and the bisector, lifted 2 degrees.
    for (double w : {0.1, 0.3}) {
        const Vec3 in_plane = (1 - w) * (1.0 / norm(to_c)) * to_c + w * (1.0 / norm(to_a)) * to_a;
        const Vec3 ray = (1.0 / norm(in_plane)) * in_plane;
        s.vertices.push_back(d + 0.5 * (ray + lift * normal));
    }
    s.triangles = {{0, 1, 2}, {1, 0, 3}, {3, 4, 5}};
    s.patches = {0, 0, 1};
    return s;
}

}  // namespace

TEST_CASE("edge flip: a cap is flipped to its other diagonal, phi stays valid", "[internal][simplify][flip]") {
    const Surface original = cap_pair();
    LiveState state(original);
    IntersectionTest intersections(state.mesh);
    FlipLimits limits;
    limits.needle_aspect = 30.0;
    limits.max_deviation = 1.0;
    const FlipStats stats = flip_edges(state.mesh, state.embedding, state.sign, intersections, limits);
    CHECK(stats.needle_flips == 1);
    CHECK(state.mesh.has_edge(2, 3));
    CHECK_FALSE(state.mesh.has_edge(0, 1));
    const Parametrization p = state.exported(original);
    CHECK(check_format(p).passed);
    CHECK(check_bijectivity(p).passed);
}

TEST_CASE("edge flip: never a feature edge", "[internal][simplify][flip]") {
    // The crease between two faces of a cube.
    const Surface original = fixtures::cube(2);
    LiveState state(original);
    int32_t creases = 0;
    for (int32_t t = 0; t < state.mesh.triangle_capacity(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int32_t a = state.mesh.triangle(t)[k], b = state.mesh.triangle(t)[(k + 1) % 3];
            if (!state.mesh.is_feature_edge(a, b)) continue;
            ++creases;
            EdgeFlip flip;
            std::string why;
            CHECK_FALSE(plan_edge_flip(state.mesh, state.embedding, a, b, flip, why));
            CHECK(why == "a feature edge");
        }
    CHECK(creases > 0);
}

TEST_CASE("edge flip: the convex edge under a sliver of a closed box is flipped", "[internal][simplify][flip]") {
    const Surface original = bent_box(0.02);
    LiveState state(original);
    IntersectionTest intersections(state.mesh);
    FlipLimits limits;
    limits.sliver_dihedral_degrees = 6.0;
    limits.max_deviation = 1.0;
    const FlipStats stats = flip_edges(state.mesh, state.embedding, state.sign, intersections, limits);
    CHECK(stats.sliver_flips == 1);
    CHECK(state.mesh.has_edge(5, 7));
    CHECK_FALSE(state.mesh.has_edge(4, 6));
    const Parametrization p = state.exported(original);
    CHECK(check_format(p).passed);
    CHECK(check_bijectivity(p).passed);

    // Off (dihedral 0): nothing happens; the flat faces of the box are never candidates.
    LiveState off(original);
    IntersectionTest off_intersections(off.mesh);
    limits.sliver_dihedral_degrees = 0.0;
    CHECK(flip_edges(off.mesh, off.embedding, off.sign, off_intersections, limits).sliver_flips == 0);
}

TEST_CASE("edge flip: a flip above the error bound is undone, phi as before", "[internal][simplify][flip]") {
    const Surface original = bent_box(0.02);
    LiveState state(original);
    const std::vector<Tri> before = state.sorted_triangles();
    IntersectionTest intersections(state.mesh);
    FlipLimits limits;
    limits.sliver_dihedral_degrees = 6.0;
    limits.max_deviation = 1e-6;  // the flip moves the ridge by up to 0.02
    const FlipStats stats = flip_edges(state.mesh, state.embedding, state.sign, intersections, limits);
    CHECK(stats.sliver_flips == 0);
    CHECK(stats.refused == 1);
    CHECK(state.sorted_triangles() == before);
    const Parametrization p = state.exported(original);
    CHECK(check_bijectivity(p).passed);
    CHECK(check_format(p).passed);
}

TEST_CASE("edge flip: phi stays bijective through flips of edges that carry phi", "[internal][simplify][flip]") {
    // After removals the coarse edges carry original vertices and crossings; flip every
    // edge that can be flipped (once), then export and check.
    const Surface original = fixtures::torus(24, 16);
    LiveState state(original);
    REQUIRE(state.remove_some(60, 5) >= 40);
    int flipped = 0, with_content = 0;
    std::vector<std::array<int32_t, 2>> edges;
    for (int32_t t = 0; t < state.mesh.triangle_capacity(); ++t) {
        if (!state.mesh.alive(t)) continue;
        const Tri& c = state.mesh.triangle(t);
        for (int k = 0; k < 3; ++k)
            if (c[k] < c[(k + 1) % 3]) edges.push_back({c[k], c[(k + 1) % 3]});
    }
    for (const auto& e : edges) {
        if (!state.mesh.has_edge(e[0], e[1])) continue;
        EdgeFlip flip;
        std::string why;
        if (!plan_edge_flip(state.mesh, state.embedding, e[0], e[1], flip, why)) continue;
        // Keep the undo data, as flip_edges does.
        EdgeFlip undo;
        undo.added = {state.mesh.triangle(flip.removed[0]), state.mesh.triangle(flip.removed[1])};
        undo.patch = flip.patch;
        for (const auto& loc : flip.new_locations) {
            detail::SurfacePoint p = state.embedding.location[loc.first];
            if (p.kind == detail::SurfacePoint::Inside) p.a = p.a == flip.removed[0] ? -1 : -2;
            undo.new_locations.push_back({loc.first, p});
        }
        for (const auto& path : flip.new_paths) {
            const auto old = state.embedding.path[size_t(path.first)];
            undo.new_paths.push_back({path.first, std::vector<detail::Crossing>(old.begin(), old.end())});
        }
        const auto ids = commit_edge_flip(state.mesh, state.embedding, flip);
        double deviation = 0.0;
        if (validate_flipped(state.mesh, state.embedding, state.sign, ids, deviation, why)) {
            ++flipped;
            if (!flip.new_locations.empty() || !flip.new_paths.empty()) ++with_content;
        } else {
            undo.removed = ids;
            commit_edge_flip(state.mesh, state.embedding, undo);
        }
    }
    CHECK(flipped >= 20);
    CHECK(with_content >= 10);
    const Parametrization p = state.exported(original);
    CHECK(check_format(p).passed);
    CHECK(check_bijectivity(p).passed);
}

// A guard's case: on `original` with `limits` no flip is made (the guard refuses it) and
// the surface is unchanged; with `guard_off` applied to the limits the flip of (0, 1) into
// (2, 3) is made, and `check_made(mesh state, stats)` looks at the result.
template <class GuardOff, class CheckMade>
void refused_only_by_the_guard(const Surface& original, FlipLimits limits, double feature_angle,
                               const std::vector<float>* ridges, GuardOff guard_off, CheckMade check_made) {
    {
        LiveState state(original, feature_angle);
        const std::vector<Tri> before = state.sorted_triangles();
        IntersectionTest intersections(state.mesh);
        const FlipStats stats = flip_edges(state.mesh, state.embedding, state.sign, intersections, limits, nullptr, ridges);
        CHECK(stats.needle_flips == 0);
        CHECK(stats.refused >= 1);
        CHECK(state.sorted_triangles() == before);
    }
    LiveState off(original, feature_angle);
    IntersectionTest off_intersections(off.mesh);
    guard_off(limits);
    const FlipStats stats = flip_edges(off.mesh, off.embedding, off.sign, off_intersections, limits, nullptr, ridges);
    CHECK(off.mesh.has_edge(2, 3));
    check_made(off, stats);
}

TEST_CASE("edge flip: a flip that folds a side of its quad is refused (ridge guard)", "[internal][simplify][flip]") {
    const Surface original = side_folding_quad();
    FlipLimits limits;
    limits.needle_aspect = 3.5;  // the cap; (2,1,4) is no needle
    limits.max_deviation = 10.0;
    limits.min_ridge_angle_degrees = 30.0;
    const std::vector<float> ridges = vertex_ridge_angles(original, LiveState(original, 180.0).embedding);
    // Without the ridge guard the flip is made (and only the side's ridge was wrong).
    refused_only_by_the_guard(
        original, limits, 180.0, &ridges, [](FlipLimits& l) { l.min_ridge_angle_degrees = 0.0; },
        [&](LiveState& off, const FlipStats& stats) {
            CHECK(stats.needle_flips >= 1);
            CHECK_FALSE(off.mesh.has_edge(0, 1));
            CHECK(check_bijectivity(off.exported(original)).passed);
            // The fold is at the side 1 -- 2, not at the new edge (a check there alone lets it pass).
            const auto ridge = [&](int32_t u, int32_t w) {
                std::vector<int32_t> tris;
                off.mesh.edge_triangles(u, w, tris);
                REQUIRE(tris.size() == 2);
                return ridge_angle_degrees(off.mesh.positions(), off.mesh.triangle(tris[0]), off.mesh.triangle(tris[1]),
                                           u, w);
            };
            CHECK(ridge(2, 3) > 150.0);
            CHECK(ridge(1, 2) < 10.0);
        });
}

TEST_CASE("edge flip: a flip that brings a new triangle near another sheet is refused (clearance)",
          "[internal][simplify][flip]") {
    const Surface original = quad_under_a_sheet();
    for (int32_t t : {0, 1})
        CHECK(relative_clearance(original.vertices, original.triangles[t], Tri{4, 5, 6}) > 10 * kClearanceFloor);
    FlipLimits limits;
    limits.max_deviation = 1.0;
    limits.clearance_floor = kClearanceFloor;
    // Without the clearance guard the flip is made: the new ridge passes under the sheet.
    refused_only_by_the_guard(
        original, limits, 60.0, nullptr, [](FlipLimits& l) { l.clearance_floor = 0.0; },
        [](LiveState& off, const FlipStats& stats) {
            CHECK(stats.needle_flips == 1);
            const auto& x = off.mesh.positions();
            double nearest = 1.0;
            for (int32_t t = 0; t < off.mesh.triangle_capacity(); ++t)
                if (off.mesh.alive(t) && off.mesh.triangle(t)[0] < 4)
                    nearest = std::min(nearest, relative_clearance(x, off.mesh.triangle(t), Tri{4, 5, 6}));
            CHECK(nearest < kClearanceFloor);
        });
}

TEST_CASE("edge flip: a flip that lays a new triangle onto another at a common corner is refused (corner wedges)",
          "[internal][simplify][flip]") {
    const Surface original = quad_beside_a_corner();
    FlipLimits limits;
    limits.max_deviation = 1.0;
    limits.corner_wedge_floor = kCornerWedgeFloorDegrees;
    // Without the corner-wedge guard the flip is made, 2 degrees from (3,4,5).
    refused_only_by_the_guard(
        original, limits, 60.0, nullptr, [](FlipLimits& l) { l.corner_wedge_floor = 0.0; },
        [](LiveState& off, const FlipStats& stats) {
            CHECK(stats.needle_flips == 1);
            CHECK(corner_wedge_degrees(off.mesh.positions(), Tri{0, 3, 2}, Tri{3, 4, 5}) < 2.5);
            CHECK(corner_wedge_degrees(off.mesh.positions(), Tri{1, 0, 3}, Tri{3, 4, 5}) > kCornerWedgeFloorDegrees);
        });
}
