// phi's distortion per piece (simplify/distortion.h) and the cost term built on it.
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/check.h"
#include "bpm/parametrization.h"
#include "fixtures_surfaces.h"
#include "simplify/distortion.h"

using namespace bpm;

namespace {

// One coarse triangle (0,0,0) (1,0,0) (0,1,0) cut into two pieces of equal parameter
// area at the midpoint of edge c1-c2; phi sends that midpoint to `mid`, so the two
// pieces' images have areas mid.y / 2 and mid.x / 2 (sum 1/2 when mid.x + mid.y = 1).
Parametrization two_pieces(const Vec3& mid, bool flip_original) {
    Parametrization p;
    p.coarse.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    p.coarse.triangles = {{0, 1, 2}};
    p.coarse.patches = {0};
    p.original.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, mid};
    p.original.triangles = {flip_original ? Tri{0, 2, 1} : Tri{0, 1, 2}};
    p.original.patches = {0};
    p.node_offsets = {0, 4};
    p.node_barycentric = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0.5, 0.5}};
    p.node_image = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, mid};
    p.piece_offsets = {0, 2};
    p.pieces = {{0, 1, 3}, {0, 3, 2}};
    p.piece_original_triangle = {0, 0};
    // What the structural guard of the checks reads (not a consistent phi: the measures
    // use only the positions above).
    p.coarse_vertex_origin = {0, 1, 2};
    p.node_kind = {NodeKind::CoarseCorner, NodeKind::CoarseCorner, NodeKind::CoarseCorner, NodeKind::OriginalVertex};
    p.node_original_vertex = {0, 1, 2, 3};
    p.node_original_edge.assign(4, {-1, -1});
    p.node_edge_parameter.assign(4, std::nan(""));
    return p;
}

}  // namespace

TEST_CASE("distortion: the identity map squeezes nothing and turns nothing", "[distortion]") {
    const Parametrization p = make_identity_parametrization(fixtures::cube(2));
    const std::vector<Vec3> normals = detail::unit_normals(p.original);
    std::vector<detail::PieceDistortion> d;
    for (int32_t t = 0; t < p.num_coarse_triangles(); ++t) {
        detail::triangle_distortion(p, t, normals, d);
        REQUIRE(d.size() == 1);
        CHECK(d[0].squeeze == Approx(1.0));
        CHECK(d[0].normal_deviation == Approx(0.0).margin(1e-6));
        CHECK_FALSE(d[0].degenerate);
    }
}

TEST_CASE("distortion: squeeze is relative to the triangle's own stretch, both ways", "[distortion]") {
    // Images 0.05 and 0.45 for parameter areas 0.25 and 0.25; the triangle's ratio is 1.
    std::vector<detail::PieceDistortion> d;
    detail::triangle_distortion(two_pieces({0.9, 0.1, 0}, false), 0, {}, d);
    REQUIRE(d.size() == 2);
    CHECK(d[0].squeeze == Approx(5.0));
    CHECK(d[1].squeeze == Approx(0.45 / 0.25));
    CHECK(d[0].normal_deviation == Approx(0.0).margin(1e-6));
    // An original triangle oriented against the coarse one: turned by 180 degrees.
    detail::triangle_distortion(two_pieces({0.9, 0.1, 0}, true), 0, {}, d);
    CHECK(d[0].normal_deviation == Approx(180.0));
    // A piece whose image has no area has no squeeze.
    detail::triangle_distortion(two_pieces({1, 0, 0}, false), 0, {}, d);
    CHECK(d[0].degenerate);
    CHECK_FALSE(d[1].degenerate);
}

TEST_CASE("distortion: bpm::check_distortion reports percentiles, maxima and folds", "[distortion]") {
    const CheckResult r = check_distortion(two_pieces({0.9, 0.1, 0}, true));
    INFO(r.summary);
    CHECK(r.passed);
    CHECK(r.count("pieces") == 2);
    CHECK(r.count("pieces_turned_over_90_degrees") == 2);
    CHECK(r.count("pieces_turned_over_60_degrees") == 2);
    REQUIRE(r.worst);
    CHECK(r.worst->value == Approx(180.0));
    bool found = false;
    for (const WorstValue& m : r.measures)
        if (m.name == "area_squeeze_max") {
            found = true;
            CHECK(m.value == Approx(5.0));
            CHECK(m.ids.size() == 2);
        }
    CHECK(found);
    const CheckResult identity = check_distortion(make_identity_parametrization(fixtures::cube(1)));
    CHECK(identity.count("pieces_turned_over_60_degrees") == 0);
    CHECK(identity.worst->value == Approx(0.0).margin(1e-6));
}

TEST_CASE("distortion: the cost term is 0 up to 45 degrees, grows, and sends folds behind", "[distortion]") {
    CHECK(detail::distortion_cost(30, 1, 90) == 0);
    CHECK(detail::distortion_cost(45, 1, 90) == 0);
    CHECK(detail::distortion_cost(90, 1, 90) == Approx(1e-3));
    CHECK(detail::distortion_cost(67.5, 2, 90) == Approx(2e-3 * 0.25));
    CHECK(detail::distortion_cost(91, 1, 90) > 1.0);
    CHECK(detail::distortion_cost(179, 0, 180) == 0);  // off
    // A fold limit works without a weight (--fold-limit alone was a silent no-op).
    CHECK(detail::distortion_cost(179, 0, 90) == 1.0);
    CHECK(detail::distortion_cost(30, 0, 20) == 1.0);
    CHECK(detail::distortion_cost(89, 0, 90) == 0);
    CHECK(detail::distortion_cost(179, 1, 180) < 0.01);  // no fold limit: the quadratic part only
}

TEST_CASE("distortion: the fold term is 0 up to 90 degrees and grows linearly to weight * 1e-3 at 180",
          "[distortion]") {
    CHECK(detail::fold_cost(45, 1) == 0);
    CHECK(detail::fold_cost(90, 1) == 0);  // perpendicular is not a fold yet
    CHECK(detail::fold_cost(135, 1) == Approx(0.5e-3));
    CHECK(detail::fold_cost(180, 2) == Approx(2e-3));
    CHECK(detail::fold_cost(179, 0) == 0);  // off
    // Smaller than any fold limit's + 1: a removal of clearly smaller error still goes first.
    CHECK(detail::fold_cost(180, 1) < 0.01);
}
