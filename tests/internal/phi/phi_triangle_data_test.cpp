// The editable per-triangle form of phi (phi/phi_triangle_data.h): loading every coarse
// triangle and appending them in order gives back the same arrays, bit for bit, and a
// triangle stored with different content changes only its own CSR ranges.
#include <cstring>
#include <vector>

#include <catch2/catch.hpp>

#include "fixtures_phi.h"
#include "phi/phi_triangle_data.h"

using namespace bpm;
using bpm::detail::PhiTriangleData;

namespace {

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

bool same_phi(const Parametrization& a, const Parametrization& b) {
    return a.node_offsets == b.node_offsets && a.piece_offsets == b.piece_offsets &&
           same_bits(a.node_barycentric, b.node_barycentric) && same_bits(a.node_image, b.node_image) &&
           a.node_kind == b.node_kind && a.node_original_vertex == b.node_original_vertex &&
           a.node_original_edge == b.node_original_edge && same_bits(a.node_edge_parameter, b.node_edge_parameter) &&
           a.pieces == b.pieces && a.piece_original_triangle == b.piece_original_triangle;
}

}  // namespace

TEST_CASE("phi triangle data: load and append of every triangle rebuild phi bit for bit", "[internal][phi]") {
    // A height field has all three node kinds (edge crossings with NaN-free parameters,
    // vertices on coarse edges, corners) and NaN edge parameters elsewhere.
    const Parametrization p = test::make_height_field(6, 2, test::default_height);
    Parametrization q = p;
    std::vector<PhiTriangleData> tris;
    for (int32_t t = 0; t < p.num_coarse_triangles(); ++t) tris.push_back(detail::load_phi_triangle(p, t));
    detail::clear_phi(q);
    CHECK(q.num_nodes() == 0);
    CHECK(q.node_offsets == std::vector<int64_t>{0});
    for (const PhiTriangleData& t : tris) detail::append_phi_triangle(q, t);
    CHECK(same_phi(p, q));
    bool has_crossing = false;
    for (NodeKind k : p.node_kind) has_crossing |= k == NodeKind::EdgeCrossing;
    CHECK(has_crossing);
}

TEST_CASE("phi triangle data: an edited triangle moves only the ranges after it", "[internal][phi]") {
    const Parametrization p = test::make_subdivided_octahedron(1);
    PhiTriangleData t1 = detail::load_phi_triangle(p, 1);
    const size_t nodes = t1.num_nodes(), pieces = t1.num_pieces();
    // One more node and piece: split piece 0 at its centroid (geometry does not matter here).
    const Tri old = t1.pieces[0];
    const int32_t c = t1.add_node({1.0 / 3, 1.0 / 3, 1.0 / 3}, {0, 0, 0}, NodeKind::OriginalVertex, 0, {-1, -1}, 0.0);
    t1.pieces[0] = {old[0], old[1], c};
    t1.add_piece({old[1], old[2], c}, t1.piece_original_triangle[0]);
    REQUIRE(t1.num_nodes() == nodes + 1);
    REQUIRE(t1.num_pieces() == pieces + 1);

    Parametrization q = p;
    detail::clear_phi(q);
    for (int32_t t = 0; t < p.num_coarse_triangles(); ++t)
        detail::append_phi_triangle(q, t == 1 ? t1 : detail::load_phi_triangle(p, t));
    for (size_t t = 0; t <= size_t(p.num_coarse_triangles()); ++t) {
        CHECK(q.node_offsets[t] == p.node_offsets[t] + (t >= 2 ? 1 : 0));
        CHECK(q.piece_offsets[t] == p.piece_offsets[t] + (t >= 2 ? 1 : 0));
    }
    const PhiTriangleData back = detail::load_phi_triangle(q, 1);
    CHECK(back.pieces == t1.pieces);
    CHECK(back.barycentric == t1.barycentric);
    const PhiTriangleData last = detail::load_phi_triangle(q, p.num_coarse_triangles() - 1);
    CHECK(last.pieces == detail::load_phi_triangle(p, p.num_coarse_triangles() - 1).pieces);
}
