// PathStore (simplify/path_store.h): the paths read back as assigned, a path's crossings
// stay in place while other paths change, and blocks given up are handed out again (the
// store exists to cost less memory than a vector per path).
#include <cstdint>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "simplify/path_store.h"

using namespace bpm::detail;

namespace {

std::vector<Crossing> random_path(std::mt19937& random, size_t n) {
    std::vector<Crossing> out(n);
    for (Crossing& c : out) {
        c.a = int32_t(random() % 1000);
        c.b = c.a + 1 + int32_t(random() % 1000);
        c.s = double(random() % 997) / 997.0;
        c.sigma = double(random() % 991) / 991.0;
    }
    return out;
}

bool same(const ConstRange<Crossing>& got, const std::vector<Crossing>& want) {
    if (got.size() != want.size()) return false;
    for (size_t i = 0; i < want.size(); ++i)
        if (got[i].a != want[i].a || got[i].b != want[i].b || got[i].s != want[i].s || got[i].sigma != want[i].sigma)
            return false;
    return true;
}

}  // namespace

TEST_CASE("path store: paths read back as assigned, others stay in place", "[internal][simplify]") {
    std::mt19937 random(11);
    PathStore store;
    const size_t edges = 500;
    store.reset(edges);
    REQUIRE(store.size() == edges);
    std::vector<std::vector<Crossing>> want(edges);
    for (size_t e = 0; e < edges; ++e) CHECK(store[e].empty());

    // Path 0 is held by a reader throughout: its range must stay valid and unchanged.
    want[0] = random_path(random, 5);
    store.assign(0, want[0].data(), want[0].size());
    const ConstRange<Crossing> held = store[0];
    for (int step = 0; step < 20000; ++step) {
        const size_t e = 1 + random() % (edges - 1);
        // Mostly short paths, now and then an empty one or a long one.
        const uint32_t r = random() % 100;
        const size_t n = r < 10 ? 0 : (r < 98 ? 1 + random() % 12 : 100 + random() % 400);
        want[e] = random_path(random, n);
        store.assign(e, want[e].data(), want[e].size());
        REQUIRE(same(store[e], want[e]));
    }
    for (size_t e = 0; e < edges; ++e) REQUIRE(same(store[e], want[e]));
    CHECK(store[0].begin() == held.begin());
    CHECK(same(held, want[0]));
    size_t total = 0;
    for (const auto& p : want) total += p.size();
    CHECK(store.total_crossings() == total);
}

TEST_CASE("path store: blocks given up are reused, paths larger than a chunk work", "[internal][simplify]") {
    std::mt19937 random(5);
    PathStore store;
    const size_t edges = 1000;
    store.reset(edges);
    // Churn: every path rewritten many times with 0 to 8 crossings. Live: at most 8 per
    // path, in blocks of at most 8; the room must stay near that, not grow with the
    // number of assignments (a store that never reused a block would need 200 times it).
    std::vector<std::vector<Crossing>> want(edges);
    for (int round = 0; round < 200; ++round)
        for (size_t e = 0; e < edges; ++e) {
            want[e] = random_path(random, random() % 9);
            store.assign(e, want[e].data(), want[e].size());
        }
    for (size_t e = 0; e < edges; ++e) REQUIRE(same(store[e], want[e]));
    CHECK(store.reserved_crossings() <= 4 * 8 * edges);

    // A path longer than a chunk (2^14 crossings), then shorter again, then empty.
    const std::vector<Crossing> longest = random_path(random, 40000);
    store.assign(3, longest.data(), longest.size());
    CHECK(same(store[3], longest));
    for (size_t e = 0; e < edges; ++e)
        if (e != 3) REQUIRE(same(store[e], want[e]));
    store.assign(3, want[3].data(), want[3].size());
    CHECK(same(store[3], want[3]));
    store.assign(3, nullptr, 0);
    CHECK(store[3].empty());
    // Its block is reused by the next path of its size.
    const size_t reserved = store.reserved_crossings();
    store.assign(4, longest.data(), longest.size());
    CHECK(store.reserved_crossings() == reserved);
    CHECK(same(store[4], longest));

    store.release();
    CHECK(store.empty());
    CHECK(store.reserved_crossings() == 0);
}
