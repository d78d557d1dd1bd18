// The layout rules of phi are visited once (libbpm/src/phi/phi_layout.cpp) for the .bpm
// writer/reader and for bpm-check's format check. These tests fail if the two drift
// apart again: a layout fault one of them lets through and the other refuses.
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "bpm/bpm_file.h"
#include "bpm/check.h"
#include "bpm/errors.h"
#include "fixtures_surfaces.h"

using namespace bpm;

namespace {

// The writer's refusal, or "" when it writes.
std::string writer_refusal(const Parametrization& p) {
    BpmFile f;
    f.param = p;
    f.units = "mm";
    f.provenance.push_back({"test", "0", "test", ""});
    try {
        write_bpm_to_memory(f);
    } catch (const OutputError& e) {
        return e.what();
    }
    return {};
}

}  // namespace

TEST_CASE("a layout fault of phi is refused by the writer and reported by the format check alike", "[format][check]") {
    const Parametrization base = fixtures::flipped_diagonal_parametrization(fixtures::cube());
    REQUIRE(writer_refusal(base).empty());
    REQUIRE(check_format(base).passed);
    int64_t crossing = -1, vertex = -1;
    for (int64_t n = 0; n < base.num_nodes(); ++n) {
        if (crossing < 0 && base.node_kind[n] == NodeKind::EdgeCrossing) crossing = n;
        if (vertex < 0 && base.node_kind[n] != NodeKind::EdgeCrossing) vertex = n;
    }
    REQUIRE(crossing >= 0);
    REQUIRE(vertex >= 0);
    const double nan = std::nan("");
    // {what, the dataset the writer must name, the element check_format must name, mutation}
    struct Case {
        const char* what;
        const char* dataset;
        std::pair<std::string, int64_t> id;
        std::function<void(Parametrization&)> mutate;
    };
    const std::vector<Case> cases = {
        {"non-finite original vertex", "/original/vertices", {"original_vertex", 2},
         [&](Parametrization& p) { p.original.vertices[2][1] = nan; }},
        {"coarse triangle corner out of range", "/coarse/triangles", {"coarse_triangle", 3},
         [&](Parametrization& p) { p.coarse.triangles[3][2] = 1000; }},
        {"one patch id too few", "/coarse/patches", {"", -1}, [&](Parametrization& p) { p.coarse.patches.pop_back(); }},
        {"vertex origin out of range", "/coarse/vertex_origin", {"coarse_vertex", 1},
         [&](Parametrization& p) { p.coarse_vertex_origin[1] = -4; }},
        {"node array one row short", "/phi/node_image", {"", -1}, [&](Parametrization& p) { p.node_image.pop_back(); }},
        {"node offsets decreasing", "/phi/node_offsets", {"coarse_triangle", 2},
         [&](Parametrization& p) { p.node_offsets[2] = p.node_offsets[3] + 1; }},
        {"piece offsets ending early", "/phi/piece_offsets", {"", -1},
         [&](Parametrization& p) { p.piece_offsets.back() -= 1; }},
        {"invalid node kind", "/phi/node_kind", {"node", vertex},
         [&](Parametrization& p) { p.node_kind[vertex] = NodeKind(5); }},
        {"non-finite barycentric", "/phi/node_barycentric", {"node", vertex},
         [&](Parametrization& p) { p.node_barycentric[vertex][2] = nan; }},
        {"crossing on a reversed edge", "/phi/node_original_edge", {"node", crossing},
         [&](Parametrization& p) { std::swap(p.node_original_edge[crossing][0], p.node_original_edge[crossing][1]); }},
        {"crossing with a NaN parameter", "/phi/node_edge_parameter", {"node", crossing},
         [&](Parametrization& p) { p.node_edge_parameter[crossing] = nan; }},
        {"original vertex out of range", "/phi/node_original_vertex", {"node", vertex},
         [&](Parametrization& p) { p.node_original_vertex[vertex] = p.original.num_vertices(); }},
        {"piece corner outside its triangle's nodes", "/phi/pieces", {"piece", 4},
         [&](Parametrization& p) { p.pieces[4][1] = 100; }},
        {"piece into a missing original triangle", "/phi/piece_original_triangle", {"piece", 0},
         [&](Parametrization& p) { p.piece_original_triangle[0] = p.original.num_triangles(); }},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        Parametrization p = base;
        c.mutate(p);
        const std::string refusal = writer_refusal(p);
        CHECK(refusal.find(std::string(c.dataset) + ":") != std::string::npos);
        const CheckResult r = check_format(p);
        REQUIRE_FALSE(r.passed);
        REQUIRE(r.problems.size() == 1);  // one fault, one problem: the rule is visited once
        if (c.id.second >= 0) CHECK(r.problems[0].id(c.id.first) == c.id.second);
    }
}
