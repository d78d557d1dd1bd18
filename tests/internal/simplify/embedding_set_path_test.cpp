// Embedding::set_path (simplify/embedding.h): the coarse edges' lists of crossing
// original edges follow the paths. set_path changes only the lists of the coarse edges a
// path leaves or newly crosses (a removal re-cuts a path inside its star and keeps its
// crossings elsewhere); the lists must hold, as multisets, exactly what the paths say.
#include <algorithm>
#include <cstdint>
#include <map>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "core/edge_key.h"
#include "fixtures_surfaces.h"
#include "simplify/embedding.h"

using namespace bpm;
using namespace bpm::detail;

namespace {

// Coarse edge key -> the original edges crossing it, sorted, from the paths themselves.
std::map<uint64_t, std::vector<int32_t>> expected_crossing_edges(const Embedding& emb) {
    std::map<uint64_t, std::vector<int32_t>> out;
    for (int32_t e = 0; e < int32_t(emb.path.size()); ++e)
        for (const Crossing& c : emb.path[size_t(e)]) out[edge_key(c.a, c.b)].push_back(e);
    for (auto& entry : out) std::sort(entry.second.begin(), entry.second.end());
    return out;
}

// The same from the embedding's lists (sorted: their order is unspecified).
std::map<uint64_t, std::vector<int32_t>> listed_crossing_edges(const Embedding& emb) {
    std::map<uint64_t, std::vector<int32_t>> out;
    emb.edge_content.for_each([&](uint64_t key, const EdgeContentView& content) {
        CHECK(!(content.vertices.empty() && content.crossing_edges.empty()));  // no empty entry stays
        if (content.crossing_edges.empty()) return;
        auto& list = out[key];
        list.assign(content.crossing_edges.begin(), content.crossing_edges.end());
        std::sort(list.begin(), list.end());
    });
    return out;
}

Crossing crossing(int32_t a, int32_t b) { return {std::min(a, b), std::max(a, b), 0.5, 0.5}; }

}  // namespace

TEST_CASE("embedding: set_path keeps the coarse edges' crossing lists equal to the paths", "[internal][simplify]") {
    const Surface s = fixtures::cube(2);
    Embedding emb;
    emb.init_identity(s, s.num_triangles());
    REQUIRE(emb.edges.size() >= 4);

    // Kept, left, newly crossed, and crossed twice by one path.
    emb.set_path(0, {crossing(1, 2), crossing(2, 3), crossing(2, 3)});
    emb.set_path(1, {crossing(2, 3)});
    CHECK(listed_crossing_edges(emb) == expected_crossing_edges(emb));
    emb.set_path(0, {crossing(2, 3), crossing(3, 4)});  // leaves 1-2, crosses 2-3 once less, adds 3-4
    CHECK(listed_crossing_edges(emb) == expected_crossing_edges(emb));
    CHECK(emb.edge_content.find(edge_key(1, 2)) == nullptr);
    emb.set_path(0, {});
    emb.set_path(1, {});
    CHECK(emb.edge_content.size() == 0);

    // Random paths over a few coarse edges, rewritten many times, some in part.
    std::mt19937 random(7);
    const int32_t num_paths = 4, num_coarse = 6;
    auto random_crossing = [&] {
        const int32_t a = int32_t(random() % num_coarse);
        return crossing(a, (a + 1 + int32_t(random() % (num_coarse - 1))) % num_coarse);
    };
    for (int step = 0; step < 300; ++step) {
        const int32_t e = int32_t(random() % num_paths);
        std::vector<Crossing> path(emb.path[size_t(e)].begin(), emb.path[size_t(e)].end());
        // Keep a random run of the old crossings (as a removal does), replace the rest.
        const size_t keep = path.empty() ? 0 : random() % (path.size() + 1);
        path.resize(keep);
        const int added = int(random() % 4);
        for (int k = 0; k < added; ++k) path.insert(path.begin() + long(random() % (path.size() + 1)), random_crossing());
        const uint32_t version = emb.path_version[size_t(e)];
        emb.set_path(e, path);
        CHECK(emb.path_version[size_t(e)] == version + 1);
        REQUIRE(emb.path[size_t(e)].size() == path.size());
        REQUIRE(listed_crossing_edges(emb) == expected_crossing_edges(emb));
    }
}
