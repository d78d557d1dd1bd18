// check_junctions: the sheets around an edge of three or more triangles agree about the
// material of every wedge between them.
#include <catch2/catch.hpp>

#include <cmath>

#include "bpm/check.h"
#include "bpm/patch_info.h"
#include "fixtures_surfaces.h"

using namespace bpm;

namespace {

// Three sheets (one triangle each) around the z axis, with their apexes at the given
// angles (degrees); sheet i is patch i. The wedges, turning from sheet 0: A, B, C.
// Each triangle runs 0 -> 1 along the edge, so its front faces the wedge turning after it.
Surface fin(double angle0, double angle1, double angle2) {
    Surface s;
    s.vertices = {{0, 0, 0}, {0, 0, 1}};
    for (double deg : {angle0, angle1, angle2}) {
        const double r = deg * M_PI / 180.0;
        s.vertices.push_back({std::cos(r), std::sin(r), 0.5});
    }
    s.triangles = {{0, 1, 2}, {0, 1, 3}, {0, 1, 4}};
    s.patches = {0, 1, 2};
    return s;
}

// Which way the turn goes depends on the convention of orient3d; the materials are
// written by that convention's own side test: the front of triangle (0, 1, c) is where
// orient3d(p0, p1, pc, x) > 0. So for angles increasing counter-clockwise seen from +z,
// find whether "after" is counter-clockwise, and name the wedges accordingly.
std::vector<PatchInfo> fin_materials() {
    // sheet 0 between C and A, sheet 1 between A and B, sheet 2 between B and C
    return {{0, "", "A", "C", true}, {1, "", "B", "A", true}, {2, "", "C", "B", true}};
}

}  // namespace

TEST_CASE("check_junctions: sheets in their order around an edge pass", "[check][junctions]") {
    // The front of (0, 1, c) points to where (p1 - p0) x (pc - p0) points: for c at angle
    // theta, z x (cos, sin) = (-sin, cos), counter-clockwise. So increasing angles turn
    // towards the fronts: sheet 0 (0 deg), sheet 1 (120), sheet 2 (240).
    const CheckResult r = check_junctions(fin(0, 120, 240), fin_materials());
    INFO(r.summary);
    CHECK(r.passed);
    CHECK(r.count("junction_edges") == 1);
    CHECK(r.count("inconsistent_junction_edges") == 0);
    CHECK(r.count("junction_edges_without_materials") == 0);
    // Any angles keeping the order pass.
    CHECK(check_junctions(fin(10, 20, 350), fin_materials()).passed);
}

TEST_CASE("check_junctions: a sheet turned past another around their edge fails", "[check][junctions]") {
    // Sheet 1 turned from 120 to 300 degrees, past sheet 2 (240): no two triangles
    // intersect, but the wedge after sheet 0 is A by sheet 0 and B by sheet 2.
    const Surface s = fin(0, 300, 240);
    const CheckResult r = check_junctions(s, fin_materials());
    INFO(r.summary);
    REQUIRE_FALSE(r.passed);
    CHECK(r.count("inconsistent_junction_edges") == 1);
    CHECK(r.problem_count == 1);
    const std::string m = r.problems.at(0).message;
    INFO(m);
    CHECK(m.find("edge vertex 0 -- vertex 1 (3 triangles)") != std::string::npos);
    CHECK(m.find("faces A on one side and B on the other") != std::string::npos);
    CHECK(r.problems.at(0).id("triangle") == 0);
    CHECK(r.problems.at(0).id("other_triangle") == 2);
    // The intersection check sees nothing wrong.
    CHECK(check_intersections(s).passed);
}

TEST_CASE("check_junctions: the orientation of each triangle decides which side faces a wedge", "[check][junctions]") {
    Surface s = fin(0, 120, 240);
    std::vector<PatchInfo> infos = fin_materials();
    std::swap(s.triangles[1][0], s.triangles[1][1]);  // sheet 1 reversed: its front is now A
    CHECK_FALSE(check_junctions(s, infos).passed);
    std::swap(infos[1].front, infos[1].back);
    CHECK(check_junctions(s, infos).passed);
}

TEST_CASE("check_junctions: edges without known materials are counted, not checked", "[check][junctions]") {
    std::vector<PatchInfo> infos = fin_materials();
    infos[2].oriented = false;
    const CheckResult r = check_junctions(fin(0, 300, 240), infos);
    CHECK(r.passed);
    CHECK(r.count("junction_edges_without_materials") == 1);
    CHECK(r.summary.find("1 not checked: materials unknown") != std::string::npos);
    CHECK(check_junctions(fin(0, 300, 240), {}).passed);
}

TEST_CASE("check_junctions: two sheets on one half-plane are a problem", "[check][junctions]") {
    const CheckResult r = check_junctions(fin(0, 120, 120), fin_materials());
    CHECK_FALSE(r.passed);
    CHECK(r.count("overlapping_junction_edges") == 1);
}

TEST_CASE("check_junctions of a file: S must keep the order of S0", "[check][junctions]") {
    BpmFile file;
    file.param = fixtures::identity_parametrization(fin(0, 120, 240));
    file.patch_info = fin_materials();
    CHECK(check_junctions(file).passed);
    // Sheet 1 of S turned past sheet 2 (S0 as it was): fails, named by coarse triangles.
    const double r = 300 * M_PI / 180.0;
    file.param.coarse.vertices[3] = {std::cos(r), std::sin(r), 0.5};
    const CheckResult turned = check_junctions(file);
    INFO(turned.summary);
    REQUIRE_FALSE(turned.passed);
    CHECK(turned.count("inconsistent_junction_edges") == 1);
    CHECK(turned.count("original_inconsistent_junction_edges") == 0);
    CHECK(turned.problems.at(0).id("coarse_triangle") == 0);
    CHECK(turned.problems.at(0).message.find("coarse vertex 0 (original 0) -- coarse vertex 1 (original 1)") !=
          std::string::npos);
    // Materials that contradict S0 itself (a reader's guess) say nothing about S: counted, not failed.
    file.param.original.vertices[3] = file.param.coarse.vertices[3];
    const CheckResult guessed = check_junctions(file);
    INFO(guessed.summary);
    CHECK(guessed.passed);
    CHECK(guessed.count("original_inconsistent_junction_edges") == 1);
    CHECK(guessed.count("patches_contradicting_original") == 3);
    CHECK(guessed.count("junction_edges_without_materials") == 1);
}
