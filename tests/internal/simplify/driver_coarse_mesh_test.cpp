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

TEST_CASE("coarse mesh: shrink_to_fit keeps every triangle list, also the spilled ones", "[internal][simplify]") {
    // shrink_to_fit() stores the per-vertex lists as one flat array (CSR) before phi is
    // exported; a vertex of degree > 15 keeps its list outside its block until then.
    const Surface s = grid_surface();
    CoarseMesh mesh(s);
    const int32_t nv = s.num_vertices();
    for (int32_t i = 1; i + 1 < nv; ++i) mesh.add_triangle({0, i, i + 1}, 0);  // vertex 0: degree 24
    mesh.remove_triangle(0);
    mesh.remove_triangle(mesh.triangle_capacity() - 1);
    for (int32_t t = 2; t < 32; t += 2) mesh.remove_triangle(t);  // vertices 6 .. 18 become isolated or thin
    REQUIRE(mesh.triangles_of(0).size() > 15);
    std::vector<std::vector<int32_t>> before(static_cast<size_t>(nv));
    std::vector<bool> alive_before(static_cast<size_t>(nv));
    for (int32_t v = 0; v < nv; ++v) {
        before[size_t(v)].assign(mesh.triangles_of(v).begin(), mesh.triangles_of(v).end());
        alive_before[size_t(v)] = mesh.vertex_alive(v);
    }
    std::vector<int32_t> origin_before, origin_after;
    const Surface surface_before = mesh.to_surface(origin_before);
    mesh.shrink_to_fit();
    for (int32_t v = 0; v < nv; ++v) {
        const auto list = mesh.triangles_of(v);
        CHECK(std::vector<int32_t>(list.begin(), list.end()) == before[size_t(v)]);
        CHECK(mesh.vertex_alive(v) == alive_before[size_t(v)]);
    }
    // has_edge() and find_triangle() are not available after shrink_to_fit() (their
    // neighbour bits are freed); the lists they merge are checked above.
    const Surface surface_after = mesh.to_surface(origin_after);
    CHECK(origin_after == origin_before);
    CHECK(surface_after.triangles == surface_before.triangles);
    CHECK(surface_after.vertices == surface_before.vertices);
}
