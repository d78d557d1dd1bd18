// Smoothing phi by edge relaxation: phi stays a valid bijection, node images stay on the
// original surface (in fact unchanged points of S0), the coarse surface never moves, and
// the refined-triangle quality improves on a real mesh.

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "bpm/check.h"
#include "bpm/errors.h"
#include "bpm/phi_evaluation.h"
#include "bpm/refine.h"
#include "bpm/simplify.h"
#include "bpm/smooth.h"
#include "bpm/surface_io.h"
#include "fixtures_phi.h"
#include "fixtures_surfaces.h"
#include "test_support.h"

using namespace bpm;

namespace {

using test_support::check_text;
using test_support::require_valid_parametrization;

// Every node image is what its kind says (a vertex of S0 or a point on an edge of S0).
double max_image_error(const Parametrization& p) {
    double worst = 0;
    for (int64_t n = 0; n < p.num_nodes(); ++n) worst = std::max(worst, distance(p.node_image[size_t(n)], node_image_from_kind(p, n)));
    return worst;
}

Parametrization simplified(const Surface& s, double ratio) {
    Parametrization p;
    SimplifyOptions o;
    o.target_ratio = ratio;
    simplify(s, o, Context{}, p);
    return p;
}

}  // namespace

TEST_CASE("smoothing keeps phi a bijection on synthetic parametrizations", "[smooth]") {
    struct Case {
        std::string name;
        Parametrization param;
    };
    std::vector<Case> cases;
    cases.push_back({"height field", test::make_height_field(12, 3, test::default_height)});
    cases.push_back({"octahedron", test::make_subdivided_octahedron(3)});
    cases.push_back({"torus simplified", simplified(fixtures::torus(24, 16), 0.15)});
    cases.push_back({"two cubes simplified", simplified(fixtures::two_cubes(5), 0.2)});
    for (Case& c : cases) {
        INFO(c.name);
        const Surface coarse = c.param.coarse;
        const Surface original = c.param.original;
        SmoothOptions o;
        o.iterations = 4;
        o.quality_levels = 2;
        const SmoothResult r = smooth(c.param, o, Context{});
        INFO(r.updates << " updates, " << r.rejected << " rejected, " << r.skipped << " left alone");
        CHECK(c.param.coarse.vertices == coarse.vertices);
        CHECK(c.param.coarse.triangles == coarse.triangles);
        CHECK(c.param.original.vertices == original.vertices);
        CHECK(max_image_error(c.param) == 0.0);
        require_valid_parametrization(c.param);
    }
}

TEST_CASE("smoothing a perfect map changes nothing of substance", "[smooth]") {
    // The octahedron fixture maps each face onto a subdivided face: smoothing must keep
    // it valid and the refined quality must not get worse.
    Parametrization p = test::make_subdivided_octahedron(2, 0.0);
    SmoothOptions o;
    o.quality_levels = 2;
    const SmoothResult r = smooth(p, o, Context{});
    CHECK(r.after.max_aspect_ratio <= r.before.max_aspect_ratio * 1.01);
    require_valid_parametrization(p);
}

TEST_CASE("smoothing slides original vertices along patch borders by arc length", "[smooth]") {
    // The height field's coarse columns are different patches, so its vertical coarse
    // edges are patch borders, and the original vertices on them sit at their projected
    // (y) positions. After smoothing they must sit where the arc length of S0 along the
    // border puts them (before sliding was implemented such pairs were left alone).
    Parametrization p = test::make_height_field(12, 3, test::default_height);
    SmoothOptions o;
    o.quality_levels = 1;
    o.check_levels = 0;  // the sliding itself, also where it makes a refined triangle worse
    const SmoothResult r = smooth(p, o, Context{});
    CHECK(r.slides > 0);
    require_valid_parametrization(p);
    // Coarse edge -> its triangles, to find the borders.
    std::map<std::pair<int32_t, int32_t>, std::vector<int32_t>> edge_tris;
    for (int32_t t = 0; t < p.coarse.num_triangles(); ++t)
        for (int k = 0; k < 3; ++k) {
            int32_t a = p.coarse.triangles[size_t(t)][size_t(k)], b = p.coarse.triangles[size_t(t)][size_t((k + 1) % 3)];
            edge_tris[{std::min(a, b), std::max(a, b)}].push_back(t);
        }
    int borders = 0;
    double worst = 0;
    for (int32_t t = 0; t < p.coarse.num_triangles(); ++t) {
        const Tri& ct = p.coarse.triangles[size_t(t)];
        for (int k = 0; k < 3; ++k) {
            const int32_t a = ct[size_t(k)], b = ct[size_t((k + 1) % 3)];
            const auto& tris = edge_tris[{std::min(a, b), std::max(a, b)}];
            if (tris.size() != 2 || p.coarse.patches[size_t(tris[0])] == p.coarse.patches[size_t(tris[1])]) continue;
            ++borders;
            // (position along the edge from corner k, image) of the nodes on local edge k.
            std::vector<std::pair<double, Vec3>> chain;
            for (int64_t n = p.node_offsets[size_t(t)]; n < p.node_offsets[size_t(t) + 1]; ++n) {
                const Vec3& bc = p.node_barycentric[size_t(n)];
                if (bc[size_t((k + 2) % 3)] == 0) chain.push_back({bc[size_t((k + 1) % 3)], p.node_image[size_t(n)]});
            }
            std::sort(chain.begin(), chain.end());
            REQUIRE(chain.size() == 5);  // two corners and the three original vertices between them
            std::vector<double> arc(chain.size(), 0.0);
            for (size_t i = 1; i < chain.size(); ++i) arc[i] = arc[i - 1] + distance(chain[i - 1].second, chain[i].second);
            for (size_t i = 0; i < chain.size(); ++i) worst = std::max(worst, std::abs(chain[i].first - arc[i] / arc.back()));
        }
    }
    CHECK(borders > 0);
    CHECK(worst < 1e-12);
}

TEST_CASE("smoothing does not make the refined surface of CAD-like shapes worse", "[smooth]") {
    // A new user's audit (gmsh torus, cylinder with caps, L-block, box with a hole, two
    // boxes): the relaxation, which places the original vertices by the shape of S0 alone,
    // made the 3-times refined surface worse on all of them, in max |flat - phi| (L-block
    // 4.2e-3 -> 9.0e-3 of the diagonal) and in the max aspect ratio (box with a hole 30.6
    // -> 81). Small analytic shapes of the same kinds show it too; an update is now kept
    // only if neither of its two coarse triangles gets worse.
    struct Case {
        std::string name;
        Surface surface;
        double ratio;
    };
    std::vector<Case> cases;
    cases.push_back({"torus", fixtures::torus(32, 20), 0.1});
    cases.push_back({"two cubes", fixtures::two_cubes(6), 0.1});
    cases.push_back({"cube", fixtures::cube(8), 0.1});
    cases.push_back({"cylinder", fixtures::cylinder_wedges(24, 6), 0.1});
    for (Case& c : cases) {
        INFO(c.name);
        Parametrization p = simplified(c.surface, c.ratio);
        RefineOptions ro;
        ro.levels = 3;
        RefinedSurface refined;
        const RefineResult before = refine(p, ro, Context{}, refined);
        SmoothOptions o;
        const SmoothResult r = smooth(p, o, Context{});
        const RefineResult after = refine(p, ro, Context{}, refined);
        INFO(r.updates << " updates, " << r.rejected << " rejected; K=3 max |flat - phi| " << before.max_estimated_error
                       << " -> " << after.max_estimated_error << ", max aspect ratio " << r.before.max_aspect_ratio
                       << " -> " << r.after.max_aspect_ratio);
        CHECK(r.after.max_aspect_ratio <= r.before.max_aspect_ratio * (1 + 1e-9));
        // 1e-12 of the diagonal: rounding (the simplifier now keeps the cubes exact, 1e-15).
        CHECK(after.max_estimated_error <= before.max_estimated_error * (1 + 1e-6) + 1e-12);
        require_valid_parametrization(p);
    }
}

TEST_CASE("smoothing slides along the long shallow creases the simplifier kept", "[smooth][chains]") {
    // The lens's rim, 27.5 degrees (below the feature angle), is a crease of the simplifier
    // by its chain rule (SimplifyOptions::crease_chain_angle_degrees): coarse edges run
    // along it. The smoother must take it for a feature line too (the same rule, the same
    // defaults), so its original vertices only slide along those edges. Before, the
    // smoother judged by the feature angle alone and relaxed across the rim (0 slides).
    const Parametrization simplified_lens = simplified(fixtures::ridged_lens(48, 12, 20.0), 0.1);
    SmoothOptions o;
    o.quality_levels = 1;
    o.check_levels = 0;  // the sliding itself
    Parametrization p = simplified_lens;
    const SmoothResult r = smooth(p, o, Context{});
    CHECK(r.slides > 0);
    require_valid_parametrization(p);
    o.crease_chain_angle_degrees = 180.0;  // off: no feature line on the lens at all
    Parametrization q = simplified_lens;
    CHECK(smooth(q, o, Context{}).slides == 0);
}

TEST_CASE("smoothing rejects bad options", "[smooth]") {
    Parametrization p = test::make_subdivided_octahedron(1);
    SmoothOptions o;
    o.iterations = -1;
    CHECK_THROWS_AS(smooth(p, o, Context{}), OptionError);
    o = SmoothOptions{};
    o.crease_chain_angle_degrees = 200.0;
    CHECK_THROWS_AS(smooth(p, o, Context{}), OptionError);
    // The feature angle too (a negative one made nearly every edge of S0 a crease, NaN none).
    o = SmoothOptions{};
    o.feature_angle_degrees = -5.0;
    CHECK_THROWS_AS(smooth(p, o, Context{}), OptionError);
    o.feature_angle_degrees = std::nan("");
    CHECK_THROWS_WITH(smooth(p, o, Context{}), Catch::Contains("smooth: feature_angle_degrees"));
}

TEST_CASE("smoothing improves the refined femur and keeps phi valid", "[smooth][real]") {
    const std::string path = std::string(BPM_MESH_DIR) + "/femur.off";
    if (!std::filesystem::exists(path)) {
        WARN("missing " << path);
        return;
    }
    Parametrization p = simplified(read_surface(path), 0.1);
    const Surface coarse = p.coarse;
    // Per coarse triangle: how near its nearest node (not a corner) is to a corner.
    const auto corner_gaps = [](const Parametrization& q) {
        std::vector<double> gap(size_t(q.coarse.num_triangles()), 1.0);
        for (int32_t t = 0; t < q.coarse.num_triangles(); ++t)
            for (int64_t n = q.node_offsets[size_t(t)]; n < q.node_offsets[size_t(t) + 1]; ++n)
                if (q.node_kind[size_t(n)] != NodeKind::CoarseCorner) {
                    const Vec3& b = q.node_barycentric[size_t(n)];
                    gap[size_t(t)] = std::min(gap[size_t(t)], 1 - std::max({b[0], b[1], b[2]}));
                }
        return gap;
    };
    const std::vector<double> gaps_before = corner_gaps(p);
    SmoothOptions o;
    o.iterations = 10;
    const SmoothResult r = smooth(p, o, Context{});
    // femur has saddle vertices of S where the sweeps, unchecked, contract the star of S0
    // around the vertex into the corner (to 1e-10 of the triangle after five sweeps).
    const std::vector<double> gaps_after = corner_gaps(p);
    int collapsed = 0;
    for (size_t t = 0; t < gaps_after.size(); ++t) collapsed += gaps_after[t] < std::min(gaps_before[t], 1e-2) * (1 - 1e-9);
    CHECK(collapsed == 0);
    INFO("aspect ratio K=3: max " << r.before.max_aspect_ratio << " -> " << r.after.max_aspect_ratio << ", p99 "
                                  << r.before.p99_aspect_ratio << " -> " << r.after.p99_aspect_ratio << ", mean "
                                  << r.before.mean_aspect_ratio << " -> " << r.after.mean_aspect_ratio);
    CHECK(r.updates > 0);
    CHECK(r.after.p99_aspect_ratio < r.before.p99_aspect_ratio);
    CHECK(r.after.mean_aspect_ratio < r.before.mean_aspect_ratio);
    CHECK(p.coarse.vertices == coarse.vertices);
    CHECK(max_image_error(p) == 0.0);
    require_valid_parametrization(p);
    const CheckResult inter = check_intersections(p.coarse);
    CHECK(inter.passed);

    // Refining the smoothed map: vertices on S0, a valid refined .bpm.
    RefinedSurface refined;
    RefineOptions ro;
    ro.levels = 2;
    refine(p, ro, Context{}, refined);
    const PhiEvaluator phi(p);
    const double diagonal = bounding_box_diagonal(p.original);
    double worst = 0;
    for (size_t v = 0; v < refined.surface.vertices.size(); ++v) {
        const Tri& t = p.original.triangles[size_t(refined.vertex_original_triangle[v])];
        const Vec3 x = barycentric_point(p.original.vertices[size_t(t[0])], p.original.vertices[size_t(t[1])],
                                         p.original.vertices[size_t(t[2])], refined.vertex_original_barycentric[v]);
        worst = std::max(worst, distance(x, refined.surface.vertices[v]) / diagonal);
    }
    CHECK(worst < 1e-12);
    require_valid_parametrization(refined_parametrization(p, refined));
}
