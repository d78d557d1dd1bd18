// The crease rule with chains (core/crease_chains.h) that the simplifier, the smoother and
// bpm-info share: the rim of a lens (one even line of shallow edges) is a crease, the
// kinks of a noisy sphere are not, and the answer does not depend on how the triangles
// are stored.
#include <map>
#include <vector>

#include <catch2/catch.hpp>

#include "core/crease.h"
#include "core/crease_chains.h"
#include "fixtures_surfaces.h"

using namespace bpm;
using namespace bpm::detail;

namespace {

// Every edge of two triangles, once, in increasing (u, w).
std::vector<SheetEdge> sheet_edges(const Surface& s) {
    std::map<std::pair<int32_t, int32_t>, std::vector<int32_t>> at;
    for (int32_t t = 0; t < s.num_triangles(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int32_t a = s.triangles[size_t(t)][size_t(k)], b = s.triangles[size_t(t)][size_t((k + 1) % 3)];
            at[{std::min(a, b), std::max(a, b)}].push_back(t);
        }
    std::vector<SheetEdge> edges;
    for (const auto& [e, ts] : at)
        if (ts.size() == 2) edges.push_back({e.first, e.second, s.triangles[size_t(ts[0])], s.triangles[size_t(ts[1])]});
    return edges;
}

CreaseRule default_rule(const Surface& s) {
    CreaseRule rule;
    rule.feature_angle_degrees = 60.0;
    rule.chain_angle_degrees = 20.0;
    rule.min_chain_length = 0.1 * bounding_box_diagonal(s);
    return rule;
}

int count(const std::vector<uint8_t>& v) {
    int n = 0;
    for (const uint8_t x : v) n += x;
    return n;
}

}  // namespace

TEST_CASE("crease chains: the rim of a lens is one long crease below the feature angle",
          "[internal][core][crease]") {
    const Surface s = fixtures::ridged_lens(48, 12, 20.0);
    const std::vector<SheetEdge> edges = sheet_edges(s);
    const std::vector<uint8_t> crease = find_creases(s.vertices, edges, default_rule(s));
    int on_rim = 0;
    for (size_t e = 0; e < edges.size(); ++e) {
        const bool rim = s.vertices[size_t(edges[e].u)][2] == 0.0 && s.vertices[size_t(edges[e].w)][2] == 0.0;
        on_rim += rim ? 1 : 0;
        INFO("edge " << edges[e].u << "-" << edges[e].w);
        CHECK(bool(crease[e]) == rim);
    }
    CHECK(on_rim == 48);
    // Below the feature angle: CreaseTest alone finds none of them.
    CreaseRule off = default_rule(s);
    off.chain_angle_degrees = 180.0;
    CHECK(count(find_creases(s.vertices, edges, off)) == 0);
    // Longer than the rim (about 1.9 diagonals): not a crease.
    CreaseRule longer = default_rule(s);
    longer.min_chain_length = 2.0 * bounding_box_diagonal(s);
    CHECK(count(find_creases(s.vertices, edges, longer)) == 0);
    // Turned over triangles, edges in another order: the same answer.
    std::vector<SheetEdge> turned(edges.rbegin(), edges.rend());
    for (SheetEdge& e : turned) std::swap(e.t0[1], e.t0[2]);
    const std::vector<uint8_t> again = find_creases(s.vertices, turned, default_rule(s));
    CHECK(std::vector<uint8_t>(again.rbegin(), again.rend()) == crease);
}

TEST_CASE("crease chains: a line that turns more than 20 degrees at each vertex is no chain",
          "[internal][core][crease]") {
    // 12 segments around: the rim turns 30 degrees at each of its vertices.
    const Surface s = fixtures::ridged_lens(12, 6, 20.0);
    CHECK(count(find_creases(s.vertices, sheet_edges(s), default_rule(s))) == 0);
    // 24 around (15 degrees) but only 8 edges needed: a crease again.
    const Surface t = fixtures::ridged_lens(24, 6, 20.0);
    CHECK(count(find_creases(t.vertices, sheet_edges(t), default_rule(t))) == 24);
}

TEST_CASE("crease chains: the kinks of a noisy sphere stay what the feature angle says",
          "[internal][core][crease]") {
    const Surface s = fixtures::ridged_lens(48, 12, 0.0, 0.02);
    const std::vector<SheetEdge> edges = sheet_edges(s);
    int shallow = 0, sharp = 0;
    const CreaseTest over20(20.0), over60(60.0);
    std::vector<uint8_t> expected;
    for (const SheetEdge& e : edges) {
        shallow += over20.is_crease(s.vertices, e.t0, e.t1, e.u, e.w) ? 1 : 0;
        expected.push_back(over60.is_crease(s.vertices, e.t0, e.t1, e.u, e.w) ? 1 : 0);
        sharp += expected.back();
    }
    CHECK(shallow - sharp > 500);  // plenty of candidates
    CHECK(find_creases(s.vertices, edges, default_rule(s)) == expected);
}
