// The export of the simplifier's phi (simplify/export_phi.h), tested directly: before any
// removal it is the identity; after removals it passes the format and bijectivity checks,
// over several chunks, and is the same with one thread and with two.
#include <algorithm>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/check.h"
#include "fixtures_surfaces.h"
#include "simplify/coarse_mesh.h"
#include "simplify/embedding.h"
#include "simplify/export_phi.h"
#include "simplify/overlay.h"
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

namespace {

// phi of coarse triangle t as the overlay makes it (build_triangle_graph, compute_faces,
// triangulate_faces), in the export's form: nodes in graph order, pieces as triangulated.
void overlay_phi(const LiveState& state, int32_t t, std::vector<Vec3>& bary,
                 std::vector<Vec3>& image, std::vector<NodeKind>& kind, std::vector<int32_t>& vertex,
                 std::vector<Tri>& pieces, std::vector<int32_t>& piece_triangle) {
    TriangleGraph graph;
    build_triangle_graph(state.mesh, state.embedding, t, graph);
    std::vector<OverlayFace> faces;
    REQUIRE(compute_faces(graph, state.embedding, state.sign, faces));
    REQUIRE(triangulate_faces(graph, state.embedding, state.sign, faces, pieces, piece_triangle));
    bary.clear();
    image.clear();
    kind.clear();
    vertex.clear();
    for (const GraphNode& g : graph.nodes) {
        bary.push_back(g.bary);
        image.push_back(node_image(g, state.embedding));
        kind.push_back(g.kind);
        vertex.push_back(g.kind == NodeKind::EdgeCrossing ? -1 : g.vertex);
    }
}

}  // namespace

TEST_CASE("export of phi: triangles with nothing on them are exported as the overlay makes them",
          "[internal][simplify]") {
    // The export appends a coarse triangle with nothing on its sides and nothing inside
    // (every triangle before any removal, those away from the removals after) directly as
    // its corners and one piece. That must be what the overlay makes of it, also where the
    // input's orientation is reversed (orientation sign -1): a torus with every third
    // triangle stored the other way round, after a few removals.
    Surface original = fixtures::torus(32, 20);
    for (size_t t = 0; t < original.triangles.size(); t += 3) std::swap(original.triangles[t][1], original.triangles[t][2]);
    LiveState state(original);
    REQUIRE(std::count(state.sign.begin(), state.sign.end(), int8_t(-1)) > 0);
    REQUIRE(state.remove_some(40, 7) >= 20);
    const Parametrization out = state.exported(original);
    std::vector<int32_t> alive;
    state.mesh.alive_triangles(alive);
    REQUIRE(int64_t(alive.size()) == out.num_coarse_triangles());
    std::vector<Vec3> bary, image;
    std::vector<NodeKind> kind;
    std::vector<int32_t> vertex, piece_triangle;
    std::vector<Tri> pieces;
    size_t bare = 0, flipped_bare = 0;
    for (size_t i = 0; i < alive.size(); ++i) {
        overlay_phi(state, alive[i], bary, image, kind, vertex, pieces, piece_triangle);
        const int64_t n0 = out.node_offsets[i], n1 = out.node_offsets[i + 1];
        const int64_t p0 = out.piece_offsets[i], p1 = out.piece_offsets[i + 1];
        REQUIRE(size_t(n1 - n0) == bary.size());
        REQUIRE(size_t(p1 - p0) == pieces.size());
        for (size_t k = 0; k < bary.size(); ++k) {
            CHECK(out.node_barycentric[size_t(n0) + k] == bary[k]);
            CHECK(out.node_image[size_t(n0) + k] == image[k]);
            CHECK(out.node_kind[size_t(n0) + k] == kind[k]);
            CHECK(out.node_original_vertex[size_t(n0) + k] == vertex[k]);
        }
        for (size_t k = 0; k < pieces.size(); ++k) {
            CHECK(out.pieces[size_t(p0) + k] == pieces[k]);
            CHECK(out.piece_original_triangle[size_t(p0) + k] == piece_triangle[k]);
        }
        if (bary.size() == 3) {
            ++bare;
            flipped_bare += state.sign[size_t(piece_triangle[0])] < 0;
        }
    }
    CHECK(bare > 100);
    CHECK(flipped_bare > 10);
    CHECK(bare < alive.size());  // and triangles that went through the overlay
}
