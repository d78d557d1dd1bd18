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
