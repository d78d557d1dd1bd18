// The simplifier's input check on its own grid (simplify/input_intersections.h): its
// verdict must be check_intersections' on every surface it decides (clean, crossing,
// degenerate, with triangles too large for the grid's cells), and on random surfaces.
#include <cmath>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/check.h"
#include "bpm/surface.h"
#include "simplify/coarse_mesh.h"
#include "simplify/input_intersections.h"
#include "simplify/intersection_test.h"

using namespace bpm;
using namespace bpm::detail;

namespace {

// An n x n grid of squares over [0, 1]^2, two triangles each, at heights z(i, j).
template <class Height>
Surface height_field(int n, Height z) {
    Surface s;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) s.vertices.push_back({double(i) / n, double(j) / n, z(i, j)});
    const auto v = [n](int i, int j) { return int32_t(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            s.triangles.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
            s.triangles.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
        }
    s.patches.assign(s.triangles.size(), 0);
    return s;
}

// Adds a triangle with three new vertices.
void add_triangle(Surface& s, const Vec3& a, const Vec3& b, const Vec3& c) {
    const int32_t n = int32_t(s.vertices.size());
    s.vertices.insert(s.vertices.end(), {a, b, c});
    s.triangles.push_back({n, n + 1, n + 2});
    s.patches.push_back(0);
}

bool grid_verdict(const Surface& s) {
    const CoarseMesh mesh(s);
    const IntersectionTest test(mesh);
    return surely_passes_intersection_check(s, test.grid());
}

bool check_verdict(const Surface& s) { return check_intersections(s, CheckOptions{}, Context{}, "input").passed; }

}  // namespace

TEST_CASE("input check on the grid: clean and crossing surfaces", "[internal][simplify]") {
    const auto wavy = [](int i, int j) { return 0.05 * std::sin(0.7 * i) * std::cos(0.9 * j); };
    Surface s = height_field(12, wavy);
    CHECK(check_verdict(s));
    CHECK(grid_verdict(s));
    // A small triangle through the surface, far from every triangle by index.
    Surface crossing = s;
    add_triangle(crossing, {0.41, 0.43, -0.2}, {0.47, 0.43, 0.2}, {0.44, 0.49, 0.2});
    CHECK(!check_verdict(crossing));
    CHECK(!grid_verdict(crossing));
    // The same above the surface: no intersection.
    Surface above = s;
    add_triangle(above, {0.41, 0.43, 0.3}, {0.47, 0.43, 0.3}, {0.44, 0.49, 0.35});
    CHECK(check_verdict(above));
    CHECK(grid_verdict(above));
}

TEST_CASE("input check on the grid: degenerate triangles are left to the check", "[internal][simplify]") {
    Surface s = height_field(6, [](int, int) { return 0.0; });
    add_triangle(s, {2, 0, 0}, {3, 0, 0}, {4, 0, 0});  // collinear corners
    CHECK(!check_verdict(s));
    CHECK(!grid_verdict(s));
}

TEST_CASE("input check on the grid: triangles larger than the cells", "[internal][simplify]") {
    const auto flat = [](int, int) { return 0.0; };
    // A triangle spanning thousands of cells, below the surface: clean.
    Surface below = height_field(30, flat);
    add_triangle(below, {-20, -20, -0.5}, {20, -20, -0.5}, {0, 20, -0.5});
    CHECK(check_verdict(below));
    CHECK(grid_verdict(below));
    // Tilted through it: it cuts the surface.
    Surface through = height_field(30, flat);
    add_triangle(through, {-20, -20, -0.5}, {20, -20, -0.5}, {0, 20, 0.5});
    CHECK(!check_verdict(through));
    CHECK(!grid_verdict(through));
    // Two large triangles crossing each other, away from the surface.
    Surface pair = height_field(30, flat);
    add_triangle(pair, {-20, -20, 5}, {20, -20, 5}, {0, 20, 5});
    add_triangle(pair, {-20, 0, 3}, {20, 0, 3}, {0, 0.5, 8});
    CHECK(!check_verdict(pair));
    CHECK(!grid_verdict(pair));
}

TEST_CASE("input check on the grid: the check's verdict on random surfaces", "[internal][simplify]") {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int passed = 0, failed = 0;
    for (int round = 0; round < 60; ++round) {
        const double amplitude = 0.2 * unit(random);
        std::vector<double> heights(11 * 11);
        for (double& h : heights) h = amplitude * (unit(random) - 0.5);
        Surface s = height_field(10, [&](int i, int j) { return heights[size_t(j * 11 + i)]; });
        // A few small triangles near the surface: some cross it, some do not.
        for (int k = 0; k < 3; ++k) {
            const Vec3 c{unit(random), unit(random), 0.3 * (unit(random) - 0.5)};
            const double r = 0.1 * unit(random) + 0.01;
            add_triangle(s, c + Vec3{r, 0, 0.5 * r * (unit(random) - 0.5)}, c + Vec3{-r, r, r * (unit(random) - 0.5)},
                         c + Vec3{0, -r, r * (unit(random) - 0.5)});
        }
        const bool check = check_verdict(s);
        CHECK(grid_verdict(s) == check);
        (check ? passed : failed) += 1;
    }
    // Both verdicts occur (the test compares something).
    CHECK(passed > 5);
    CHECK(failed > 5);
}
