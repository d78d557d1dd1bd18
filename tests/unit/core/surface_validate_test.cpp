// validate_surface, the two repairs and the bounding box: every problem kind is found,
// reported with the right elements, in a deterministic order, and the repairs renumber
// deterministically.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "bpm/surface.h"
#include "fixtures_surfaces.h"

using namespace bpm;
using Kind = SurfaceProblem::Kind;

namespace {

Surface tetrahedron() {
    Surface s;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    s.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    s.patches = {0, 0, 0, 0};
    return s;
}

std::vector<SurfaceProblem> of_kind(const std::vector<SurfaceProblem>& all, Kind kind) {
    std::vector<SurfaceProblem> out;
    for (const SurfaceProblem& p : all) {
        if (p.kind == kind) out.push_back(p);
    }
    return out;
}

}  // namespace

TEST_CASE("a clean tetrahedron has no problems", "[validate]") { CHECK(validate_surface(tetrahedron()).empty()); }

TEST_CASE("bounding box diagonal", "[validate]") {
    CHECK(bounding_box_diagonal(tetrahedron()) == Approx(std::sqrt(3.0)));
    CHECK(bounding_box_diagonal(std::vector<Vec3>{{1, 2, 3}}) == 0.0);
    CHECK(bounding_box_diagonal(std::vector<Vec3>{}) == 0.0);
    CHECK(bounding_box_diagonal(std::vector<Vec3>{{-1, 0, 0}, {2, 4, 0}}) == Approx(5.0));
}

TEST_CASE("validate: non-finite coordinates", "[validate]") {
    Surface s = tetrahedron();
    s.vertices[2][1] = std::numeric_limits<double>::quiet_NaN();
    s.vertices[3][0] = -std::numeric_limits<double>::infinity();
    const auto problems = of_kind(validate_surface(s), Kind::NonFiniteCoordinate);
    REQUIRE(problems.size() == 2);
    CHECK(problems[0].element == 2);
    CHECK(problems[1].element == 3);
    CHECK(describe_problem(problems[0], s) == "vertex 2: coordinate y is NaN");
    CHECK(describe_problem(problems[1], s) == "vertex 3: coordinate x is infinite");
    CHECK(of_kind(validate_surface(s), Kind::ZeroArea).empty());  // no collinearity test on NaN
}

TEST_CASE("validate: indices out of range", "[validate]") {
    Surface s = tetrahedron();
    s.triangles[1] = {0, -1, 3};
    s.triangles[3] = {1, 2, 4};
    const auto problems = validate_surface(s);
    const auto bad = of_kind(problems, Kind::IndexOutOfRange);
    REQUIRE(bad.size() == 2);
    CHECK(bad[0].element == 1);
    CHECK(bad[0].other == -1);
    CHECK(bad[1].element == 3);
    CHECK(bad[1].other == 4);
    CHECK(bad[1].describe() == "triangle 3: vertex index 4 is out of range");
}

TEST_CASE("validate: repeated corner", "[validate]") {
    Surface s = tetrahedron();
    s.triangles.push_back({3, 1, 3});
    s.patches.push_back(0);
    const auto problems = validate_surface(s);
    REQUIRE(problems.size() == 1);
    CHECK(problems[0].kind == Kind::RepeatedCorner);
    CHECK(problems[0].element == 4);
    CHECK(problems[0].other == 3);
    CHECK(describe_problem(problems[0], s) == "triangle 4 (vertices 3, 1, 3): corners 0 and 2 are the same vertex");
}

TEST_CASE("validate: zero area is decided exactly", "[validate]") {
    Surface s = tetrahedron();
    // Exactly collinear, far from the origin.
    s.vertices.push_back({1e8, 1e8, 1e8});
    s.vertices.push_back({2e8, 2e8, 2e8});
    s.vertices.push_back({3e8, 3e8, 3e8});
    s.triangles.push_back({4, 5, 6});
    // Off the line by one unit in the last place: not collinear, though any tolerance would call it flat.
    s.vertices.push_back({0.0, 0.0, 7.0});
    s.vertices.push_back({1.0, 1.0, 7.0});
    s.vertices.push_back({2.0, std::nextafter(2.0, 3.0), 7.0});
    s.triangles.push_back({7, 8, 9});
    // Tiny but real.
    s.vertices.push_back({0, 0, 5});
    s.vertices.push_back({1e-300, 0, 5});
    s.vertices.push_back({0, 1e-300, 5});
    s.triangles.push_back({10, 11, 12});
    s.patches.assign(s.triangles.size(), 0);
    const auto problems = validate_surface(s);
    REQUIRE(problems.size() == 1);
    CHECK(problems[0].kind == Kind::ZeroArea);
    CHECK(problems[0].element == 4);
}

TEST_CASE("validate: duplicate triangles in any order and orientation", "[validate]") {
    Surface s = tetrahedron();
    s.triangles.push_back({1, 2, 0});  // same set as triangle 0, same orientation
    s.triangles.push_back({3, 1, 0});  // same set as triangle 1, reversed
    s.triangles.push_back({2, 0, 1});  // triangle 0 a third time
    s.patches.assign(s.triangles.size(), 0);
    const auto problems = validate_surface(s);
    REQUIRE(problems.size() == 3);
    for (const auto& p : problems) CHECK(p.kind == Kind::DuplicateTriangle);
    CHECK(problems[0].element == 4);
    CHECK(problems[0].other == 0);
    CHECK(problems[1].element == 5);
    CHECK(problems[1].other == 1);
    CHECK(problems[2].element == 6);
    CHECK(problems[2].other == 0);
    CHECK(problems[0].describe() == "triangle 4: same three vertices as triangle 0");
}

TEST_CASE("validate: unreferenced vertices unless allowed", "[validate]") {
    Surface s = tetrahedron();
    s.vertices.insert(s.vertices.begin() + 1, Vec3{5, 5, 5});
    for (Tri& t : s.triangles) {
        for (int32_t& v : t) v += v >= 1 ? 1 : 0;
    }
    auto problems = validate_surface(s);
    REQUIRE(problems.size() == 1);
    CHECK(problems[0].kind == Kind::UnreferencedVertex);
    CHECK(problems[0].element == 1);
    CHECK(problems[0].describe() == "vertex 1: not used by any triangle");
    ValidateOptions allow;
    allow.allow_unreferenced_vertices = true;
    CHECK(validate_surface(s, allow).empty());
}

TEST_CASE("validate: duplicate vertices unless allowed, and -0 equals +0", "[validate]") {
    Surface s = tetrahedron();
    s.vertices.push_back({-0.0, 0.0, 1.0});  // same position as vertex 3
    s.triangles[3] = {1, 2, 4};
    auto problems = validate_surface(s);
    REQUIRE(problems.size() == 1);
    CHECK(problems[0].kind == Kind::DuplicateVertex);
    CHECK(problems[0].element == 4);
    CHECK(problems[0].other == 3);
    CHECK(describe_problem(problems[0], s) == "vertex 4: same position (-0, 0, 1) as vertex 3");
    ValidateOptions allow;
    allow.allow_duplicate_vertices = true;
    CHECK(validate_surface(s, allow).empty());
}

TEST_CASE("validate: patch count mismatch", "[validate]") {
    Surface s = tetrahedron();
    s.patches.pop_back();
    const auto problems = validate_surface(s);
    REQUIRE(problems.size() == 1);
    CHECK(problems[0].kind == Kind::PatchCountMismatch);
    CHECK(problems[0].element == 3);
    CHECK(problems[0].other == 4);
    CHECK(problems[0].describe() == "3 patch ids for 4 triangles");
}

TEST_CASE("validate: stops after max_problems, 0 means no limit", "[validate]") {
    Surface s = tetrahedron();
    for (int i = 0; i < 50; ++i) s.vertices.push_back({10.0 + i, 0, 0});  // 50 unreferenced
    ValidateOptions options;
    CHECK(validate_surface(s, options).size() == 20);
    options.max_problems = 3;
    const auto three = validate_surface(s, options);
    REQUIRE(three.size() == 3);
    CHECK(three[2].element == 6);
    options.max_problems = 0;
    CHECK(validate_surface(s, options).size() == 50);
}

TEST_CASE("validate: problems come in a fixed order", "[validate]") {
    Surface s = tetrahedron();
    s.vertices.push_back({std::nan(""), 0, 0});  // 4: non-finite and unreferenced
    s.vertices.push_back({1, 0, 0});             // 5: duplicate of 1 and unreferenced
    s.triangles.push_back({0, 1, 9});            // 4: out of range
    s.triangles.push_back({1, 0, 2});            // 5: duplicate of 0
    s.patches.assign(s.triangles.size(), 0);
    ValidateOptions options;
    options.max_problems = 0;
    const auto problems = validate_surface(s, options);
    std::vector<Kind> kinds;
    for (const auto& p : problems) kinds.push_back(p.kind);
    CHECK(kinds == std::vector<Kind>{Kind::NonFiniteCoordinate, Kind::IndexOutOfRange, Kind::DuplicateTriangle,
                                     Kind::UnreferencedVertex, Kind::UnreferencedVertex, Kind::DuplicateVertex});
}

TEST_CASE("merge_duplicate_vertices keeps the first of each position and the order of the rest", "[validate]") {
    Surface s;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {0, 0, 0}, {-0.0, 1, 0}};
    s.triangles = {{0, 2, 1}, {5, 3, 4}, {0, 4, 6}, {3, 6, 4}};
    s.patches = {0, 1, 2, 3};
    CHECK(merge_duplicate_vertices(s) == 3);
    CHECK(s.vertices == std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
    CHECK(s.triangles == std::vector<Tri>{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}});
    CHECK(s.patches == std::vector<int32_t>{0, 1, 2, 3});
    CHECK(merge_duplicate_vertices(s) == 0);
}

TEST_CASE("merge_duplicate_vertices never merges NaN vertices", "[validate]") {
    Surface s = tetrahedron();
    s.vertices.push_back({std::nan(""), 0, 0});
    s.vertices.push_back({std::nan(""), 0, 0});
    CHECK(merge_duplicate_vertices(s) == 0);
    CHECK(s.vertices.size() == 6);
}

TEST_CASE("merging can leave repeated corners for validation to report", "[validate]") {
    Surface s = tetrahedron();
    s.vertices.push_back({1, 0, 0});  // 4 == 1
    s.triangles.push_back({1, 4, 3});
    s.patches.push_back(0);
    CHECK(validate_surface(s).at(0).kind == Kind::ZeroArea);
    merge_duplicate_vertices(s);
    const auto problems = validate_surface(s);
    REQUIRE(problems.size() == 1);
    CHECK(problems[0].kind == Kind::RepeatedCorner);
    CHECK(problems[0].element == 4);
}

TEST_CASE("drop_unreferenced_vertices keeps order and renumbers", "[validate]") {
    Surface s;
    s.vertices = {{9, 9, 9}, {0, 0, 0}, {1, 0, 0}, {8, 8, 8}, {0, 1, 0}, {0, 0, 1}, {7, 7, 7}};
    s.triangles = {{1, 4, 2}, {1, 2, 5}, {1, 5, 4}, {2, 4, 5}};
    s.patches = {0, 0, 0, 0};
    CHECK(drop_unreferenced_vertices(s) == 3);
    const Surface t = tetrahedron();
    CHECK(s.vertices == t.vertices);
    CHECK(s.triangles == t.triangles);
    CHECK(drop_unreferenced_vertices(s) == 0);
}

TEST_CASE("drop_unreferenced_vertices leaves bad indices detectable", "[validate]") {
    Surface s = tetrahedron();
    s.vertices.push_back({4, 4, 4});
    s.triangles.push_back({0, 1, 17});
    s.patches.push_back(0);
    CHECK(drop_unreferenced_vertices(s) == 1);
    CHECK(s.triangles.back()[2] == -1);
    CHECK(of_kind(validate_surface(s), Kind::IndexOutOfRange).size() == 1);
}

TEST_CASE("fuse_duplicate_triangles keeps the first of each set and gives shared ones a patch", "[validate]") {
    // A tetrahedron (patch 0) and a second one on its face (0, 1, 2) (patch 1, that face
    // reversed): the shared face once, in its first orientation, as patch 2; a plain
    // duplicate within patch 1 is just removed.
    Surface s;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}};
    s.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3},   // tetrahedron 0123, outwards
                   {0, 1, 2}, {0, 4, 1}, {0, 2, 4}, {1, 4, 2},   // tetrahedron 0124, outwards
                   {4, 1, 0}};                                   // duplicate of (0, 4, 1)
    s.patches = {0, 0, 0, 0, 1, 1, 1, 1, 1};
    CHECK(validate_surface(s).at(0).kind == Kind::DuplicateTriangle);
    std::vector<FusedPatch> fused;
    CHECK(fuse_duplicate_triangles(s, &fused) == 2);
    CHECK(s.triangles == std::vector<Tri>{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 4, 1}, {0, 2, 4}, {1, 4, 2}});
    CHECK(s.patches == std::vector<int32_t>{2, 0, 0, 0, 1, 1, 1});
    REQUIRE(fused.size() == 1);
    CHECK(fused[0].patch == 2);
    CHECK(fused[0].joins == std::vector<int32_t>{0, 1});
    CHECK(fused[0].triangles == 1);
    CHECK(validate_surface(s).empty());
    CHECK(fuse_duplicate_triangles(s) == 0);
}

TEST_CASE("fuse_duplicate_triangles: one closed cube per material becomes two cubes with a shared sheet",
          "[validate]") {
    // Each cube alone (labels 1 | 0 and 0 | 2), as two files would hold them.
    Surface s = combine_surfaces({fixtures::voxel_surface(2, 1, 1, {1, 0}, 3), fixtures::voxel_surface(2, 1, 1, {0, 2}, 3)});
    CHECK(merge_duplicate_vertices(s) == 16);  // the 4 x 4 grid of the shared square
    std::vector<FusedPatch> fused;
    CHECK(fuse_duplicate_triangles(s, &fused) == 18);  // 3 x 3 quads of two triangles
    REQUIRE(fused.size() == 1);
    CHECK(fused[0].triangles == 18);
    CHECK(validate_surface(s).empty());
    const Surface reference = fixtures::two_cubes(3);
    CHECK(s.num_vertices() == reference.num_vertices());
    CHECK(s.num_triangles() == reference.num_triangles());
}

TEST_CASE("merge_close_vertices joins each vertex to the first kept one within the distance", "[validate]") {
    // The tetrahedron of merge_duplicate_vertices' test with its copies moved by 1e-9
    // (a seam open by rounding), and vertex 7 1.5e-9 beyond copy 3: 2.5e-9 from vertex 1,
    // which is kept, it stays, although it is within the distance of copy 3 (no chains:
    // nothing moves by more than the distance).
    Surface s;
    const double e = 1e-9;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1 + e, 0, 0}, {0, 0, 1}, {0, e, 0}, {0, 1, e}, {1 + 2.5 * e, 0, 0}};
    s.triangles = {{0, 2, 1}, {5, 3, 4}, {0, 4, 6}, {3, 6, 4}, {7, 2, 4}};
    s.patches = {0, 1, 2, 3, 4};
    const CloseVertexMerge m = merge_close_vertices(s, 2 * e);
    CHECK(m.merged == 3);
    CHECK(m.largest_move == Approx(e).epsilon(1e-6));
    CHECK(m.collapsed_triangle == -1);
    CHECK(s.vertices == std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1 + 2.5 * e, 0, 0}});
    CHECK(s.triangles == std::vector<Tri>{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {4, 2, 3}});
    CHECK(s.patches == std::vector<int32_t>{0, 1, 2, 3, 4});
    // Exact duplicates merge at distance 0, as merge_duplicate_vertices does.
    Surface d;
    d.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}};
    d.triangles = {{0, 1, 2}, {3, 2, 0}};
    d.patches = {0, 0};
    CHECK(merge_close_vertices(d, 0.0).merged == 1);
    CHECK(d.triangles == std::vector<Tri>{{0, 1, 2}, {1, 2, 0}});
}

TEST_CASE("merge_close_vertices refuses a distance that collapses a triangle and changes nothing", "[validate]") {
    Surface s = tetrahedron();
    const Surface before = s;
    const CloseVertexMerge m = merge_close_vertices(s, 10.0);
    CHECK(m.merged == 0);
    CHECK(m.collapsed_triangle == 0);
    CHECK(m.collapsed_corners[0] != m.collapsed_corners[1]);
    CHECK(s.vertices == before.vertices);
    CHECK(s.triangles == before.triangles);
}

TEST_CASE("find_open_seam pairs boundary edges whose ends are within the gap", "[validate]") {
    // Two triangles that should share the edge (1, 2), written with a copy of it 1e-9 away.
    Surface s;
    const double e = 1e-9;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, e, 0}, {e, 1, 0}};
    s.triangles = {{0, 1, 2}, {4, 3, 5}};
    s.patches = {0, 0};
    const std::optional<OpenSeam> seam = find_open_seam(s, 1e-6);
    REQUIRE(seam);
    CHECK(seam->boundary_edges == 6);
    CHECK(seam->paired_edges == 2);
    CHECK(seam->gap == Approx(e).epsilon(1e-6));
    CHECK(seam->first_edge == std::array<int32_t, 2>{1, 2});
    CHECK_FALSE(find_open_seam(s, 1e-10));  // the gap is larger
    CHECK(seam_merge_tolerance(s, *seam, 1.0) == Approx(1e-8));
    CHECK_FALSE(find_open_seam(tetrahedron(), 1e-6));  // closed
}
