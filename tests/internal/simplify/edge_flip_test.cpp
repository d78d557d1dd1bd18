// Edge flips of the coarse surface with phi re-embedded (simplify/edge_flip.h): a cap
// needle is flipped, a feature edge never, a sliver edge of a closed surface is, phi
// stays bijective through flips of edges that carry original vertices and crossings,
// and a flip refused by the error bound leaves phi as it was.
#include <algorithm>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/check.h"
#include "fixtures_surfaces.h"
#include "simplify/coarse_mesh.h"
#include "simplify/edge_flip.h"
#include "simplify/embedding.h"
#include "simplify/export_phi.h"
#include "simplify/intersection_test.h"
#include "simplify/planning_pool.h"
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
