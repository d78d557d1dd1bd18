// PhiTriangle is the per-coarse-triangle read view of phi: code that uses it instead
// of the CSR offsets must see exactly its own triangle's nodes and pieces.
#include <catch2/catch.hpp>

#include "bpm/check.h"
#include "bpm/phi_triangle.h"
#include "fixtures_surfaces.h"

using namespace bpm;

namespace {

// Every field the view shows agrees with the CSR slice of triangle t, and the views of
// all triangles together cover every node and piece exactly once, in order.
void require_views_match_csr(const Parametrization& p) {
    REQUIRE(check_format(p).passed);
    int64_t next_node = 0, next_piece = 0;
    for (int32_t t = 0; t < p.num_coarse_triangles(); ++t) {
        const PhiTriangle phi(p, t);
        CHECK(phi.triangle() == t);
        CHECK(phi.corners() == p.coarse.triangles[t]);
        REQUIRE(phi.first_node() == next_node);
        REQUIRE(phi.first_piece() == next_piece);
        REQUIRE(phi.num_nodes() == p.node_offsets[t + 1] - p.node_offsets[t]);
        REQUIRE(phi.num_pieces() == p.piece_offsets[t + 1] - p.piece_offsets[t]);
        for (int64_t i = 0; i < phi.num_nodes(); ++i) {
            const int64_t n = next_node + i;
            CHECK(phi.barycentric(i) == p.node_barycentric[n]);
            CHECK(phi.image(i) == p.node_image[n]);
            CHECK(phi.kind(i) == p.node_kind[n]);
            CHECK(phi.original_vertex(i) == p.node_original_vertex[n]);
            CHECK(phi.original_edge(i) == p.node_original_edge[n]);
            const double s = p.node_edge_parameter[n];
            CHECK((phi.edge_parameter(i) == s || (std::isnan(phi.edge_parameter(i)) && std::isnan(s))));
        }
        for (int64_t j = 0; j < phi.num_pieces(); ++j) {
            const int64_t q = next_piece + j;
            CHECK(phi.piece(j) == p.pieces[q]);
            CHECK(phi.original_triangle(j) == p.piece_original_triangle[q]);
            for (int k = 0; k < 3; ++k) {
                const int64_t n = phi.piece_node(j, k);
                // a piece corner is one of this triangle's own nodes, never a neighbour's
                CHECK(n >= phi.first_node());
                CHECK(n < phi.first_node() + phi.num_nodes());
                CHECK(n == p.node_offsets[t] + p.pieces[q][k]);
            }
        }
        next_node += phi.num_nodes();
        next_piece += phi.num_pieces();
    }
    CHECK(next_node == p.num_nodes());
    CHECK(next_piece == p.num_pieces());
}

}  // namespace

TEST_CASE("the view of a coarse triangle shows its own CSR slice of phi and nothing else", "[phi]") {
    SECTION("identity: three corner nodes and one piece per triangle") {
        const Parametrization p = fixtures::identity_parametrization(fixtures::cube());
        require_views_match_csr(p);
        const PhiTriangle phi(p, 5);
        CHECK(phi.num_nodes() == 3);
        CHECK(phi.num_pieces() == 1);
    }
    SECTION("refined: nodes on coarse edges and inside, triangles of different sizes") {
        require_views_match_csr(fixtures::refined_parametrization(fixtures::two_cubes()));
    }
    SECTION("edge crossings") {
        const Parametrization p = fixtures::flipped_diagonal_parametrization(fixtures::cube());
        require_views_match_csr(p);
        bool crossing = false;
        for (int32_t t = 0; t < p.num_coarse_triangles(); ++t) {
            const PhiTriangle phi(p, t);
            for (int64_t i = 0; i < phi.num_nodes(); ++i)
                if (phi.kind(i) == NodeKind::EdgeCrossing) {
                    crossing = true;
                    CHECK(phi.original_vertex(i) == -1);
                    CHECK(phi.edge_parameter(i) > 0);
                    CHECK(phi.edge_parameter(i) < 1);
                }
        }
        CHECK(crossing);
    }
}
