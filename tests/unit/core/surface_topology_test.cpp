#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "bpm/surface_topology.h"
#include "fixtures_surfaces.h"

using namespace bpm;

namespace {

struct Expected {
    int64_t components, chi, b0, b1, b2, boundary_loops;
    bool orientable, manifold;
    size_t feature_vertices, feature_lines;
};

void check_invariants(const Surface& s, const Expected& e) {
    const SurfaceTopology t = compute_topology(s);
    INFO(describe_topology(t));
    CHECK(static_cast<int64_t>(t.components.size()) == e.components);
    CHECK(t.euler_characteristic == e.chi);
    CHECK(t.betti0 == e.b0);
    CHECK(t.betti1 == e.b1);
    CHECK(t.betti2 == e.b2);
    CHECK(t.boundary_loops == e.boundary_loops);
    CHECK(t.orientable == e.orientable);
    CHECK(t.manifold == e.manifold);
    CHECK(t.feature_vertices.size() == e.feature_vertices);
    CHECK(t.feature_lines.size() == e.feature_lines);
    // Euler-Poincare over Z2 holds by construction; V - E + T must match the counts.
    CHECK(t.vertices - t.edges + t.triangles == t.euler_characteristic);
    // Nothing in a consistent surface compares unequal to itself.
    TopologyCorrespondence identity;
    for (int32_t v = 0; v < s.num_vertices(); ++v) identity.vertex_map.push_back(v);
    for (size_t c = 0; c < t.components.size(); ++c) identity.component_map.push_back(static_cast<int32_t>(c));
    CHECK(compare_topology(t, t, identity).empty());
}

size_t lines_with_sheets(const SurfaceTopology& t, int32_t sheets) {
    return static_cast<size_t>(std::count_if(t.feature_lines.begin(), t.feature_lines.end(),
                                             [&](const FeatureLine& l) { return l.sheets == sheets; }));
}

}  // namespace

TEST_CASE("connectivity lists every incident triangle of an edge", "[topology]") {
    const Surface s = fixtures::two_cubes();
    const SurfaceConnectivity c = build_connectivity(s);
    int three = 0;
    for (int32_t e = 0; e < c.num_edges(); ++e) {
        CHECK(c.edge_degree(e) >= 2);
        three += c.edge_degree(e) == 3;
        CHECK(c.find_edge(c.edges[e][1], c.edges[e][0]) == e);
    }
    CHECK(three == 4);  // the shared square's edges
    CHECK(c.find_edge(0, 0) == -1);
    for (int32_t t = 0; t < s.num_triangles(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int32_t e = c.triangle_edges[t][k];
            REQUIRE(e >= 0);
            CHECK(c.edges[e] == std::array<int32_t, 2>{std::min(s.triangles[t][k], s.triangles[t][(k + 1) % 3]),
                                                        std::max(s.triangles[t][k], s.triangles[t][(k + 1) % 3])});
        }
}

TEST_CASE("closed manifolds: Euler characteristic and Z2 Betti numbers", "[topology]") {
    SECTION("tetrahedron") { check_invariants(fixtures::tetrahedron(), {1, 2, 1, 0, 1, 0, true, true, 0, 0}); }
    SECTION("cube") {
        REQUIRE(fixtures::cube().num_triangles() == 12);
        check_invariants(fixtures::cube(), {1, 2, 1, 0, 1, 0, true, true, 0, 0});
        check_invariants(fixtures::cube(3), {1, 2, 1, 0, 1, 0, true, true, 0, 0});
    }
    SECTION("torus") { check_invariants(fixtures::torus(), {1, 0, 1, 2, 1, 0, true, true, 0, 0}); }
    SECTION("double torus") {
        check_invariants(fixtures::double_torus(), {1, -2, 1, 4, 1, 0, true, true, 0, 0});
        check_invariants(fixtures::double_torus(2), {1, -2, 1, 4, 1, 0, true, true, 0, 0});
    }
}

TEST_CASE("surfaces with boundary", "[topology]") {
    SECTION("disk: one boundary loop, a closed feature line of one sheet") {
        check_invariants(fixtures::disk(), {1, 1, 1, 0, 0, 1, true, true, 0, 1});
        const SurfaceTopology t = compute_topology(fixtures::disk());
        CHECK(t.feature_lines[0].closed);
        CHECK(t.feature_lines[0].sheets == 1);
        CHECK(t.feature_lines[0].edges.size() == 16);
    }
    SECTION("Moebius strip: non-orientable, one boundary loop") {
        check_invariants(fixtures::moebius(), {1, 0, 1, 1, 0, 1, false, true, 0, 1});
    }
    SECTION("two triangles touching at a vertex: two loops, not a figure eight") {
        Surface s;
        s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
        s.triangles = {{0, 1, 2}, {0, 3, 4}};
        s.patches = {0, 0};
        const SurfaceTopology t = compute_topology(s);
        CHECK(t.components.size() == 2);
        CHECK(t.boundary_loops == 2);
        CHECK(t.contact_vertices == std::vector<int32_t>{0});
        CHECK(t.betti0 == 1);
        CHECK(t.betti1 == 0);
        CHECK_FALSE(t.manifold);
        CHECK(std::find(t.feature_vertices.begin(), t.feature_vertices.end(), 0) != t.feature_vertices.end());
    }
    SECTION("a strip of triangles whose ends meet at one vertex: one component, pinched") {
        Surface s;
        s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}, {9, 9, 9}, {2, 2, 1}};
        s.triangles = {{0, 1, 2}, {1, 6, 2}, {6, 3, 2}, {6, 4, 3}, {0, 3, 4}};
        s.patches.assign(s.triangles.size(), 0);
        const SurfaceTopology t = compute_topology(s);
        CHECK(t.components.size() == 1);
        CHECK(t.vertices == 6);  // vertex 5 is unreferenced and ignored
        CHECK(t.euler_characteristic == 0);
        CHECK(t.betti1 == 1);
        CHECK(t.betti2 == 0);
        CHECK(t.boundary_loops == 1);
        CHECK_FALSE(t.components[0].manifold);
        CHECK(t.contact_vertices.empty());
        CHECK(std::find(t.feature_vertices.begin(), t.feature_vertices.end(), 0) != t.feature_vertices.end());
    }
}

TEST_CASE("non-manifold surfaces", "[topology]") {
    SECTION("two cubes sharing a face: a 3-sheet closed feature line") {
        for (int res : {1, 2}) {
            check_invariants(fixtures::two_cubes(res), {1, 3, 1, 0, 2, 0, true, false, 0, 1});
            const SurfaceTopology t = compute_topology(fixtures::two_cubes(res));
            CHECK(t.feature_lines[0].closed);
            CHECK(t.feature_lines[0].sheets == 3);
            CHECK(t.feature_lines[0].patches == std::vector<int32_t>{1, 2, 102});
            CHECK(t.feature_lines[0].edges.size() == static_cast<size_t>(4 * res));
            CHECK(t.components[0].sheets == 3);
        }
    }
    SECTION("three wedges of a cylinder: 4 lines of 3 sheets between the axis ends") {
        const Surface s = fixtures::cylinder_wedges();
        check_invariants(s, {1, 4, 1, 0, 3, 0, true, false, 2, 4});
        const SurfaceTopology t = compute_topology(s);
        CHECK(t.feature_vertices == std::vector<int32_t>{0, 2});  // axis ends
        CHECK(lines_with_sheets(t, 3) == 4);
        for (const FeatureLine& l : t.feature_lines) {
            CHECK(l.first_vertex == 0);
            CHECK(l.last_vertex == 2);
        }
    }
    SECTION("cube split into octants: 4-sheet lines, 6 lines at the centre") {
        for (int res : {1, 2}) {
            const Surface s = fixtures::octants(res);
            check_invariants(s, {1, 9, 1, 0, 8, 0, true, false, 7, 18});
            const SurfaceTopology t = compute_topology(s);
            CHECK(lines_with_sheets(t, 4) == 6);
            CHECK(lines_with_sheets(t, 3) == 12);
            // the centre (1,1,1) ends six lines
            int32_t centre = -1;
            for (int32_t v = 0; v < s.num_vertices(); ++v)
                if (s.vertices[v] == Vec3{1, 1, 1}) centre = v;
            REQUIRE(centre >= 0);
            int ends = 0;
            for (const FeatureLine& l : t.feature_lines) ends += (l.first_vertex == centre) + (l.last_vertex == centre);
            CHECK(ends == 6);
            CHECK(t.components[0].sheets == 8 + 12);  // one outer corner piece per octant, 12 internal quarters
        }
    }
    SECTION("hourglass: two components touching at the apex") {
        check_invariants(fixtures::hourglass(), {2, 3, 1, 0, 2, 0, true, false, 1, 0});
        const SurfaceTopology t = compute_topology(fixtures::hourglass());
        CHECK(t.contact_vertices == std::vector<int32_t>{0});
        CHECK(t.feature_vertices == std::vector<int32_t>{0});
        for (const ComponentSummary& c : t.components) {
            CHECK(c.euler_characteristic == 2);
            CHECK(c.betti1 == 0);
            CHECK(c.betti2 == 1);
            CHECK(c.manifold);
        }
    }
}

TEST_CASE("feature structure of open surfaces", "[topology]") {
    SECTION("disk with two patches: the interface meets the boundary at two feature vertices") {
        Surface s = fixtures::disk(4);
        for (int32_t t = 0; t < s.num_triangles(); ++t) {
            const Tri& c = s.triangles[t];
            const double x = (s.vertices[c[0]][0] + s.vertices[c[1]][0] + s.vertices[c[2]][0]) / 3;
            s.patches[t] = x < 2 ? 0 : 1;
        }
        const SurfaceTopology t = compute_topology(s);
        CHECK(t.feature_vertices == std::vector<int32_t>{2, 22});  // (2,0) and (2,4)
        REQUIRE(t.feature_lines.size() == 3);
        CHECK(lines_with_sheets(t, 1) == 2);
        CHECK(lines_with_sheets(t, 2) == 1);
        CHECK(t.boundary_loops == 1);
        CHECK(t.components[0].sheets == 2);
    }
    SECTION("fin: three flaps on one edge") {
        Surface s;
        s.vertices = {{0, 0, 0}, {0, 0, 1}};
        for (int i = 0; i < 3; ++i) {
            const double a = 2.0943951023931953 * i;
            s.vertices.push_back({std::cos(a), std::sin(a), 0});
            s.vertices.push_back({std::cos(a), std::sin(a), 1});
        }
        for (int32_t i = 0; i < 3; ++i) {
            const int32_t p = 2 + 2 * i, q = 3 + 2 * i;
            s.triangles.push_back({0, p, q});
            s.triangles.push_back({0, q, 1});
        }
        s.patches.assign(s.triangles.size(), 0);
        const SurfaceTopology t = compute_topology(s);
        CHECK(t.euler_characteristic == 1);
        CHECK(t.betti1 == 0);
        CHECK(t.betti2 == 0);
        CHECK(t.feature_vertices == std::vector<int32_t>{0, 1});
        CHECK(t.feature_lines.size() == 4);
        CHECK(lines_with_sheets(t, 3) == 1);
        CHECK(lines_with_sheets(t, 1) == 3);
        CHECK(t.boundary_loops == 1);  // the three boundary arcs meet in one wedge at each end
        CHECK_FALSE(t.manifold);
    }
}

TEST_CASE("compare_topology reports the first difference", "[topology]") {
    const SurfaceTopology cube = compute_topology(fixtures::cube());
    const SurfaceTopology torus = compute_topology(fixtures::torus());
    auto d = compare_topology(cube, torus, {});
    REQUIRE_FALSE(d.empty());
    CHECK(d.front().find("Euler characteristic") != std::string::npos);

    // Same counts but a different feature vertex: map the octants' vertices shifted by one.
    const Surface oct = fixtures::octants();
    const SurfaceTopology t = compute_topology(oct);
    TopologyCorrespondence shifted;
    for (int32_t v = 0; v < oct.num_vertices(); ++v) shifted.vertex_map.push_back((v + 1) % oct.num_vertices());
    d = compare_topology(t, t, shifted);
    REQUIRE_FALSE(d.empty());
    CHECK(d.front().find("feature vertex") != std::string::npos);

    // Without maps, equal multisets compare equal.
    CHECK(compare_topology(t, t, {}).empty());
}

TEST_CASE("Betti numbers scale to large surfaces", "[.perf]") {
    const Surface s = fixtures::torus(1000, 500);  // 1M triangles
    REQUIRE(s.num_triangles() == 1000000);
    const SurfaceTopology t = compute_topology(s);
    CHECK(t.betti1 == 2);
    const Surface oct = fixtures::octants(100);  // 1.44M triangles, 8 cells
    const SurfaceTopology to = compute_topology(oct);
    CHECK(to.betti2 == 8);
    CHECK(to.feature_lines.size() == 18);
}
