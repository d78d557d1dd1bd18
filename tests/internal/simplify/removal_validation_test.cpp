// assign_pieces, check_new_triangles (simplify/removal_validation.h): the exact check
// of a fan's transfer.
#include <catch2/catch.hpp>

#include "removal_test_fans.h"
#include "simplify/coarse_mesh.h"
#include "simplify/polar_map.h"
#include "simplify/removal_validation.h"

using namespace bpm;
using namespace bpm::detail;

namespace {

// Vertex 0 of a fan surface through the transfer's cost: located, re-cut.
struct Transferred {
    Surface s;
    CoarseMesh mesh;
    Embedding emb;
    std::vector<int8_t> sign;
    std::vector<Vec3> normals, new_normals;
    std::vector<Fan> fans;
    PolarMap map;
    FanTriangulation tri;
    StarGraph graph;
    RecutEdges cuts;
    explicit Transferred(Surface surface) : s(std::move(surface)), mesh(s), sign(s.triangles.size(), 1) {
        emb.init_identity(s, mesh.triangle_capacity());
        for (const Tri& t : s.triangles) normals.push_back(triangle_normal(s.vertices[t[0]], s.vertices[t[1]], s.vertices[t[2]]));
        StarScratch star;
        EarScratch ears;
        StarGraphScratch scratch;
        std::vector<std::array<double, 4>> boxes;
        bool crease_line = false;
        std::string why;
        REQUIRE(classify_star(mesh, 0, false, fans, crease_line, why, star) == VertexClass::Regular);
        REQUIRE(polar_map(mesh.positions(), 0, fans[0], 1.0, map, why));
        REQUIRE(retriangulate_fan(mesh, fans[0], map, {}, tri, ears, why));
        for (const auto& t : tri.triangles) {
            const auto& l = fans[0].link;
            new_normals.push_back(triangle_normal(s.vertices[l[t[0]]], s.vertices[l[t[1]]], s.vertices[l[t[2]]]));
        }
        graph.clear(s.vertices.size());
        REQUIRE(gather_star_nodes(mesh, emb, 0, fans[0], map.q, true, nullptr, graph, scratch, why));
        REQUIRE(gather_straight_segments(emb, 0, fans[0], graph, scratch, why));
        REQUIRE(locate_free_nodes(emb, fans[0], map.q, tri, true, graph, boxes, why));
        REQUIRE(cut_segments(emb, fans[0], map.q, tri, graph, cuts, why));
    }
    FanTransfer view(const TransferPieces& pieces) const {
        return {emb, sign, normals, fans[0], tri, new_normals, graph, cuts, pieces};
    }
};

}  // namespace

TEST_CASE("removal validation: a lifted irregular hexagon's transfer is valid", "[simplify][removal]") {
    // No two link vertices opposite: the centre is on no diagonal.
    Transferred t(removal_test::fan_surface({0, 50, 110, 170, 240, 290}, {1, 1, 1, 1, 1, 1}, true, 0.5));
    TransferPieces pieces;
    std::array<int32_t, 2> along{-1, -1};
    std::string why;
    const bool assigned = assign_pieces(t.fans[0], t.tri, t.graph, t.cuts, pieces, along, why);
    INFO(why);
    REQUIRE(assigned);
    CHECK(along == std::array<int32_t, 2>{-1, -1});
    // A segment with k cuts is k + 1 pieces; one path edit per segment.
    CHECK(pieces.pieces.size() == t.graph.segments.size() + t.cuts.crossings.size());
    REQUIRE(pieces.path_edits.size() == t.graph.segments.size());
    for (size_t i = 0; i < t.graph.segments.size(); ++i)
        CHECK(pieces.path_edits[i].middle.size() == size_t(t.cuts.cut_begin[i + 1] - t.cuts.cut_begin[i]));
    for (const Piece& p : pieces.pieces) {
        CHECK(p.triangle >= 0);
        CHECK(p.triangle < int32_t(t.tri.triangles.size()));
    }

    TriangleCheck check;
    double min_cosine = 1.0;
    const int32_t n = static_cast<int32_t>(t.tri.triangles.size());
    REQUIRE(check_new_triangles(t.view(pieces), 0, n, check, min_cosine, why));
    // The new triangles lie in z = 0; every original triangle has a face in one of them.
    double expected = 1.0;
    for (const Vec3& normal : t.normals) expected = std::min(expected, normal[2]);
    CHECK(min_cosine == Approx(expected));
    CHECK(min_cosine < 0.99);
    // In two ranges, as on two threads: the same result.
    double first = 1.0, second = 1.0;
    TriangleCheck other;
    REQUIRE(check_new_triangles(t.view(pieces), 0, n / 2, check, first, why));
    REQUIRE(check_new_triangles(t.view(pieces), n / 2, n, other, second, why));
    CHECK(std::min(first, second) == min_cosine);
}

TEST_CASE("removal validation: an original edge along a diagonal is no piece", "[simplify][removal]") {
    // A regular hexagon: its centre lies on a long diagonal, and so do two spokes. Until
    // issue 19 (quality) such a transfer was refused ("original edge along a new edge"),
    // which froze flat regularly meshed regions; the runs along the diagonal are now, like
    // runs along a feature edge, no pieces: their ends lie on the two triangles' common side.
    Transferred t(removal_test::fan_surface({0, 60, 120, 180, 240, 300}, {1, 1, 1, 1, 1, 1}, true, 0.5));
    TransferPieces pieces;
    std::array<int32_t, 2> along{-1, -1};
    std::string why;
    const bool assigned = assign_pieces(t.fans[0], t.tri, t.graph, t.cuts, pieces, along, why);
    INFO(why);
    REQUIRE(assigned);
    CHECK(along == std::array<int32_t, 2>{-1, -1});
    // The centre is on a diagonal; of its six spokes, the two along that diagonal are no pieces.
    int32_t centre_diagonal = -1;
    for (const StarNode& s : t.graph.nodes)
        if (s.free && s.vertex == 0) centre_diagonal = s.diagonal;
    REQUIRE(centre_diagonal >= 0);
    const auto d = t.tri.diagonals[size_t(centre_diagonal)];
    CHECK(std::abs(d[0] - d[1]) == 3);  // opposite corners
    CHECK(pieces.pieces.size() == t.graph.segments.size() + t.cuts.crossings.size() - 2);
    TriangleCheck check;
    double min_cosine = 1.0;
    REQUIRE(check_new_triangles(t.view(pieces), 0, int32_t(t.tri.triangles.size()), check, min_cosine, why));
}

TEST_CASE("removal validation: a segment that skips its cuts is refused", "[simplify][removal]") {
    Transferred t(removal_test::fan_surface({0, 50, 110, 170, 240, 290}, {1, 1, 1, 1, 1, 1}, true, 0.5));
    REQUIRE_FALSE(t.cuts.crossings.empty());
    // Forget the cuts: a segment that crosses a diagonal now has its ends in two
    // triangles that share no piece.
    t.cuts.crossings.clear();
    std::fill(t.cuts.cut_begin.begin(), t.cuts.cut_begin.end(), 0);
    TransferPieces pieces;
    std::array<int32_t, 2> along{-1, -1};
    std::string why;
    CHECK_FALSE(assign_pieces(t.fans[0], t.tri, t.graph, t.cuts, pieces, along, why));
    CHECK(why == "re-cut lost track of an original edge");
}
