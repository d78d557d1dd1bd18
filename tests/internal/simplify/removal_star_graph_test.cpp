// gather_star_nodes, gather_straight_segments (simplify/star_graph.h): the original
// surface inside a fan as nodes and straightened segments.
#include <catch2/catch.hpp>

#include "removal_test_fans.h"
#include "simplify/coarse_mesh.h"
#include "simplify/embedding.h"
#include "simplify/polar_map.h"
#include "simplify/star_graph.h"
#include "simplify/vertex_removal.h"

using namespace bpm;
using namespace bpm::detail;

namespace {

// A fan surface with one more original vertex (7) at the centroid of triangle (0, 1, 2),
// already removed from the coarse surface: 7 lies inside coarse triangle (0, 1, 2).
struct HexagonWithInnerVertex {
    Surface original;
    CoarseMesh mesh;
    Embedding emb;
    std::vector<int8_t> sign;
    std::vector<Vec3> no_normals;  // VertexRemover keeps a reference
    std::vector<float> no_ridges;
    static Surface make() {
        Surface s = removal_test::hexagon_fan();
        s.vertices.push_back((1.0 / 3.0) * (s.vertices[0] + s.vertices[1] + s.vertices[2]));
        s.triangles[0] = {0, 1, 7};
        s.triangles.push_back({1, 2, 7});
        s.triangles.push_back({2, 0, 7});
        s.patches.assign(s.triangles.size(), 0);
        return s;
    }
    HexagonWithInnerVertex() : original(make()), mesh(original), sign(original.triangles.size(), 1) {
        emb.init_identity(original, mesh.triangle_capacity());
        VertexRemover remover(mesh, emb, sign, no_normals, no_ridges);
        RemovalPlan plan;
        remover.plan(7, true, plan);
        REQUIRE(plan.valid);
        commit_removal(mesh, emb, plan);
        REQUIRE(emb.location[7].kind == SurfacePoint::Inside);
    }
};

}  // namespace

TEST_CASE("removal star graph: a disk with an inner vertex", "[simplify][removal]") {
    HexagonWithInnerVertex h;
    std::vector<Fan> fans;
    StarScratch star;
    bool crease_line = false;
    std::string why;
    REQUIRE(classify_star(h.mesh, 0, false, fans, crease_line, why, star) == VertexClass::Regular);
    PolarMap map;
    REQUIRE(polar_map(h.mesh.positions(), 0, fans[0], 1.0, map, why));
    StarGraph graph;
    StarGraphScratch scratch;
    graph.clear(h.original.vertices.size());
    REQUIRE(gather_star_nodes(h.mesh, h.emb, 0, fans[0], map.q, true, nullptr, graph, scratch, why));
    // The six corners, no fixed nodes (nothing lies on the link edges), then the free
    // nodes 0 (the removed vertex of a disk) and 7, sorted.
    REQUIRE(graph.nodes.size() == 8);
    for (int32_t i = 0; i < 6; ++i) {
        CHECK(graph.nodes[i].poly_corner == i);
        CHECK_FALSE(graph.nodes[i].free);
        CHECK(graph.vertex_node.get(fans[0].link[i]) == i);
    }
    CHECK(graph.free_vertices == std::vector<int32_t>{0, 7});
    CHECK(graph.nodes[6].free);
    CHECK(graph.nodes[6].pos == Vec2{0.0, 0.0});
    // 7 through the polar map: the centroid of (v, corner of 1, corner of 2).
    const int32_t c1 = fans[0].corner_index(1), c2 = fans[0].corner_index(2);
    CHECK(graph.nodes[7].pos[0] == Approx((map.q[c1][0] + map.q[c2][0]) / 3.0));
    CHECK(graph.nodes[7].pos[1] == Approx((map.q[c1][1] + map.q[c2][1]) / 3.0));
    for (const auto& side : graph.side_nodes) CHECK(side.empty());

    REQUIRE(gather_straight_segments(h.emb, 0, fans[0], graph, scratch, why));
    // The six spokes, 0 -- 7, 1 -- 7 and 2 -- 7; the link edges run along the boundary.
    CHECK(graph.segments.size() == 9);
    int with_7 = 0;
    for (const StraightSegment& s : graph.segments) {
        CHECK(s.a != s.b);
        const auto& e = h.emb.edges[s.edge];
        CHECK(graph.nodes[s.a].vertex == e[s.sigma_a == 0.0 ? 0 : 1]);
        if (e[1] == 7) ++with_7;
    }
    CHECK(with_7 == 3);
}

TEST_CASE("removal star graph: a half-disk puts v on its new edge", "[simplify][removal]") {
    const Surface s = removal_test::half_disk_fan();
    CoarseMesh mesh(s);
    mesh.mark_feature_edges(60.0);
    Embedding emb;
    emb.init_identity(s, mesh.triangle_capacity());
    std::vector<Fan> fans;
    StarScratch star;
    bool crease_line = false;
    std::string why;
    REQUIRE(classify_star(mesh, 0, false, fans, crease_line, why, star) == VertexClass::FeatureLine);
    PolarMap map;
    REQUIRE(polar_map(mesh.positions(), 0, fans[0], 1.0, map, why));
    StarGraph graph;
    StarGraphScratch scratch;
    const std::unordered_map<int32_t, double> params{{0, 0.5}};
    graph.clear(s.vertices.size());
    REQUIRE(gather_star_nodes(mesh, emb, 0, fans[0], map.q, true, &params, graph, scratch, why));
    REQUIRE(graph.nodes.size() == 6);  // five corners and v, fixed on the new edge
    const StarNode& v = graph.nodes[5];
    CHECK_FALSE(v.free);
    CHECK(v.poly_edge == 4);
    CHECK(v.pos == Vec2{0.0, 0.0});
    CHECK(v.poly_t == Approx(0.5));
    CHECK(v.edge_lo == 1);
    CHECK(v.edge_hi == 5);
    CHECK(v.edge_s == 0.5);
    CHECK(graph.side_nodes[4] == std::vector<int32_t>{5});
    CHECK(graph.free_vertices.empty());
    REQUIRE(gather_straight_segments(emb, 0, fans[0], graph, scratch, why));
    CHECK(graph.segments.size() == 3);  // the interior spokes; the feature edges are on the boundary

    // Every vertex on the new edge needs its parameter.
    const std::unordered_map<int32_t, double> none;
    graph.clear(s.vertices.size());
    CHECK_FALSE(gather_star_nodes(mesh, emb, 0, fans[0], map.q, true, &none, graph, scratch, why));
    CHECK(why == "internal: vertex on the new feature edge without parameter");
}
