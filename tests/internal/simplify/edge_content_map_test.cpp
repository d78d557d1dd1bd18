// EdgeContentMap (simplify/edge_content_map.h) against a model made of two std::vectors
// per key with the semantics the embedding relied on before the map stored its ids in a
// block pool: append at the end of a list, take one occurrence off by moving the last
// into its place, an entry exactly while it holds an id. Orders must match exactly (the
// simplifier's outputs were proven byte-identical with that).
#include <algorithm>
#include <cstdint>
#include <map>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "simplify/edge_content_map.h"

using namespace bpm::detail;

namespace {

struct ModelContent {
    std::vector<int32_t> vertices, crossing_edges;
};

void erase_one(std::vector<int32_t>& list, int32_t value) {
    auto it = std::find(list.begin(), list.end(), value);
    if (it == list.end()) return;
    *it = list.back();
    list.pop_back();
}

bool same(const ConstRange<int32_t>& got, const std::vector<int32_t>& want) {
    return got.size() == want.size() && std::equal(want.begin(), want.end(), got.begin());
}

}  // namespace

TEST_CASE("edge content map: lists in the order of the vector model, entries while non-empty", "[internal][simplify]") {
    std::mt19937 random(3);
    EdgeContentMap map;
    std::map<uint64_t, ModelContent> model;
    const uint64_t keys = 300;
    for (int step = 0; step < 200000; ++step) {
        // Phases: the map fills up, drains to a few entries (the table shrinks), fills again.
        const int phase = (step / 50000) % 2;
        const uint64_t key = (random() % keys) * 1000003u;
        const int32_t id = int32_t(random() % 24);
        const uint32_t op = random() % 100;
        ModelContent& m = model[key];
        if (op < (phase == 0 ? 30u : 10u)) {
            map.add_vertex(key, id);
            m.vertices.push_back(id);
        } else if (op < (phase == 0 ? 60u : 20u)) {
            map.add_crossing_edge(key, id);
            m.crossing_edges.push_back(id);
        } else if (op < 80) {
            map.remove_vertex(key, id);
            erase_one(m.vertices, id);
        } else {
            map.remove_crossing_edge(key, id);
            erase_one(m.crossing_edges, id);
        }
        if (m.vertices.empty() && m.crossing_edges.empty()) model.erase(key);
        const EdgeContentMap::Entry* e = map.find(key);
        REQUIRE((e != nullptr) == (model.count(key) == 1));
        if (e) {
            const EdgeContentView view = map.view(*e);
            REQUIRE(same(view.vertices, model[key].vertices));
            REQUIRE(same(view.crossing_edges, model[key].crossing_edges));
        }
        if (step % 1000 == 999) {
            REQUIRE(map.size() == model.size());
            size_t visited = 0;
            map.for_each([&](uint64_t k, const EdgeContentView& view) {
                ++visited;
                const auto it = model.find(k);
                REQUIRE(it != model.end());
                CHECK(same(view.vertices, it->second.vertices));
                CHECK(same(view.crossing_edges, it->second.crossing_edges));
            });
            CHECK(visited == model.size());
        }
    }
    map.release();
    CHECK(map.size() == 0);
    CHECK(map.find(0) == nullptr);
}
