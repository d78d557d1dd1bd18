// The ridge guard (simplify/ridge_guard.h, SimplifyOptions::min_ridge_angle_degrees): the
// ridge a removal makes is measured on its new diagonals and on the sides of its hole
// (only where they get sharper), feature edges are exempt, and removal_cost() refuses a
// ridge sharper than min(floor, the original's sharpest ridge in the star - margin).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/simplify.h"
#include "bpm/surface.h"
#include "core/crease.h"
#include "simplify/coarse_mesh.h"
#include "simplify/embedding.h"
#include "simplify/removal_cost.h"
#include "simplify/ridge_guard.h"

using namespace bpm;
using namespace bpm::detail;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A star of vertex 0 at the origin over the link 1 = (w, 0, 0), 2 = (0, 1, h),
// 3 = (-w, 0, 0), 4 = (0, -1, h), closed by a fifth vertex 5 at (0, 0, -1) under the four
// link edges, so that the link edges have two triangles each (a closed surface, no
// boundary). Removing 0 with the diagonal 1-3 folds the triangles (1, 2, 3) and (3, 4, 1)
// into a V of opening 2 atan(1 / h) along the x axis; the diagonal 2-4 makes a tent of
// opening 2 atan(w / h).
Surface folded_star(double h, double w) {
    Surface s;
    s.vertices = {{0, 0, 0}, {w, 0, 0}, {0, 1, h}, {-w, 0, 0}, {0, -1, h}, {0, 0, -1}};
    s.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}, {5, 2, 1}, {5, 3, 2}, {5, 4, 3}, {5, 1, 4}};
    s.patches.assign(s.triangles.size(), 0);
    return s;
}

double v_opening(double h) { return 2.0 * std::atan(1.0 / h) * 180.0 / kPi; }

std::vector<int32_t> star_of_0(const CoarseMesh& mesh) {
    std::vector<int32_t> star;
    for (int32_t t : mesh.triangles_of(0)) star.push_back(t);
    return star;
}

}  // namespace

TEST_CASE("ridge guard: a new diagonal's ridge is measured, a flatter choice is not sharp",
          "[internal][simplify][ridge]") {
    const Surface s = folded_star(5.0, 8.0);
    CoarseMesh mesh(s);
    mesh.mark_feature_edges(180.0);  // no creases: every edge is judged
    RidgeScratch scratch;
    const std::vector<int32_t> star = star_of_0(mesh);
    REQUIRE(star.size() == 4);
    // Diagonal 1-3: the V of opening 2 atan(1/5) = 22.6 degrees. The sides of the hole get
    // flatter or stay (the triangles below are far from the V), so the diagonal decides.
    const double v = sharpest_changed_ridge(mesh, star, {{1, 2, 3}, {3, 4, 1}}, -1, -1, scratch);
    CHECK(v == Approx(v_opening(5.0)).epsilon(1e-9));
    // Diagonal 2-4: a tent of 2 atan(8 / 5) = 116 degrees; the sides are no sharper.
    CHECK(sharpest_changed_ridge(mesh, star, {{1, 2, 4}, {2, 3, 4}}, -1, -1, scratch) > 90.0);
    // The diagonal as a new feature edge (a removal on a feature line) is exempt.
    CHECK(sharpest_changed_ridge(mesh, star, {{1, 2, 3}, {3, 4, 1}}, 3, 1, scratch) > v);
}

TEST_CASE("ridge guard: a side of the hole counts where the new triangle makes it sharper, not feature edges",
          "[internal][simplify][ridge]") {
    // The link flat (h = 0), 5 just below it at z = -0.2. With 0 high above (z = 8) the
    // sides of the star are blunt (about 101 degrees); removing 0 lays the new triangles
    // flat over the shallow ones below: the sides become wedges of atan(0.2 / |(0.5, 0.5)|).
    Surface s = folded_star(0.0, 1.0);
    s.vertices[0] = {0, 0, 8};
    s.vertices[5] = {0, 0, -0.2};
    const double wedge = std::atan(0.2 / std::sqrt(0.5)) * 180.0 / kPi;
    RidgeScratch scratch;
    {
        CoarseMesh mesh(s);
        mesh.mark_feature_edges(180.0);
        CHECK(sharpest_changed_ridge(mesh, star_of_0(mesh), {{1, 2, 3}, {3, 4, 1}}, -1, -1, scratch) ==
              Approx(wedge).epsilon(1e-9));
    }
    {
        // The sides are creases before (their normals 79 degrees apart): exempt.
        CoarseMesh creased(s);
        creased.mark_feature_edges(60.0);
        CHECK(sharpest_changed_ridge(creased, star_of_0(creased), {{1, 2, 3}, {3, 4, 1}}, -1, -1, scratch) == 180.0);
    }
    // With 0 just above 5 (z = -0.1) the sides are sharper before (about 8 degrees) than
    // after: the removal makes them flatter, they do not count.
    s.vertices[0] = {0, 0, -0.1};
    CoarseMesh mesh(s);
    mesh.mark_feature_edges(180.0);
    CHECK(sharpest_changed_ridge(mesh, star_of_0(mesh), {{1, 2, 3}, {3, 4, 1}}, -1, -1, scratch) == 180.0);
}

TEST_CASE("ridge guard: the original's ridge angles per vertex", "[internal][simplify][ridge]") {
    const Surface s = folded_star(5.0, 8.0);
    Embedding emb;
    CoarseMesh mesh(s);
    emb.init_identity(s, mesh.triangle_capacity());
    const std::vector<float> ridge = vertex_ridge_angles(s, emb);
    REQUIRE(ridge.size() == s.vertices.size());
    // Against every pair of triangles that share an edge.
    std::vector<double> expected(s.vertices.size(), 180.0);
    for (size_t i = 0; i < s.triangles.size(); ++i)
        for (size_t j = i + 1; j < s.triangles.size(); ++j)
            for (int k = 0; k < 3; ++k) {
                const int32_t u = s.triangles[i][k], w = s.triangles[i][(k + 1) % 3];
                const Tri& t = s.triangles[j];
                if ((t[0] == u || t[1] == u || t[2] == u) && (t[0] == w || t[1] == w || t[2] == w)) {
                    const double r = ridge_angle_degrees(s.vertices, s.triangles[i], t, u, w);
                    expected[u] = std::min(expected[u], r);
                    expected[w] = std::min(expected[w], r);
                }
            }
    for (size_t v = 0; v < s.vertices.size(); ++v) {
        INFO("vertex " << v);
        CHECK(ridge[v] == Approx(expected[v]).epsilon(1e-6));
        CHECK(ridge[v] < 180.0f);
    }
}

TEST_CASE("ridge guard: removal_cost refuses a ridge sharper than min(floor, original - margin)",
          "[internal][simplify][ridge]") {
    SimplifyOptions options;  // min_ridge_angle_degrees 20
    RemovalPlan plan;
    plan.valid = plan.estimated = true;
    plan.worst_new_aspect = plan.worst_old_aspect = 2.0;
    std::string why;
    plan.sharpest_new_ridge = 17.2;  // femur's coarse edge 176-367, original there no sharper than 54
    plan.sharpest_original_ridge = 53.9;
    CHECK(std::isinf(removal_cost(plan, options, 1.0, CostBasis::Plan, why)));
    CHECK(why == "ridge angle limit (min_ridge_angle_degrees)");
    CHECK(std::isinf(removal_cost(plan, options, 1.0, CostBasis::Estimate, why)));
    // Where the original is itself as sharp (a crease of 20 degrees), 15 is allowed, 14 not.
    plan.sharpest_original_ridge = 20.0;
    plan.sharpest_new_ridge = 15.0;
    CHECK(std::isfinite(removal_cost(plan, options, 1.0, CostBasis::Plan, why)));
    plan.sharpest_new_ridge = 14.9;
    CHECK(std::isinf(removal_cost(plan, options, 1.0, CostBasis::Plan, why)));
    // Off: anything goes.
    options.min_ridge_angle_degrees = 0.0;
    plan.sharpest_new_ridge = 1.0;
    CHECK(std::isfinite(removal_cost(plan, options, 1.0, CostBasis::Plan, why)));
}

TEST_CASE("ridge guard: the planner's hole sides give the same angle as the search",
          "[internal][simplify][ridge]") {
    // The sides named with their removed triangles and the diagonal with its other
    // triangle (as the planner hands them over), or the diagonal left to the search (-1):
    // every case above measures the same with them as without.
    auto side_of = [](const CoarseMesh& mesh, const std::vector<Tri>& added, bool name_diagonal) {
        std::vector<int32_t> sides;
        for (size_t i = 0; i < added.size(); ++i)
            for (int k = 0; k < 3; ++k) {
                const int32_t inside = mesh.find_triangle(0, added[i][k], added[i][(k + 1) % 3]);
                sides.push_back(inside >= 0 || !name_diagonal ? inside : -2 - int32_t(1 - i));
            }
        return sides;
    };
    const std::vector<Tri> v_diagonal{{1, 2, 3}, {3, 4, 1}}, tent_diagonal{{1, 2, 4}, {2, 3, 4}};
    Surface folded = folded_star(5.0, 8.0), wedged = folded_star(0.0, 1.0);
    wedged.vertices[0] = {0, 0, 8};
    wedged.vertices[5] = {0, 0, -0.2};
    RidgeScratch scratch;
    for (const Surface* s : {&folded, &wedged})
        for (double feature_angle : {180.0, 60.0})
            for (const auto* added : {&v_diagonal, &tent_diagonal}) {
                CoarseMesh mesh(*s);
                mesh.mark_feature_edges(feature_angle);
                const double searched = sharpest_changed_ridge(mesh, star_of_0(mesh), *added, -1, -1, scratch);
                for (bool name_diagonal : {false, true}) {
                    const std::vector<int32_t> sides = side_of(mesh, *added, name_diagonal);
                    REQUIRE(std::count_if(sides.begin(), sides.end(), [](int32_t h) { return h >= 0; }) == 4);
                    CHECK(sharpest_changed_ridge(mesh, star_of_0(mesh), *added, -1, -1, scratch, sides) == searched);
                }
            }
}
