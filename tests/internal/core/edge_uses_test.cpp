// The sides of a surface's triangles grouped by edge (core/edge_uses.h), which reading a
// surface uses for the orientation warning and the boundary edges of find_open_seam: every
// edge once in (smaller, larger) order with its uses in triangle order and their
// direction, the same as a sort of all sides would give, also at a vertex with more sides
// than the insertion sort takes (the stable sort), and sides a validation refuses skipped.
#include <algorithm>
#include <tuple>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/surface.h"
#include "core/edge_uses.h"

using namespace bpm;
using bpm::detail::EdgeUses;

namespace {

// (smaller, larger, triangle, ascending) of every use, as for_each_edge hands them over.
using Row = std::tuple<int32_t, int32_t, int32_t, bool>;

std::vector<Row> visited(const Surface& s) {
    std::vector<Row> rows;
    EdgeUses(s).for_each_edge([&](int32_t a, int32_t b, const EdgeUses::Use* uses, size_t count) {
        REQUIRE(count >= 1);
        for (size_t i = 0; i < count; ++i) {
            CHECK(uses[i].larger == b);
            rows.emplace_back(a, b, uses[i].triangle(), uses[i].ascending());
        }
    });
    return rows;
}

// The same by sorting every valid side by edge and triangle (stably: a triangle with a
// repeated corner has two sides on one edge, in corner order).
std::vector<Row> sorted_sides(const Surface& s) {
    std::vector<Row> rows;
    const int32_t nv = s.num_vertices();
    for (int32_t t = 0; t < s.num_triangles(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int32_t a = s.triangles[size_t(t)][size_t(k)], b = s.triangles[size_t(t)][size_t((k + 1) % 3)];
            if (a < 0 || b < 0 || a >= nv || b >= nv || a == b) continue;
            rows.emplace_back(std::min(a, b), std::max(a, b), t, a < b);
        }
    std::stable_sort(rows.begin(), rows.end(), [](const Row& x, const Row& y) {
        return std::make_tuple(std::get<0>(x), std::get<1>(x), std::get<2>(x)) <
               std::make_tuple(std::get<0>(y), std::get<1>(y), std::get<2>(y));
    });
    return rows;
}

// A fan of n triangles around vertex 0 (an open disk; n > 32 sides at vertex 0 take the
// stable sort), listed from the last to the first so that the sort has work to do.
Surface fan(int32_t n) {
    Surface s;
    s.vertices.push_back({0, 0, 0});
    for (int32_t i = 0; i <= n; ++i) s.vertices.push_back({double(i), 1, 0});
    for (int32_t i = n - 1; i >= 0; --i) s.triangles.push_back({0, i + 1, i + 2});
    s.patches.assign(s.triangles.size(), 0);
    return s;
}

}  // namespace

TEST_CASE("edge uses: a tetrahedron's sides grouped by edge, in triangle order", "[internal][core]") {
    Surface s;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    s.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
    s.patches = {0, 0, 0, 0};
    const std::vector<Row> rows = visited(s);
    CHECK(rows == sorted_sides(s));
    REQUIRE(rows.size() == 12);
    // Edge {0, 1}: triangle 0 runs 1 -> 0, triangle 1 runs 0 -> 1.
    CHECK(rows[0] == Row{0, 1, 0, false});
    CHECK(rows[1] == Row{0, 1, 1, true});
    CHECK(EdgeUses(s).boundary_edges().empty());
}

TEST_CASE("edge uses: boundary edges of an open fan, and a vertex with many sides", "[internal][core]") {
    for (int32_t n : {3, 40}) {
        const Surface s = fan(n);
        CHECK(visited(s) == sorted_sides(s));
        const auto boundary = EdgeUses(s).boundary_edges();
        // The rim (i, i + 1) and the two outer spokes.
        REQUIRE(boundary.size() == size_t(n) + 2);
        CHECK(boundary.front() == std::pair<int32_t, int32_t>{0, 1});
        CHECK(boundary[1] == std::pair<int32_t, int32_t>{0, n + 1});
        CHECK(std::is_sorted(boundary.begin(), boundary.end()));
    }
}

TEST_CASE("edge uses: sides with a repeated corner or an index out of range are skipped", "[internal][core]") {
    Surface s;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    s.triangles = {{0, 1, 2}, {0, 0, 1}, {0, 1, 7}, {-1, 1, 2}};
    s.patches = {0, 0, 0, 0};
    CHECK(visited(s) == sorted_sides(s));
    CHECK(visited(s).size() == 3 + 2 + 1 + 1);
}
