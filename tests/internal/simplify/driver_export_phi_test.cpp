// The export of the simplifier's phi (simplify/export_phi.h), tested directly: before any
// removal it is the identity; after removals it passes the format and bijectivity checks,
// over several chunks, and is the same with one thread and with two.
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/check.h"
#include "fixtures_surfaces.h"
#include "simplify/coarse_mesh.h"
#include "simplify/embedding.h"
#include "simplify/export_phi.h"
#include "simplify/planning_pool.h"
#include "simplify/vertex_removal.h"
#include "simplifier_state_fixture.h"

using namespace bpm;
using namespace bpm::detail;
using bpm::detail::test::LiveState;

TEST_CASE("export of phi: before any removal, the identity", "[internal][simplify]") {
    const Surface original = fixtures::cube();
    LiveState state(original);
    PlanningPool pool(1);
    Parametrization out;
    const double deviation = export_parametrization(original, state.mesh, state.embedding, state.sign, pool, out);
    CHECK(deviation == 0.0);
    REQUIRE(out.num_coarse_triangles() == original.num_triangles());
    CHECK(out.num_nodes() == 3 * int64_t(original.num_triangles()));
    CHECK(out.num_pieces() == int64_t(original.num_triangles()));
    for (int64_t n = 0; n < out.num_nodes(); ++n) {
        CHECK(out.node_kind[n] == NodeKind::CoarseCorner);
        CHECK(out.node_image[n] == original.vertices[out.node_original_vertex[n]]);
    }
    CHECK(check_format(out).passed);
    CHECK(check_bijectivity(out).passed);
}

TEST_CASE("export of phi: after removals, valid and the same for one and two threads", "[internal][simplify]") {
    // 1280 triangles: three chunks of the export.
    const Surface original = fixtures::torus(32, 20);
    LiveState state(original);
    REQUIRE(state.remove_some(40, 7) >= 20);
    Parametrization one, two;
    double deviation_one = 0.0, deviation_two = 0.0;
    {
        PlanningPool pool(1);
        deviation_one = export_parametrization(original, state.mesh, state.embedding, state.sign, pool, one);
    }
    {
        PlanningPool pool(2);
        deviation_two = export_parametrization(original, state.mesh, state.embedding, state.sign, pool, two);
    }
    CHECK(deviation_one > 0.0);
    CHECK(deviation_one == deviation_two);
    CHECK(one.num_coarse_triangles() == state.mesh.num_alive_triangles());
    CHECK(one.node_offsets == two.node_offsets);
    CHECK(one.piece_offsets == two.piece_offsets);
    CHECK(one.node_image == two.node_image);
    CHECK(one.pieces == two.pieces);
    CHECK(one.piece_original_triangle == two.piece_original_triangle);
    CHECK(check_format(one).passed);
    CHECK(check_bijectivity(one).passed);
}

namespace {

// Exports phi of `original` after a few removals, compacts the mesh and the embedding as
// the simplifier does before its export (CoarseMesh::shrink_to_fit, Embedding::freeze),
// checks that crossings() and content() read the same as before and that phi is exported
// the same; returns the number of original vertices located on coarse edges.
size_t check_compacted_export(const Surface& original, int removals, int stride) {
    LiveState state(original);
    REQUIRE(state.remove_some(removals, stride) >= removals / 2);
    const Embedding& e = state.embedding;
    const int32_t num_edges = static_cast<int32_t>(e.edges.size());
    std::vector<std::vector<Crossing>> paths_before;
    size_t crossings_before = 0;
    for (int32_t k = 0; k < num_edges; ++k) {
        const auto c = e.crossings(k);
        paths_before.emplace_back(c.begin(), c.end());
        crossings_before += c.size();
    }
    REQUIRE(crossings_before > 0);
    // The content of every coarse edge, with its vertices.
    size_t on_edges = 0;
    auto contents = [&](const Embedding& emb) {
        std::vector<std::vector<int32_t>> out;
        on_edges = 0;
        const int32_t nv = original.num_vertices();
        for (int32_t a = 0; a < nv; ++a)
            for (int32_t b = a + 1; b < nv; ++b) {
                EdgeContentView view;
                if (!emb.content(a, b, view)) continue;
                std::vector<int32_t> row{a, b, int32_t(view.vertices.size())};
                row.insert(row.end(), view.vertices.begin(), view.vertices.end());
                row.insert(row.end(), view.crossing_edges.begin(), view.crossing_edges.end());
                out.push_back(row);
                on_edges += view.vertices.size();
            }
        return out;
    };
    const auto contents_before = contents(e);
    REQUIRE(!contents_before.empty());
    const size_t on_edges_before = on_edges;
    PlanningPool pool(1);
    Parametrization before, after;
    const double deviation_before = export_parametrization(original, state.mesh, e, state.sign, pool, before);
    state.mesh.shrink_to_fit();
    state.embedding.freeze();
    REQUIRE(e.frozen());
    CHECK(e.path.empty());
    CHECK(e.edge_content.size() == 0);
    for (int32_t k = 0; k < num_edges; ++k) {
        const auto c = e.crossings(k);
        REQUIRE(c.size() == paths_before[size_t(k)].size());
        for (size_t j = 0; j < c.size(); ++j) {
            CHECK(c[j].a == paths_before[size_t(k)][j].a);
            CHECK(c[j].b == paths_before[size_t(k)][j].b);
            CHECK(c[j].s == paths_before[size_t(k)][j].s);
            CHECK(c[j].sigma == paths_before[size_t(k)][j].sigma);
        }
    }
    CHECK(contents(e) == contents_before);
    const double deviation_after = export_parametrization(original, state.mesh, e, state.sign, pool, after);
    CHECK(deviation_after == deviation_before);
    CHECK(after.coarse.triangles == before.coarse.triangles);
    CHECK(after.node_offsets == before.node_offsets);
    CHECK(after.node_barycentric == before.node_barycentric);
    CHECK(after.node_image == before.node_image);
    CHECK(after.node_kind == before.node_kind);
    CHECK(after.node_original_vertex == before.node_original_vertex);
    CHECK(after.node_original_edge == before.node_original_edge);
    CHECK(after.piece_offsets == before.piece_offsets);
    CHECK(after.pieces == before.pieces);
    CHECK(after.piece_original_triangle == before.piece_original_triangle);
    return on_edges_before;
}

}  // namespace

TEST_CASE("export of phi: the same after the mesh and the embedding are compacted", "[internal][simplify]") {
    // Before phi is exported the simplifier compacts the coarse mesh and stores the paths
    // and the edge contents flat; the export reads them through crossings() and content().
    // A torus (crossings only) and a cube whose crease vertices end up on coarse edges.
    check_compacted_export(fixtures::torus(32, 20), 40, 7);
    CHECK(check_compacted_export(fixtures::cube(6), 60, 3) > 0);
}
