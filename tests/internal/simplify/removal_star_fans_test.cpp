// classify_star (simplify/star_fans.h): the star of a vertex as fans, or why it is kept.
#include <catch2/catch.hpp>

#include "removal_test_fans.h"
#include "simplify/coarse_mesh.h"
#include "simplify/star_fans.h"

using namespace bpm;
using namespace bpm::detail;

TEST_CASE("removal star: a regular vertex is one closed fan in link order", "[simplify][removal]") {
    const Surface s = removal_test::hexagon_fan();
    CoarseMesh mesh(s);
    mesh.mark_feature_edges(60.0);
    std::vector<Fan> fans;
    StarScratch scratch;
    bool crease_line = true;
    std::string why;
    REQUIRE(classify_star(mesh, 0, false, fans, crease_line, why, scratch) == VertexClass::Regular);
    CHECK_FALSE(crease_line);
    REQUIRE(fans.size() == 1);
    CHECK(fans[0].closed);
    // Starts at the smallest triangle id, counter-clockwise.
    CHECK(fans[0].link == std::vector<int32_t>{1, 2, 3, 4, 5, 6});
    CHECK(fans[0].triangles == std::vector<int32_t>{0, 1, 2, 3, 4, 5});
    CHECK(fans[0].link_side(6, 1) == 5);
    CHECK(fans[0].spoke_index(0, 3, 0) == 2);
    CHECK(fans[0].is_interior_spoke(0));
}

TEST_CASE("removal star: a boundary vertex is an open fan between its feature edges", "[simplify][removal]") {
    const Surface s = removal_test::half_disk_fan();
    CoarseMesh mesh(s);
    mesh.mark_feature_edges(60.0);
    std::vector<Fan> fans;
    StarScratch scratch;
    bool crease_line = true;
    std::string why;
    REQUIRE(classify_star(mesh, 0, false, fans, crease_line, why, scratch) == VertexClass::FeatureLine);
    CHECK_FALSE(crease_line);  // hard edges, not creases
    REQUIRE(fans.size() == 1);
    CHECK_FALSE(fans[0].closed);
    CHECK(fans[0].link == std::vector<int32_t>{1, 2, 3, 4, 5});
    CHECK(fans[0].triangles == std::vector<int32_t>{0, 1, 2, 3});
    CHECK_FALSE(fans[0].is_interior_spoke(0));
    CHECK_FALSE(fans[0].is_interior_spoke(4));
    CHECK(fans[0].is_interior_spoke(2));
    CHECK(fans[0].link_side(5, 1) == -1);  // the new edge is not a link edge
}

TEST_CASE("removal star: feature vertices are kept with the reason", "[simplify][removal]") {
    const Surface s = removal_test::hexagon_fan();
    std::vector<Fan> fans;
    StarScratch scratch;
    bool crease_line = false;
    std::string why;
    {
        CoarseMesh mesh(s);
        mesh.set_feature_edge(0, 3, CoarseMesh::Feature::Hard);  // a feature line ends at 0
        CHECK(classify_star(mesh, 0, false, fans, crease_line, why, scratch) == VertexClass::Feature);
        CHECK(why == "end of a feature line");
    }
    {
        CoarseMesh mesh(s);
        for (int32_t x : {1, 3, 5}) mesh.set_feature_edge(0, x, CoarseMesh::Feature::Hard);
        CHECK(classify_star(mesh, 0, false, fans, crease_line, why, scratch) == VertexClass::Feature);
        CHECK(why == "meeting point of feature lines");
    }
    {
        // Two creases through 0 are followed, unless the caller forces a disk.
        CoarseMesh mesh(s);
        for (int32_t x : {1, 4}) mesh.set_feature_edge(0, x, CoarseMesh::Feature::Crease);
        REQUIRE(classify_star(mesh, 0, false, fans, crease_line, why, scratch) == VertexClass::FeatureLine);
        CHECK(crease_line);
        REQUIRE(fans.size() == 2);
        // Each half-disk counter-clockwise, so from 1 to 4 on one side and back on the other.
        CHECK(fans[0].link == std::vector<int32_t>{1, 2, 3, 4});
        CHECK(fans[1].link == std::vector<int32_t>{4, 5, 6, 1});
        CHECK(fans[1].triangles == std::vector<int32_t>{3, 4, 5});
        CHECK(classify_star(mesh, 0, true, fans, crease_line, why, scratch) == VertexClass::Regular);
    }
    {
        CoarseMesh mesh(s);
        mesh.remove_triangle(2);  // a gap in the star without a feature mark
        CHECK(classify_star(mesh, 0, false, fans, crease_line, why, scratch) == VertexClass::Feature);
        CHECK(why == "non-manifold edge without feature mark");
    }
}
