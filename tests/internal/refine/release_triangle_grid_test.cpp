// The triangle grid as bpm-refine's release step uses it (core/triangle_grid.h, built on
// the surface, a moved triangle taken out with its old corners and put back with its new
// ones): for any query box the candidates hold every triangle whose box meets it (what
// release's scan of all triangles found), also after vertices move, including moves out
// of the box the grid's lattice was made for and a triangle stretched across the whole grid.
#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "fixtures_surfaces.h"
#include "core/triangle_grid.h"

using namespace bpm;
using namespace bpm::detail;
using bpm::fixtures::torus;

namespace {

// The grid kept current as release keeps it: remove with the corners it was filed with,
// insert with the new ones. `visited` counts the candidates returned (the grid's work,
// against the triangles x queries of a scan).
class MovingGrid {
public:
    explicit MovingGrid(const Surface& s) : filed_(s.vertices) {
        Vec3 lo = s.vertices[0], hi = lo;
        for (const Vec3& p : s.vertices)
            for (size_t k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
        grid_ = TriangleGrid(1.0, TriangleGrid::Frame::of_box(lo, hi));
        std::vector<int32_t> ids(s.triangles.size());
        for (size_t t = 0; t < ids.size(); ++t) ids[t] = int32_t(t);
        grid_.insert_all(ids, s.triangles, s.vertices);
    }
    // Vertex v of `s` moved (s already holds its new place): its triangles re-filed.
    void moved(const Surface& s, int32_t v, const std::vector<int32_t>& triangles) {
        for (int32_t t : triangles) {
            const Tri& c = s.triangles[size_t(t)];
            grid_.remove(t, filed_[size_t(c[0])], filed_[size_t(c[1])], filed_[size_t(c[2])]);
        }
        filed_[size_t(v)] = s.vertices[size_t(v)];
        for (int32_t t : triangles) {
            const Tri& c = s.triangles[size_t(t)];
            grid_.insert(t, filed_[size_t(c[0])], filed_[size_t(c[1])], filed_[size_t(c[2])]);
        }
    }
    void candidates(const Vec3& lo, const Vec3& hi, std::vector<int32_t>& out) {
        grid_.query_boxes(lo, hi, entries_);
        out.clear();
        for (const auto& e : entries_) out.push_back(e.id);
        visited_ += int64_t(out.size());
    }
    int64_t visited() const { return visited_; }

private:
    TriangleGrid grid_{1.0};
    std::vector<Vec3> filed_;  // the positions the triangles are filed with
    std::vector<TriangleGrid::Entry> entries_;
    int64_t visited_ = 0;
};

bool box_meets(const Surface& s, int32_t t, const Vec3& lo, const Vec3& hi) {
    // As Refiner::release tests it.
    const Tri& c = s.triangles[size_t(t)];
    for (size_t k = 0; k < 3; ++k) {
        const double a = s.vertices[size_t(c[0])][k], b = s.vertices[size_t(c[1])][k], e = s.vertices[size_t(c[2])][k];
        if (std::max({a, b, e}) < lo[k] || std::min({a, b, e}) > hi[k]) return false;
    }
    return true;
}

std::vector<int32_t> scan(const Surface& s, const Vec3& lo, const Vec3& hi) {
    std::vector<int32_t> out;
    for (int32_t t = 0; t < s.num_triangles(); ++t)
        if (box_meets(s, t, lo, hi)) out.push_back(t);
    return out;
}

// The grid's candidates for [lo, hi], checked (ascending, each once), filtered as release
// filters them.
std::vector<int32_t> found(MovingGrid& grid, const Surface& s, const Vec3& lo, const Vec3& hi) {
    std::vector<int32_t> candidates, out;
    grid.candidates(lo, hi, candidates);
    CHECK(std::is_sorted(candidates.begin(), candidates.end()));
    CHECK(std::adjacent_find(candidates.begin(), candidates.end()) == candidates.end());
    for (int32_t t : candidates)
        if (box_meets(s, t, lo, hi)) out.push_back(t);
    return out;
}

// Random query boxes, from points to a third of the surface's width, some reaching outside it;
// also boxes around triangles (shared corners: boxes that only touch).
void check_queries(MovingGrid& grid, const Surface& s, std::mt19937& rng, int count) {
    std::uniform_real_distribution<double> at(-4.6, 4.6), size(0.0, 2.5);
    for (int q = 0; q < count; ++q) {
        Vec3 lo, hi;
        if (q % 4 == 0) {
            const int32_t t = int32_t(rng() % uint32_t(s.num_triangles()));
            lo = hi = s.vertices[size_t(s.triangles[size_t(t)][0])];  // a corner: touches its neighbours
        } else {
            for (size_t k = 0; k < 3; ++k) {
                lo[k] = at(rng);
                hi[k] = lo[k] + (q % 4 == 1 ? 0.0 : size(rng));
            }
        }
        REQUIRE(found(grid, s, lo, hi) == scan(s, lo, hi));
    }
}

}  // namespace

TEST_CASE("release triangle grid: the candidates hold every triangle whose box meets the query, before and after moves",
          "[internal][refine][release]") {
    Surface s = torus(40, 24);  // 1920 triangles in [-4, 4] x [-4, 4] x [-1, 1]
    std::mt19937 rng(7);
    MovingGrid grid(s);
    check_queries(grid, s, rng, 400);
    const int64_t visited = grid.visited();
    CHECK(visited < 400 * int64_t(s.triangles.size()) / 4);  // the grid's point: far fewer than a scan

    std::vector<std::vector<int32_t>> incident(s.vertices.size());
    for (int32_t t = 0; t < s.num_triangles(); ++t)
        for (int32_t v : s.triangles[size_t(t)]) incident[size_t(v)].push_back(t);
    auto move = [&](int32_t v, const Vec3& to) {
        s.vertices[size_t(v)] = to;
        grid.moved(s, v, incident[size_t(v)]);
    };
    // Small moves (as release's trials: within a cell or to the next), moves far outside
    // the box the grid was built on (clamped cells), and one triangle stretched across it
    // all (filed with the large ones), then shrunk again.
    std::normal_distribution<double> small(0.0, 0.2);
    for (int32_t v = 0; v < s.num_vertices(); v += 7)
        move(v, {s.vertices[size_t(v)][0] + small(rng), s.vertices[size_t(v)][1] + small(rng),
                 s.vertices[size_t(v)][2] + small(rng)});
    check_queries(grid, s, rng, 400);
    move(3, {9, 9, 9});
    move(500, {-7, 0.2, -8});
    REQUIRE(found(grid, s, {8.5, 8.5, 8.5}, {9.5, 9.5, 9.5}) == scan(s, {8.5, 8.5, 8.5}, {9.5, 9.5, 9.5}));
    REQUIRE(!scan(s, {8.5, 8.5, 8.5}, {9.5, 9.5, 9.5}).empty());
    check_queries(grid, s, rng, 400);
    const Vec3 kept = s.vertices[size_t(s.triangles[100][1])];
    move(s.triangles[100][1], {4, 4, 1});  // its triangle's box: most of the grid
    check_queries(grid, s, rng, 400);
    move(s.triangles[100][1], kept);
    move(3, {0, 0, 0});
    check_queries(grid, s, rng, 400);
}

TEST_CASE("release triangle grid: degenerate surfaces (one triangle, all corners in a plane or a point)",
          "[internal][refine][release]") {
    Surface s;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    s.triangles = {{0, 1, 2}, {1, 3, 2}};
    MovingGrid grid(s);
    CHECK(found(grid, s, {0.5, 0.5, 0}, {0.5, 0.5, 0}) == std::vector<int32_t>{0, 1});
    CHECK(found(grid, s, {1, 1, 0}, {2, 2, 2}) == std::vector<int32_t>{0, 1});  // boxes that touch meet
    CHECK(found(grid, s, {1.5, 0, 0}, {2, 2, 0}).empty());
    CHECK(found(grid, s, {0, 0, 1e-9}, {1, 1, 1}).empty());
    Surface point;
    point.vertices = {{2, 2, 2}, {2, 2, 2}, {2, 2, 2}};
    point.triangles = {{0, 1, 2}};
    MovingGrid tiny(point);
    CHECK(found(tiny, point, {2, 2, 2}, {3, 3, 3}) == std::vector<int32_t>{0});
    point.vertices[1] = {-5, 2, 2};
    tiny.moved(point, 1, {0});
    CHECK(found(tiny, point, {-6, 1, 1}, {-4, 3, 3}) == std::vector<int32_t>{0});
}
