// locate_free_nodes, cut_segments, transfer_deviation (simplify/phi_transfer.h): the
// original surface of a fan moved onto its new triangles.
#include <catch2/catch.hpp>

#include "removal_test_fans.h"
#include "simplify/coarse_mesh.h"
#include "simplify/phi_transfer.h"
#include "simplify/polar_map.h"

using namespace bpm;
using namespace bpm::detail;

namespace {

// Vertex 0 of a fan surface up to its star graph and new triangulation.
struct Planned {
    Surface s;
    CoarseMesh mesh;
    Embedding emb;
    std::vector<Fan> fans;
    PolarMap map;
    FanTriangulation tri;
    StarGraph graph;
    std::vector<std::array<double, 4>> boxes;
    explicit Planned(Surface surface) : s(std::move(surface)), mesh(s) {
        emb.init_identity(s, mesh.triangle_capacity());
        StarScratch star;
        EarScratch ears;
        StarGraphScratch scratch;
        bool crease_line = false;
        std::string why;
        REQUIRE(classify_star(mesh, 0, false, fans, crease_line, why, star) == VertexClass::Regular);
        REQUIRE(polar_map(mesh.positions(), 0, fans[0], 1.0, map, why));
        REQUIRE(retriangulate_fan(mesh, fans[0], map, {}, tri, ears, why));
        graph.clear(s.vertices.size());
        REQUIRE(gather_star_nodes(mesh, emb, 0, fans[0], map.q, true, nullptr, graph, scratch, why));
        REQUIRE(gather_straight_segments(emb, 0, fans[0], graph, scratch, why));
    }
};

}  // namespace

TEST_CASE("removal phi transfer: the centre of a lifted hexagon moves onto the new triangles",
          "[simplify][removal]") {
    Planned p(removal_test::fan_surface({0, 60, 120, 180, 240, 300}, {1, 1, 1, 1, 1, 1}, true, 0.5));
    std::string why;
    REQUIRE(locate_free_nodes(p.emb, p.fans[0], p.map.q, p.tri, true, p.graph, p.boxes, why));
    const StarNode& v = p.graph.nodes[6];
    REQUIRE(v.free);
    REQUIRE(v.vertex == 0);
    // The origin is on a long diagonal of the regular hexagon, or inside a new triangle.
    if (v.diagonal >= 0) {
        CHECK(v.new_triangle < 0);
        CHECK(v.edge_s > 0.0);
        CHECK(v.edge_s < 1.0);
    } else {
        REQUIRE(v.new_triangle >= 0);
        CHECK(v.bary[0] + v.bary[1] + v.bary[2] == Approx(1.0));
        for (int k = 0; k < 3; ++k) CHECK(v.bary[k] > 0.0);
    }

    RecutEdges cuts;
    REQUIRE(cut_segments(p.emb, p.fans[0], p.map.q, p.tri, p.graph, cuts, why));
    REQUIRE(cuts.cut_begin.size() == p.graph.segments.size() + 1);
    CHECK(cuts.cut_begin.back() == int32_t(cuts.crossings.size()));
    // Every cut is of its segment's edge, strictly inside it, in order along it.
    for (size_t i = 0; i + 1 < cuts.cut_begin.size(); ++i)
        for (int32_t c = cuts.cut_begin[i]; c < cuts.cut_begin[i + 1]; ++c) {
            const NewCrossing& nc = cuts.crossings[c];
            CHECK(nc.edge == p.graph.segments[i].edge);
            CHECK(nc.lambda > 0.0);
            CHECK(nc.lambda < 1.0);
            CHECK(nc.lo < nc.hi);
            if (c > cuts.cut_begin[i]) CHECK(cuts.crossings[c - 1].lambda < nc.lambda);
        }
    // The regular hexagon goes onto a regular hexagon: the centre's image is the origin,
    // 0.5 below it.
    CHECK(transfer_deviation(p.mesh.positions(), p.emb, p.fans[0], p.tri, p.graph, cuts) == Approx(0.5));
}

TEST_CASE("removal phi transfer: a flat star keeps phi the identity", "[simplify][removal]") {
    Surface s = removal_test::dented_fan();  // non-convex: the layout goes onto the circle
    Planned p(std::move(s));
    std::string why;
    REQUIRE(locate_free_nodes(p.emb, p.fans[0], p.map.q, p.tri, true, p.graph, p.boxes, why));
    RecutEdges cuts;
    REQUIRE(cut_segments(p.emb, p.fans[0], p.map.q, p.tri, p.graph, cuts, why));
    // On the circle the layout is not the star's own shape: the centre moves off.
    CHECK(transfer_deviation(p.mesh.positions(), p.emb, p.fans[0], p.tri, p.graph, cuts) > 0.0);

    Planned flat(removal_test::hexagon_fan());
    REQUIRE(locate_free_nodes(flat.emb, flat.fans[0], flat.map.q, flat.tri, true, flat.graph, flat.boxes, why));
    REQUIRE(cut_segments(flat.emb, flat.fans[0], flat.map.q, flat.tri, flat.graph, cuts, why));
    CHECK(transfer_deviation(flat.mesh.positions(), flat.emb, flat.fans[0], flat.tri, flat.graph, cuts) ==
          Approx(0.0).margin(1e-12));
}

TEST_CASE("removal phi transfer: a free node outside the polygon is refused", "[simplify][removal]") {
    Planned p(removal_test::hexagon_fan());
    p.graph.nodes[6].pos = {5.0, 5.0};
    std::string why;
    CHECK_FALSE(locate_free_nodes(p.emb, p.fans[0], p.map.q, p.tri, true, p.graph, p.boxes, why));
    CHECK(why == "an original vertex would leave the star");
    // Without the check it is still not in any new triangle.
    CHECK_FALSE(locate_free_nodes(p.emb, p.fans[0], p.map.q, p.tri, false, p.graph, p.boxes, why));
    CHECK(why == "cannot locate an original vertex in the new triangles");
}
