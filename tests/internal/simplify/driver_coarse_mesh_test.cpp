// The adjacency lookups of the coarse mesh (simplify/coarse_mesh.h): has_edge() and
// find_triangle() merge the sorted triangle lists of the vertices, so they must agree
// with a scan of the triangles' corners after any sequence of removals and additions
// (the lists stay sorted only because new triangles get the largest id).
#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/surface.h"
#include "simplify/coarse_mesh.h"

using namespace bpm;
using namespace bpm::detail;

namespace {

// A 5 x 5 grid of vertices split into 32 triangles.
Surface grid_surface() {
    Surface s;
    const int n = 5;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) s.vertices.push_back({double(i), double(j), 0.0});
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const int32_t a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
            s.triangles.push_back({a, b, c});
            s.triangles.push_back({a, c, d});
        }
    s.patches.assign(s.triangles.size(), 0);
    return s;
}

bool scan_has_edge(const CoarseMesh& m, int32_t a, int32_t b) {
    for (int32_t t = 0; t < m.triangle_capacity(); ++t) {
        if (!m.alive(t)) continue;
        const Tri& c = m.triangle(t);
        const bool ha = c[0] == a || c[1] == a || c[2] == a;
        const bool hb = c[0] == b || c[1] == b || c[2] == b;
        if (ha && hb) return true;
    }
    return false;
}

int32_t scan_find_triangle(const CoarseMesh& m, int32_t a, int32_t b, int32_t c) {
    for (int32_t t = 0; t < m.triangle_capacity(); ++t) {
        if (!m.alive(t)) continue;
        const Tri& x = m.triangle(t);
        auto has = [&](int32_t v) { return x[0] == v || x[1] == v || x[2] == v; };
        if (has(a) && has(b) && has(c)) return t;
    }
    return -1;
}

}  // namespace

TEST_CASE("coarse mesh: has_edge and find_triangle agree with a scan after edits", "[internal][simplify]") {
    const Surface s = grid_surface();
    CoarseMesh mesh(s);
    std::mt19937 rng(7);
    const int32_t nv = s.num_vertices();
    for (int round = 0; round < 40; ++round) {
        // Remove a random alive triangle, add a random new one (larger id than all).
        std::vector<int32_t> alive;
        for (int32_t t = 0; t < mesh.triangle_capacity(); ++t)
            if (mesh.alive(t)) alive.push_back(t);
        if (!alive.empty()) mesh.remove_triangle(alive[rng() % alive.size()]);
        if (round % 3 != 2) {
            const int32_t a = int32_t(rng() % nv), b = int32_t(rng() % nv), c = int32_t(rng() % nv);
            if (a != b && b != c && a != c) mesh.add_triangle({a, b, c}, 0);
        }
        for (int32_t v = 0; v < nv; ++v) {
            const auto& list = mesh.triangles_of(v);
            REQUIRE(std::is_sorted(list.begin(), list.end()));
        }
        for (int32_t a = 0; a < nv; ++a)
            for (int32_t b = 0; b < nv; ++b) {
                REQUIRE(mesh.has_edge(a, b) == scan_has_edge(mesh, a, b));
                const int32_t c = (a + b + round) % nv;
                REQUIRE(mesh.find_triangle(a, b, c) == scan_find_triangle(mesh, a, b, c));
            }
    }
}
