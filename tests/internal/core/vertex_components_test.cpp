// The components of a triangle set through shared vertices (core/vertex_components.h),
// which the island guard and bpm-check's junctions check both number: triangles touching
// only at a vertex are one component (an hourglass), the numbering follows each
// component's smallest vertex whatever order the triangles come in, and a vertex of no
// triangle gets -1.
#include <vector>

#include <catch2/catch.hpp>

#include "core/vertex_components.h"

using namespace bpm;
using bpm::detail::VertexComponents;

TEST_CASE("vertex components: joined through shared vertices, numbered by their smallest vertex",
          "[internal][core]") {
    // Vertices 0..9: {1, 4, 7} and {7, 8, 9} meet only at 7 (one component); {2, 5, 6}
    // another; 0 and 3 in no triangle. The triangles come largest component last.
    VertexComponents components(10);
    for (const Tri& t : {Tri{7, 8, 9}, Tri{6, 5, 2}, Tri{4, 7, 1}}) components.add(t);
    std::vector<int32_t> id;
    CHECK(components.number(id) == 2);
    CHECK(id == std::vector<int32_t>{-1, 0, 1, -1, 0, 1, 1, 0, 0, 0});
}

TEST_CASE("vertex components: numbered by their smallest vertex, not by first appearance", "[internal][core]") {
    // The first triangle is {6, 5, 2}: numbered as they first appear, {2, 5, 6} would be
    // component 0 and {0, 1, 3, 4} component 1; by the smallest vertex it is the other way
    // round (0 < 2). Vertex 7 is in no triangle.
    VertexComponents components(8);
    for (const Tri& t : {Tri{6, 5, 2}, Tri{4, 3, 1}, Tri{1, 0, 4}}) components.add(t);
    std::vector<int32_t> id;
    CHECK(components.number(id) == 2);
    CHECK(id == std::vector<int32_t>{0, 0, 1, 0, 0, 1, 1, -1});
}

TEST_CASE("vertex components: none without triangles", "[internal][core]") {
    VertexComponents components(3);
    std::vector<int32_t> id = {5};
    CHECK(components.number(id) == 0);
    CHECK(id == std::vector<int32_t>{-1, -1, -1});
}
