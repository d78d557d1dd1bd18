// The simplifier's intersection test (simplify/intersection_test.h), tested directly on
// small triangle sets: what it must refuse (a piercing triangle, a coplanar fold, two new
// triangles crossing each other) and what it must allow (sharing an edge or a vertex,
// overlapping only a triangle the removal takes away), also after update().
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/predicates.h"
#include "bpm/surface.h"
#include "simplify/coarse_mesh.h"
#include "simplify/intersection_test.h"

using namespace bpm;
using namespace bpm::detail;

namespace {

// The unit square in z = 0 as triangles 0 = (0,1,2) and 1 = (0,2,3) (triangle 0 is the
// half y <= x), and unreferenced vertices for the triangles under test.
Surface square_and_points() {
    Surface s;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                  // 4-6: a triangle through the interior of triangle 0
                  {0.4, 0.3, -1}, {0.4, 0.3, 1}, {0.8, 0.3, 1},
                  // 7-9: a triangle above the square
                  {0, 0, 1}, {1, 0, 1}, {0, 1, 1},
                  // 10: above the edge 0-1; 11: inside triangle 0, in the square's plane
                  {0.5, 0, 1}, {0.6, 0.3, 0},
                  // 12, 13: with 11, a triangle crossing (0, 1, 11)'s plane through it
                  {0.4, -0.5, 0.5}, {0.4, 0.5, -0.5}};
    s.triangles = {{0, 1, 2}, {0, 2, 3}};
    s.patches = {0, 0};
    return s;
}

}  // namespace

TEST_CASE("intersection test: meet_improperly on pairs of triangles", "[internal][simplify]") {
    const Surface s = square_and_points();
    const auto& x = s.vertices;
    CHECK(meet_improperly(x, Tri{4, 5, 6}, Tri{0, 1, 2}));    // pierces triangle 0
    CHECK(!meet_improperly(x, Tri{7, 8, 9}, Tri{0, 1, 2}));   // above it
    CHECK(!meet_improperly(x, Tri{0, 1, 10}, Tri{0, 1, 2}));  // shares the edge 0-1, stands up
    CHECK(meet_improperly(x, Tri{0, 1, 11}, Tri{0, 1, 2}));   // shares the edge, folds onto it
    CHECK(!meet_improperly(x, Tri{0, 1, 11}, Tri{0, 2, 3}));  // meets triangle 1 only at vertex 0
    CHECK(!meet_improperly(x, Tri{0, 1, 2}, Tri{0, 2, 3}));   // the square's own two halves
    // Symmetric in its arguments.
    CHECK(meet_improperly(x, Tri{0, 1, 2}, Tri{4, 5, 6}));
    CHECK(meet_improperly(x, Tri{0, 1, 2}, Tri{0, 1, 11}));
}

TEST_CASE("intersection test: coplanar triangles sharing a corner", "[internal][simplify]") {
    // The fan of a CAD disc: slivers around one centre in one plane. Apart on both sides
    // of a line through the centre (the quick exact answer), overlapping, or touching
    // along a ray (both meet improperly).
    const std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {1, 0.1, 0}, {-1, 0.05, 0}, {-1, -0.05, 0},
                                 {1, -0.1, 0}, {2, 0, 0}, {0.5, 0.02, 0}, {0.3, 0.3, 0.3}};
    CHECK_FALSE(meet_improperly(x, Tri{0, 1, 2}, Tri{0, 3, 4}));  // opposite wedges
    CHECK_FALSE(meet_improperly(x, Tri{0, 1, 2}, Tri{0, 5, 1}));  // a shared edge, on either side
    CHECK_FALSE(meet_improperly(x, Tri{0, 1, 2}, Tri{4, 0, 5}));  // neighbouring wedges
    CHECK(meet_improperly(x, Tri{0, 1, 2}, Tri{0, 6, 7}));        // overlapping wedges
    CHECK(meet_improperly(x, Tri{0, 1, 2}, Tri{0, 5, 6}));        // along the ray 0 -- 1
    CHECK(meet_improperly(x, Tri{0, 1, 2}, Tri{0, 0, 3}));        // a degenerate triangle
    // Against the full exact test on small integer coordinates in tilted planes (many
    // collinear and touching cases): the same answer for every pair with one shared corner.
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> coordinate(-3, 3);
    int apart = 0, met = 0;
    for (int round = 0; round < 20000; ++round) {
        // The plane z = 2 u + 3 w (exact in doubles), or x = 0 (axis-aligned).
        const bool tilted = round % 2 == 0;
        std::vector<Vec3> p;
        for (int i = 0; i < 5; ++i) {
            const double u = coordinate(rng), w = coordinate(rng);
            p.push_back(tilted ? Vec3{u, w, 2 * u + 3 * w} : Vec3{0, u, w});
        }
        const Tri a{0, 1, 2}, b{0, 3, 4};
        const Vec3 pa[3] = {p[0], p[1], p[2]}, pb[3] = {p[0], p[3], p[4]};
        const int shared[3] = {0, -1, -1};
        const bool full = triangles_intersect_improperly(pa, pb, shared);
        CHECK(meet_improperly(p, a, b) == full);
        (full ? met : apart) += 1;
    }
    CHECK(apart > 1000);
    CHECK(met > 1000);
}

TEST_CASE("intersection test: two sets of triangles", "[internal][simplify]") {
    const Surface s = square_and_points();
    const auto& x = s.vertices;
    const std::vector<Tri> square{{0, 1, 2}, {0, 2, 3}};
    CHECK(meet_improperly(x, std::vector<Tri>{{7, 8, 9}, {4, 5, 6}}, square));
    CHECK(!meet_improperly(x, std::vector<Tri>{{7, 8, 9}, {0, 1, 10}}, square));
    CHECK(!meet_improperly(x, std::vector<Tri>{}, square));
}

TEST_CASE("intersection test: new triangles against the rest of a coarse mesh", "[internal][simplify]") {
    const Surface s = square_and_points();
    CoarseMesh mesh(s);
    IntersectionTest test(mesh);
    std::vector<TriangleGrid::Entry> scratch;
    const std::vector<int32_t> none;
    CHECK(test.intersects_rest({{4, 5, 6}}, none, scratch));
    CHECK(!test.intersects_rest({{7, 8, 9}}, none, scratch));
    CHECK(!test.intersects_rest({{0, 1, 10}}, none, scratch));
    CHECK(test.intersects_rest({{0, 1, 11}}, none, scratch));
    // The fold is over triangle 0 only: allowed if the removal takes triangle 0 away.
    const int32_t t0 = mesh.find_triangle(0, 1, 2);
    REQUIRE(t0 >= 0);
    CHECK(!test.intersects_rest({{0, 1, 11}}, {t0}, scratch));
    // Two new triangles that cross each other, each clear of the square.
    CHECK(!test.intersects_rest({{7, 8, 9}}, {t0}, scratch));
    CHECK(test.intersects_rest({{0, 1, 11}, {11, 12, 13}}, {t0}, scratch));
    CHECK(!test.intersects_rest({}, none, scratch));
}

TEST_CASE("intersection test: update() follows the mesh", "[internal][simplify]") {
    const Surface s = square_and_points();
    CoarseMesh mesh(s);
    IntersectionTest test(mesh);
    std::vector<TriangleGrid::Entry> scratch;
    // Replace triangle 0 by the standing triangle (0, 1, 10): the piercing triangle then
    // meets only triangle 1, which it misses (it pierces the half y <= x).
    const int32_t t0 = mesh.find_triangle(0, 1, 2);
    const Tri corners = mesh.triangle(t0);
    const int32_t first_new = mesh.triangle_capacity();
    mesh.remove_triangle(t0);
    mesh.add_triangle({0, 1, 10}, 0);
    test.update({{t0, corners}}, first_new);
    CHECK(!test.intersects_rest({{4, 5, 6}}, {}, scratch));
    // The new triangle is in the grid: a triangle crossing it (and clear of triangle 1)
    // is found, and so is one that its apex 10 touches.
    CHECK(test.intersects_rest({{11, 12, 13}}, {}, scratch));
    CHECK(test.intersects_rest({{7, 8, 9}}, {}, scratch));
    CHECK(!test.intersects_rest({{0, 1, 11}}, {}, scratch));  // folds onto nothing now
    test.rebuild_if_sparse();  // 2 of 2 alive: no rebuild, the same answers
    CHECK(!test.intersects_rest({{4, 5, 6}}, {}, scratch));
}

TEST_CASE("triangle grid: boxes on the 16-bit lattice are rounded outwards", "[internal][simplify]") {
    // A frame a million times the triangles' size: a lattice step (1e6 / 65000) is much
    // larger than the boxes, which must still be found when they only touch.
    const TriangleGrid::Frame frame = TriangleGrid::Frame::of_box({-5e5, -5e5, -5e5}, {5e5, 5e5, 5e5});
    TriangleGrid grid(1.0, frame);
    const std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1e-9, 0, 0}, {3, 3, 3}, {4, 4, 4}};
    grid.insert(7, x[0], x[1], x[2]);
    std::vector<TriangleGrid::Entry> found;
    grid.query_boxes({1, 1, 0}, {2, 2, 1}, found);  // touches the box at the corner (1, 1, 0)
    REQUIRE(found.size() == 1);
    CHECK(found[0].id == 7);
    const TriangleGrid::LatticeBox touching = grid.lattice_box({1, 0.5, 0}, {1, 0.5, 0});
    CHECK(!TriangleGrid::apart(touching, found[0].lo, found[0].hi));
    // Far apart boxes are told apart by the lattice.
    const TriangleGrid::LatticeBox far = grid.lattice_box(x[4], x[5]);
    CHECK(!TriangleGrid::apart(far, far.lo, far.hi));
    CHECK(TriangleGrid::apart(grid.lattice_box({1e4, 1e4, 1e4}, {2e4, 2e4, 2e4}), found[0].lo, found[0].hi));
    grid.remove(7, x[0], x[1], x[2]);
    grid.query_boxes({1, 1, 0}, {2, 2, 1}, found);
    CHECK(found.empty());
}
