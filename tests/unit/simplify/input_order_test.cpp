// simplify() runs on its own numbering of the input (Morton order, libbpm/src/simplify/
// vertex_order.h) and maps everything back: the caller sees the input as given and only
// the caller's ids. The inputs here are given in a scrambled order, so that a missing or
// wrong mapping of any id (coarse_vertex_origin, node_original_vertex, node_original_edge
// and its parameter, piece_original_triangle, the recorded steps, the slivers, the
// messages) names other vertices or triangles and fails the checker.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

#include "bpm/bpm_file.h"
#include "bpm/check.h"
#include "bpm/errors.h"
#include "bpm/simplify.h"
#include "fixtures_surfaces.h"
#include "test_support.h"

using namespace bpm;

namespace {

// A fixed pseudo-random permutation of 0..n-1 (own generator: the same on every platform).
std::vector<int32_t> scrambled_ids(size_t n, uint64_t seed) {
    std::vector<int32_t> p(n);
    std::iota(p.begin(), p.end(), 0);
    uint64_t x = seed;
    for (size_t i = n; i > 1; --i) {
        x = x * 6364136223846793005ULL + 1442695040888963407ULL;
        std::swap(p[i - 1], p[size_t((x >> 33) % i)]);
    }
    return p;
}

// `s` with its vertices, triangles (with their patches) and triangle corners in a
// scrambled order, and a vertex array of two components (v, -v) for vertex v, which must
// come back as given.
Surface scrambled(const Surface& s) {
    const std::vector<int32_t> vertex_from = scrambled_ids(s.vertices.size(), 17);  // new -> old
    const std::vector<int32_t> triangle_from = scrambled_ids(s.triangles.size(), 29);
    std::vector<int32_t> new_id(s.vertices.size());
    for (size_t i = 0; i < vertex_from.size(); ++i) new_id[size_t(vertex_from[i])] = int32_t(i);
    Surface out;
    for (int32_t v : vertex_from) out.vertices.push_back(s.vertices[size_t(v)]);
    for (size_t i = 0; i < triangle_from.size(); ++i) {
        const Tri& t = s.triangles[size_t(triangle_from[i])];
        const int r = int(i % 3);  // rotate the corners too (same orientation)
        out.triangles.push_back({new_id[size_t(t[size_t(r)])], new_id[size_t(t[size_t((r + 1) % 3)])],
                                 new_id[size_t(t[size_t((r + 2) % 3)])]});
        out.patches.push_back(s.patches[size_t(triangle_from[i])]);
    }
    VertexArray id{"id", 2, {}};
    for (size_t v = 0; v < out.vertices.size(); ++v) id.values.insert(id.values.end(), {double(v), -double(v)});
    out.vertex_data.push_back(id);
    return out;
}

// Every check the checker has for a simplifier's output, the replay of the recorded steps included.
void require_all_checks_pass(const BpmFile& f) {
    test_support::require_valid_parametrization(f.param);
    const CheckResult intersections = check_intersections(f.param.coarse);
    INFO(test_support::check_text(intersections));
    CHECK(intersections.passed);
    const CheckResult replay = check_replay(f);
    INFO(test_support::check_text(replay));
    CHECK(replay.passed);
}

BpmFile simplified(const Surface& s, SimplifyOptions o, SimplifyResult* result = nullptr) {
    o.record_steps = true;
    BpmFile f;
    SimplifyResult r = simplify(s, o, Context{}, f.param);
    f.simplification_steps = r.steps;
    f.provenance.push_back({"bpm-simplify", "test", "simplify", ""});
    if (result) *result = std::move(r);
    return f;
}

// What the caller must see: the input as given, and ids that mean the caller's vertices.
void require_callers_ids(const Surface& input, const Parametrization& p) {
    CHECK(p.original.vertices == input.vertices);
    CHECK(p.original.triangles == input.triangles);
    CHECK(p.original.patches == input.patches);
    REQUIRE(p.original.vertex_data.size() == 1);
    CHECK(p.original.vertex_data[0].values == input.vertex_data[0].values);
    // Coarse vertices sorted by the caller's id, each where its original vertex is.
    CHECK(std::is_sorted(p.coarse_vertex_origin.begin(), p.coarse_vertex_origin.end()));
    CHECK(std::adjacent_find(p.coarse_vertex_origin.begin(), p.coarse_vertex_origin.end()) ==
          p.coarse_vertex_origin.end());
    for (size_t i = 0; i < p.coarse_vertex_origin.size(); ++i)
        CHECK(p.coarse.vertices[i] == input.vertices[size_t(p.coarse_vertex_origin[i])]);
    // Every node's image is where its kind says, on the caller's vertices and edges.
    for (int64_t n = 0; n < p.num_nodes(); ++n) {
        const size_t i = size_t(n);
        if (p.node_kind[i] == NodeKind::EdgeCrossing) CHECK(p.node_original_edge[i][0] < p.node_original_edge[i][1]);
        // To the bit, as the export writes it (an edge's ends swapped in the caller's ids:
        // the image again from 1 - s).
        CHECK(p.node_image[i] == node_image_from_kind(p, n));
    }
}

}  // namespace

TEST_CASE("simplify of a scrambled input: the caller's ids everywhere, every check passes", "[simplify][order]") {
    struct Case {
        const char* name;
        Surface surface;
        double ratio;
    };
    const std::vector<Case> cases = {
        {"torus", fixtures::torus(30, 20), 0.15},
        {"two cubes (two materials)", fixtures::two_cubes(4), 0.3},
        {"octants (eight materials)", fixtures::octants(3), 0.3},
    };
    for (const Case& c : cases) {
        INFO(c.name);
        const Surface input = scrambled(c.surface);
        SimplifyOptions o;
        o.target_ratio = c.ratio;
        o.threads = 1;
        SimplifyResult result;
        const BpmFile f = simplified(input, o, &result);
        CHECK(result.removed > 0);
        require_callers_ids(input, f.param);
        require_all_checks_pass(f);
        // The same surface in its own order gives a valid result of the same size class.
        const BpmFile plain = simplified([&] {
            Surface s = c.surface;
            s.vertex_data = input.vertex_data;
            return s;
        }(), o);
        require_all_checks_pass(plain);
        // Threads 1 and 2: the same output.
        o.threads = 2;
        const BpmFile two = simplified(input, o);
        CHECK(two.param.coarse.triangles == f.param.coarse.triangles);
        CHECK(two.param.coarse_vertex_origin == f.param.coarse_vertex_origin);
        CHECK(two.param.pieces == f.param.pieces);
        CHECK(two.param.node_original_edge == f.param.node_original_edge);
        CHECK(two.param.piece_original_triangle == f.param.piece_original_triangle);
        CHECK(two.simplification_steps->vertex == f.simplification_steps->vertex);
    }
}

TEST_CASE("simplify of a scrambled input taken over and in place: the input comes back as given",
          "[simplify][order]") {
    const Surface input = scrambled(fixtures::torus(24, 16));
    SimplifyOptions o;
    o.target_ratio = 0.2;
    Parametrization copied;
    simplify(input, o, Context{}, copied);
    Parametrization moved;
    simplify(Surface(input), o, Context{}, moved);
    Parametrization in_place;
    in_place.original = input;
    simplify(in_place.original, o, Context{}, in_place);
    for (const Parametrization* p : {&copied, &moved, &in_place}) {
        require_callers_ids(input, *p);
        CHECK(p->coarse.triangles == copied.coarse.triangles);
        CHECK(p->piece_original_triangle == copied.piece_original_triangle);
        CHECK(p->node_original_vertex == copied.node_original_vertex);
        test_support::require_valid_parametrization(*p);
    }
}

TEST_CASE("simplify's slivers name the caller's vertices", "[simplify][order]") {
    // A limit no triangle of the grid meets (its right triangles have R/r 2.41): every
    // triangle stays and is reported (simplify_test.cpp, the same on the grid in order).
    const Surface input = scrambled(fixtures::cube(3));
    SimplifyOptions o;
    o.target_ratio = 0.5;
    o.max_aspect_ratio = 2.2;
    Parametrization p;
    const SimplifyResult r = simplify(input, o, Context{}, p);
    REQUIRE(!r.worst_slivers.empty());
    for (const SliverReport& s : r.worst_slivers) {
        // Its corners are a coarse triangle's, named by the caller's ids.
        Tri corners{};
        for (int k = 0; k < 3; ++k) {
            const auto it = std::lower_bound(p.coarse_vertex_origin.begin(), p.coarse_vertex_origin.end(),
                                             s.vertices[size_t(k)]);
            REQUIRE(it != p.coarse_vertex_origin.end());
            REQUIRE(*it == s.vertices[size_t(k)]);
            corners[size_t(k)] = int32_t(it - p.coarse_vertex_origin.begin());
        }
        std::sort(corners.begin(), corners.end());
        bool found = false;
        for (Tri t : p.coarse.triangles) {
            std::sort(t.begin(), t.end());
            found = found || t == corners;
        }
        CHECK(found);
        Vec3 c{};
        for (int32_t v : s.vertices)
            for (int k = 0; k < 3; ++k) c[size_t(k)] += input.vertices[size_t(v)][size_t(k)] / 3;
        for (int k = 0; k < 3; ++k) CHECK(std::abs(c[size_t(k)] - s.centroid[size_t(k)]) < 1e-12);
    }
}

TEST_CASE("simplify names the caller's triangles when the input intersects itself", "[simplify][order]") {
    // A scrambled cube and a tetrahedron that pierces its top face.
    Surface s = fixtures::cube(4);
    const int32_t b = s.num_vertices();
    s.vertices.insert(s.vertices.end(), {{0.4, 0.4, 0.8}, {0.6, 0.4, 0.8}, {0.5, 0.6, 0.8}, {0.5, 0.5, 1.3}});
    for (const Tri& t : fixtures::tetrahedron().triangles) {
        s.triangles.push_back({b + t[0], b + t[1], b + t[2]});
        s.patches.push_back(2);
    }
    const Surface input = scrambled(s);
    CheckOptions first;
    first.max_problems = 1;
    const CheckResult direct = check_intersections(input, first, Context{}, "input intersections");
    REQUIRE_FALSE(direct.passed);
    REQUIRE(direct.problems.size() == 1);
    const std::string named = direct.problems[0].describe();  // the caller's triangle ids
    for (int threads : {1, 2}) {
        INFO(threads << " threads");
        SimplifyOptions o;
        o.target_ratio = 0.5;
        o.threads = threads;
        Parametrization p;
        try {
            simplify(input, o, Context{}, p);
            FAIL("no error for a self-intersecting input");
        } catch (const AlgorithmError& e) {
            const std::string what = e.what();
            INFO(what);
            // The caller's ids, then (the cube and the tetrahedron are patches 1 and 2)
            // that the pair lies in two patches.
            CHECK(what.find("first: " + named + ", in patches 1 and 2 (") != std::string::npos);
        }
    }
}
