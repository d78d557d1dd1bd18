// floater_repair (simplify/floater_repair.h): free nodes as convex combinations of
// their neighbours, the boundary fixed.
#include <catch2/catch.hpp>

#include "bpm/predicates.h"
#include "removal_test_fans.h"
#include "simplify/coarse_mesh.h"
#include "simplify/floater_repair.h"
#include "simplify/polar_map.h"
#include "simplify/star_graph.h"

using namespace bpm;
using namespace bpm::detail;

namespace {

struct Gathered {
    Surface s;
    CoarseMesh mesh;
    Embedding emb;
    std::vector<Fan> fans;
    PolarMap map;
    StarGraph graph;
    explicit Gathered(Surface surface) : s(std::move(surface)), mesh(s) {
        emb.init_identity(s, mesh.triangle_capacity());
        StarScratch star;
        StarGraphScratch scratch;
        bool crease_line = false;
        std::string why;
        REQUIRE(classify_star(mesh, 0, false, fans, crease_line, why, star) == VertexClass::Regular);
        REQUIRE(polar_map(mesh.positions(), 0, fans[0], 1.0, map, why));
        graph.clear(s.vertices.size());
        REQUIRE(gather_star_nodes(mesh, emb, 0, fans[0], map.q, true, nullptr, graph, scratch, why));
        REQUIRE(gather_straight_segments(emb, 0, fans[0], graph, scratch, why));
    }
};

}  // namespace

TEST_CASE("removal Floater repair: a symmetric star puts its centre back at the centre", "[simplify][removal]") {
    Gathered g(removal_test::hexagon_fan());
    REQUIRE(g.graph.nodes.size() == 7);
    StarNode& v = g.graph.nodes[6];
    REQUIRE(v.free);
    v.pos = {0.6, 0.2};  // as if straightening had moved it off
    const std::vector<StarNode> before = g.graph.nodes;
    std::string why;
    REQUIRE(floater_repair(g.emb, g.graph, why));
    CHECK(v.pos[0] == Approx(0.0).margin(1e-12));
    CHECK(v.pos[1] == Approx(0.0).margin(1e-12));
    for (int i = 0; i < 6; ++i) CHECK(g.graph.nodes[i].pos == before[i].pos);
}

TEST_CASE("removal Floater repair: a planar off-centre star keeps its centre (linear precision)",
          "[simplify][removal]") {
    // Mean value weights reproduce linear functions: in a flat star the centre is the
    // weighted mean of its neighbours where the polar map put them, at the origin.
    Surface s = removal_test::hexagon_fan();
    s.vertices[0] = {0.5, 0.1, 0.0};
    Gathered g(std::move(s));
    StarNode& v = g.graph.nodes[6];
    v.pos = {0.3, -0.2};
    std::string why;
    REQUIRE(floater_repair(g.emb, g.graph, why));
    CHECK(v.pos[0] == Approx(0.0).margin(1e-9));
    CHECK(v.pos[1] == Approx(0.0).margin(1e-9));
    const int32_t n = static_cast<int32_t>(g.map.q.size());
    for (int32_t i = 0; i < n; ++i) CHECK(orient2d(g.map.q[i], g.map.q[mod(i + 1, n)], v.pos) > 0);
}

TEST_CASE("removal Floater repair: a free node with a single neighbour is refused", "[simplify][removal]") {
    Gathered g(removal_test::hexagon_fan());
    g.graph.segments.resize(1);  // only one spoke left
    const Vec2 before = g.graph.nodes[6].pos;
    std::string why;
    CHECK_FALSE(floater_repair(g.emb, g.graph, why));
    CHECK(why == "free node with fewer than two neighbours");
    CHECK(g.graph.nodes[6].pos == before);
}
