// repair_self_intersections (bpm/self_intersection_repair.h): a closed sphere with one
// vertex pushed through to the far side (its fan pierces the other half, as where a
// scan's thin part was reconstructed through the rest) is repaired locally; what cannot
// be repaired (patches that would meet in the new triangles, a non-manifold edge) is
// left untouched with the reason.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "bpm/check.h"
#include "bpm/self_intersection_repair.h"
#include "bpm/surface.h"

using namespace bpm;

namespace {

constexpr int kRings = 12, kSegments = 24;

int32_t ring_vertex(int ring, int segment) { return 1 + (ring - 1) * kSegments + (segment % kSegments); }

// A UV sphere (266 vertices, 528 triangles, patch 3), optionally with the vertex of ring 6,
// segment 0 pushed through the centre to just outside the far side; vertex data "id" holds
// every vertex's index.
Surface sphere(bool spike) {
    Surface s;
    const double pi = std::acos(-1.0);
    s.vertices.push_back({0, 0, 1});
    for (int i = 1; i < kRings; ++i)
        for (int j = 0; j < kSegments; ++j) {
            const double th = pi * i / kRings, ph = 2 * pi * j / kSegments;
            s.vertices.push_back({std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)});
        }
    s.vertices.push_back({0, 0, -1});
    const int32_t last = s.num_vertices() - 1;
    for (int j = 0; j < kSegments; ++j) s.triangles.push_back({0, ring_vertex(1, j), ring_vertex(1, j + 1)});
    for (int i = 1; i < kRings - 1; ++i)
        for (int j = 0; j < kSegments; ++j) {
            const int32_t a = ring_vertex(i, j), b = ring_vertex(i + 1, j), c = ring_vertex(i + 1, j + 1),
                          d = ring_vertex(i, j + 1);
            s.triangles.push_back({a, b, c});
            s.triangles.push_back({a, c, d});
        }
    for (int j = 0; j < kSegments; ++j) s.triangles.push_back({last, ring_vertex(kRings - 1, j + 1), ring_vertex(kRings - 1, j)});
    if (spike) {
        Vec3& v = s.vertices[size_t(ring_vertex(6, 0))];
        v = -1.05 * v;
    }
    s.patches.assign(s.triangles.size(), 3);
    VertexArray id{"id", 1, {}};
    for (int32_t v = 0; v < s.num_vertices(); ++v) id.values.push_back(v);
    s.vertex_data.push_back(id);
    return s;
}

int64_t intersecting_pairs(const Surface& s) { return check_intersections(s).problem_count; }

// Triangle t of a repaired sphere by the input's vertex ids (its vertex data "id").
Tri input_ids(const Surface& s, const Tri& t) {
    Tri ids;
    for (int c = 0; c < 3; ++c) ids[size_t(c)] = int32_t(s.vertex_data[0].values[size_t(t[size_t(c)])]);
    return ids;
}

}  // namespace

// The spike reaches across the sphere: its repair moves the surface by ~0.2 of the diagonal.
SelfIntersectionRepairOptions far() {
    SelfIntersectionRepairOptions options;
    options.max_change = 1;
    return options;
}

TEST_CASE("a vertex pushed through the far side is repaired locally", "[self_intersection_repair]") {
    const Surface input = sphere(true);
    REQUIRE(intersecting_pairs(input) > 0);
    Surface s = input;
    const SelfIntersectionRepair r = repair_self_intersections(s, far());
    INFO(r.refused);
    CHECK(r.refused.empty());
    CHECK(r.intersecting_pairs == intersecting_pairs(input));
    CHECK(r.remaining_pairs == 0);
    CHECK(intersecting_pairs(s) == 0);
    CHECK(r.removed_triangles > 0);
    CHECK(r.removed_triangles < 40);  // local: the spike's fan and what it pierced, not the sphere
    CHECK(s.num_triangles() == input.num_triangles() - r.removed_triangles + r.added_triangles);
    CHECK(s.num_vertices() == input.num_vertices() - r.removed_vertices + r.added_vertices);
    CHECK(r.largest_change > 0.1);  // the spike reached across the sphere
    // Patches and vertex data stay in step; kept vertices keep their data, new ones take a
    // kept vertex's; the spike vertex is gone.
    REQUIRE(s.patches.size() == s.triangles.size());
    for (int32_t p : s.patches) CHECK(p == 3);
    REQUIRE(s.vertex_data.size() == 1);
    REQUIRE(s.vertex_data[0].values.size() == s.vertices.size());
    const int32_t spike = ring_vertex(6, 0);
    for (size_t v = 0; v < s.vertices.size(); ++v) {
        const double id = s.vertex_data[0].values[v];
        REQUIRE(id == std::floor(id));
        REQUIRE(id >= 0);
        REQUIRE(id < input.num_vertices());
        if (v < s.vertices.size() - size_t(r.added_vertices)) CHECK(id != spike);
    }
    // The kept triangles come first, in their order, and are the input's.
    size_t kept = 0;
    for (size_t t = 0; t < input.triangles.size() && kept < s.triangles.size(); ++t) {
        if (input_ids(s, s.triangles[kept]) == input.triangles[t]) ++kept;
    }
    CHECK(int64_t(kept) == input.num_triangles() - r.removed_triangles);
    // Kept vertices keep their positions and their own data.
    for (size_t v = 0; v + size_t(r.added_vertices) < s.vertices.size(); ++v)
        CHECK(s.vertices[v] == input.vertices[size_t(s.vertex_data[0].values[v])]);
    CHECK(r.topology_change.empty());
    // Deterministic.
    Surface again = input;
    repair_self_intersections(again, far());
    CHECK(again.vertices == s.vertices);
    CHECK(again.triangles == s.triangles);
}

TEST_CASE("a surface without intersections is left as it is", "[self_intersection_repair]") {
    const Surface input = sphere(false);
    Surface s = input;
    const SelfIntersectionRepair r = repair_self_intersections(s);
    CHECK(r.intersecting_pairs == 0);
    CHECK(r.remaining_pairs == 0);
    CHECK(r.refused.empty());
    CHECK(s.vertices == input.vertices);
    CHECK(s.triangles == input.triangles);
}

TEST_CASE("a repair whose new triangles would border two patches is refused", "[self_intersection_repair]") {
    Surface input = sphere(true);
    for (size_t t = 0; t < input.patches.size(); ++t) input.patches[t] = int32_t(t % 2);
    Surface s = input;
    const SelfIntersectionRepair r = repair_self_intersections(s, far());
    CHECK(r.refused.find("patches") != std::string::npos);
    CHECK(r.remaining_pairs == r.intersecting_pairs);
    CHECK(r.removed_triangles == 0);
    CHECK(s.vertices == input.vertices);
    CHECK(s.triangles == input.triangles);
    CHECK(s.patches == input.patches);
}

TEST_CASE("a repair that moves the surface further than max_change is refused, untouched", "[self_intersection_repair]") {
    const Surface input = sphere(true);
    Surface s = input;
    const SelfIntersectionRepair r = repair_self_intersections(s);  // max_change 0.01
    CHECK(r.refused.find("max_change") != std::string::npos);
    CHECK(r.remaining_pairs == r.intersecting_pairs);
    CHECK(r.removed_triangles == 0);
    CHECK(s.vertices == input.vertices);
    CHECK(s.triangles == input.triangles);
}

TEST_CASE("a triangle turned against its neighbours is a sheet of its own, kept", "[self_intersection_repair]") {
    Surface input = sphere(true);
    std::swap(input.triangles[30][1], input.triangles[30][2]);
    Surface s = input;
    const SelfIntersectionRepair r = repair_self_intersections(s, far());
    INFO(r.refused);
    CHECK(r.refused.empty());
    CHECK(r.remaining_pairs == 0);
    CHECK(input_ids(s, s.triangles[30]) == input.triangles[30]);
}

TEST_CASE("surfaces a caller got wrong are std::invalid_argument", "[self_intersection_repair]") {
    Surface s = sphere(true);
    s.patches.clear();
    CHECK_THROWS_AS(repair_self_intersections(s), std::invalid_argument);
    s = sphere(true);
    s.vertex_data[0].values.pop_back();
    CHECK_THROWS_AS(repair_self_intersections(s), std::invalid_argument);
    s = sphere(true);
    s.triangles[5][1] = 9999;
    CHECK_THROWS_AS(repair_self_intersections(s), std::invalid_argument);
    // Behind a harmless problem (a repeated corner in an earlier triangle) too.
    s = sphere(true);
    s.triangles[2][1] = s.triangles[2][0];
    s.triangles[5][1] = 9999;
    CHECK_THROWS_AS(repair_self_intersections(s), std::invalid_argument);
}

TEST_CASE("a non-manifold edge is kept, the crossing repaired", "[self_intersection_repair]") {
    Surface input = sphere(true);
    // A third triangle on the edge between the north pole and ring 1, outside the sphere.
    input.vertices.push_back({0.1, 0.1, 2});
    input.vertex_data[0].values.push_back(input.num_vertices() - 1);
    input.triangles.push_back({0, ring_vertex(1, 0), input.num_vertices() - 1});
    input.patches.push_back(3);
    Surface s = input;
    const SelfIntersectionRepair r = repair_self_intersections(s, far());
    INFO(r.refused);
    CHECK(r.refused.empty());
    CHECK(r.remaining_pairs == 0);
    // The flap is still there, on the same two sphere vertices (its vertex ids by data).
    CHECK(input_ids(s, s.triangles[size_t(input.num_triangles() - 1 - r.removed_triangles)]) == input.triangles.back());
    CHECK(std::count(s.vertex_data[0].values.begin(), s.vertex_data[0].values.end(), 0.0) == 1);
}

TEST_CASE("a pinched vertex (two fans meeting at their tip) is repaired around and kept as one", "[self_intersection_repair]") {
    Surface input = sphere(true);
    // A closed tetrahedron outside the sphere with one corner at the north pole (vertex 0).
    const int32_t n = input.num_vertices();
    for (const Vec3& p : {Vec3{0.3, 0, 1.5}, Vec3{-0.3, 0.3, 1.5}, Vec3{-0.3, -0.3, 1.5}}) {
        input.vertices.push_back(p);
        input.vertex_data[0].values.push_back(input.num_vertices() - 1);
    }
    for (const Tri& t : {Tri{0, n, n + 1}, Tri{0, n + 1, n + 2}, Tri{0, n + 2, n}, Tri{n, n + 2, n + 1}}) {
        input.triangles.push_back(t);
        input.patches.push_back(3);
    }
    Surface s = input;
    const SelfIntersectionRepair r = repair_self_intersections(s, far());
    INFO(r.refused);
    CHECK(r.refused.empty());
    CHECK(r.remaining_pairs == 0);
    CHECK(intersecting_pairs(s) == 0);
    // The pole is still one vertex, with the tetrahedron's triangles (the last kept ones).
    CHECK(std::count(s.vertex_data[0].values.begin(), s.vertex_data[0].values.end(), 0.0) == 1);
    CHECK(s.vertices[0] == input.vertices[0]);
    const int64_t kept = input.num_triangles() - r.removed_triangles;
    REQUIRE(kept >= 4);
    for (int k = 0; k < 4; ++k) {
        CHECK(input_ids(s, s.triangles[size_t(kept - 4 + k)]) == input.triangles[size_t(input.num_triangles() - 4 + k)]);
    }
}

TEST_CASE("max_change must be a number: NaN would accept any change", "[self_intersection_repair]") {
    Surface s = sphere(true);
    SelfIntersectionRepairOptions options;
    options.max_change = std::nan("");
    CHECK_THROWS_AS(repair_self_intersections(s, options), std::invalid_argument);
    options.max_change = -1;
    CHECK_THROWS_AS(repair_self_intersections(s, options), std::invalid_argument);
}

TEST_CASE("progress counts CGAL's rounds, not the regions within a round", "[self_intersection_repair]") {
    // Eight vertices pushed through: several separate regions in CGAL's first round. Its
    // rounds are at most 7; the visitor's stop() is also asked once per region, which was
    // counted as a round.
    Surface s = sphere(false);
    for (const auto& [ring, segment] : std::vector<std::pair<int, int>>{{3, 0}, {3, 6}, {3, 12}, {3, 18}, {9, 3}, {9, 9}, {9, 15}, {9, 21}}) {
        Vec3& v = s.vertices[size_t(ring_vertex(ring, segment))];
        v = -1.05 * v;
    }
    REQUIRE(intersecting_pairs(s) > 0);
    int largest = 0;
    Context context;
    context.progress = [&](double, const std::string& stage) {
        const std::string prefix = "self-intersection repair: round ";
        if (stage.compare(0, prefix.size(), prefix) == 0) largest = std::max(largest, std::stoi(stage.substr(prefix.size())));
        return true;
    };
    repair_self_intersections(s, far(), context);
    CHECK(largest >= 1);
    CHECK(largest <= 7);
}
