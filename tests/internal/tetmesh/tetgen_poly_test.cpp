// The TetGen input (a .poly PLC) written for bpm-mesh: internal, so tested here.
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/surface.h"
#include "fixtures_surfaces.h"
#include "tetmesh/tetgen_poly.h"

using namespace bpm;

TEST_CASE("tetmesh: the PLC lists every coarse triangle with its patch and one point per region", "[tetmesh]") {
    const Surface s = fixtures::two_cubes();
    const std::string poly = tetgen_poly(s, {{0.5, 0.5, 0.5}, {1.5, 0.5, 0.5}});
    std::istringstream in(poly);
    std::string line;
    std::vector<std::string> lines;
    while (std::getline(in, line))
        if (!line.empty() && line[0] != '#') lines.push_back(line);
    CHECK(lines[0] == std::to_string(s.num_vertices()) + " 3 0 0");
    CHECK(lines[1 + s.num_vertices()] == std::to_string(s.num_triangles()) + " 1");
    CHECK(lines[2 + s.num_vertices()] == "1 0 " + std::to_string(s.patches[0]));
    CHECK(lines[lines.size() - 3] == "2");
    CHECK(lines.back() == "1 1.5 0.5 0.5 2 0");
}
