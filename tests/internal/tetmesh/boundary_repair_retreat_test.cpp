// The retreat of the boundary repair (bpm/boundary_repair.h, step 5;
// tetmesh/boundary_repair_internal.h, retreat_boundary_vertices).
//
// On the femur at 10 % (bpm-torsion --adaptive, step 5) the mesh's smallest angle, 1.01
// degrees (flat refinement: 2.37), was a tetrahedron of three boundary vertices and an
// interior vertex UG had created at the midpoint of an edge between two boundary vertices.
// Its father was a sliver of four boundary vertices (three at phi, one held at its edge
// midpoint), 2.02 degrees at the edge opposite the one UG cut. The two tetrahedra cut from
// it share that edge and their angles there add up to the father's whatever the midpoint's
// position, so interior smoothing can give them at most 1.01 degrees each (which it did).
// Only moving a boundary corner can widen them: back towards where plain refinement put it.
#include <algorithm>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/boundary_repair.h"
#include "bpm/predicates.h"
#include "tetmesh/boundary_repair_internal.h"
#include "tetmesh/tetmesh_internal.h"

using namespace bpm;

namespace {

// The sliver (a, b, c, e) = vertices 0-3: the square (0,0), (1,0), (1,1), (0,1) with the
// diagonal a e at height 0 and the diagonal b c at height 0.018 (2.06 degrees at its four
// outer edges), cut at vertex 4, the midpoint of its outer edge c e, into T0 = (a, b, c, m)
// and T1 = (a, b, m, e), both of which have the edge a b of the sliver. All but m are
// boundary vertices; b's plain position is 0.05 higher (where plain refinement put it; the
// repair had moved it down to phi), which thickens the sliver. With `lid`, vertices 5-7
// make a tetrahedron over b that flattens as b rises, and crosses its face at z = 0.06.
struct CutSliver {
    std::vector<Vec3> x, plain;
    std::vector<Tet> tets;
    std::vector<char> boundary, movable;
};

Tet positive(Tet t, const std::vector<Vec3>& x) {
    if (orient3d(x[t[0]], x[t[1]], x[t[2]], x[t[3]]) != 1) std::swap(t[2], t[3]);
    return t;
}

CutSliver cut_sliver(bool lid) {
    CutSliver s;
    const double h = 0.018;
    s.x = {{0, 0, 0}, {1, 0, h}, {0, 1, h}, {1, 1, 0}, {0.5, 1, 0.5 * h}};
    s.tets = {positive({0, 1, 2, 4}, s.x), positive({0, 1, 4, 3}, s.x)};
    if (lid) {
        s.x.insert(s.x.end(), {{1.2, -0.2, 0.06}, {1.2, 0.2, 0.06}, {0.8, 0, 0.06}});
        s.tets.push_back(positive({1, 5, 6, 7}, s.x));
    }
    s.plain = s.x;
    s.plain[1][2] += 0.05;
    s.boundary.assign(s.x.size(), 1);
    s.boundary[4] = 0;
    s.movable.assign(s.x.size(), 0);
    s.movable[4] = 1;
    return s;
}

double min_dihedral_degrees(const CutSliver& s) { return detail::tet_quality(s.x, s.tets, {}).min_dihedral_degrees; }

bool all_positive(const CutSliver& s) {
    for (const Tet& t : s.tets)
        if (orient3d(s.x[t[0]], s.x[t[1]], s.x[t[2]], s.x[t[3]]) != 1) return false;
    return true;
}

void smooth(CutSliver& s, std::vector<char>* dirty) {
    detail::smooth_interior(s.x, s.tets, {}, s.movable, dirty, TetSmoothOptions{}, Context{}, 0, 1);
}

}  // namespace

TEST_CASE("boundary_repair retreat: a sliver of boundary vertices cut at an interior edge midpoint, which smoothing "
          "cannot widen, widens when a boundary corner moves back towards its plain position",
          "[boundary_repair][boundary_repair_retreat]") {
    CutSliver s = cut_sliver(false);
    REQUIRE(all_positive(s));
    // Smoothing alone (the repair before the retreat): the midpoint moves, the two halves
    // share the sliver's 2.06 degrees at a b, so neither gets above 1.03.
    smooth(s, nullptr);
    const double smoothed = min_dihedral_degrees(s);
    CHECK(smoothed > 0.5);
    CHECK(smoothed <= 1.04);
    const Vec3 b = s.x[1];

    BoundaryRepairOptions options;  // min_dihedral_degrees = 5
    std::vector<char> dirty(s.x.size(), 0);
    CHECK(detail::retreat_boundary_vertices(s.x, s.tets, s.plain, s.boundary, options, dirty) >= 1);
    CHECK(all_positive(s));
    // b moved up, on its segment towards its plain position.
    CHECK(s.x[1][0] == b[0]);
    CHECK(s.x[1][1] == b[1]);
    CHECK(s.x[1][2] > b[2]);
    CHECK(s.x[1][2] <= s.plain[1][2]);
    CHECK(dirty[4] == 1);  // the midpoint is smoothed again around the moved vertex
    smooth(s, &dirty);
    const double retreated = min_dihedral_degrees(s);
    CHECK(retreated > 2 * smoothed);
    CHECK(all_positive(s));
}

TEST_CASE("boundary_repair retreat: a vertex stops where the worst tetrahedron around it is widest, never making it "
          "worse",
          "[boundary_repair][boundary_repair_retreat]") {
    CutSliver s = cut_sliver(true);  // the lid over b flattens as b rises, and inverts at 0.06
    REQUIRE(all_positive(s));
    smooth(s, nullptr);
    const double before = min_dihedral_degrees(s);
    const Vec3 b = s.x[1];
    BoundaryRepairOptions options;
    std::vector<char> dirty(s.x.size(), 0);
    detail::retreat_boundary_vertices(s.x, s.tets, s.plain, s.boundary, options, dirty);
    CHECK(all_positive(s));
    CHECK(s.x[1][2] > b[2]);
    CHECK(s.x[1][2] < 0.06);  // short of the plain position 0.068, below the lid
    const double lid = detail::tet_quality(s.x, {s.tets[2]}, {}).min_dihedral_degrees;
    const double halves = detail::tet_quality(s.x, {s.tets[0], s.tets[1]}, {}).min_dihedral_degrees;
    CHECK(lid == Approx(halves).margin(0.05));  // balanced: higher, the lid would be worse
    CHECK(min_dihedral_degrees(s) > before);
}

TEST_CASE("boundary_repair retreat: nothing moves without a tetrahedron below the bound, away from the plain position "
          "or where the vertex may not retreat",
          "[boundary_repair][boundary_repair_retreat]") {
    BoundaryRepairOptions options;
    {
        CutSliver s = cut_sliver(false);
        const std::vector<Vec3> start = s.x;
        options.min_dihedral_degrees = 0.5;  // both halves are wider
        std::vector<char> dirty(s.x.size(), 0);
        CHECK(detail::retreat_boundary_vertices(s.x, s.tets, s.plain, s.boundary, options, dirty) == 0);
        CHECK(s.x == start);
        CHECK(std::count(dirty.begin(), dirty.end(), 1) == 0);
    }
    options = {};
    {
        CutSliver s = cut_sliver(false);
        s.plain = s.x;  // every vertex at its plain position
        const std::vector<Vec3> start = s.x;
        std::vector<char> dirty(s.x.size(), 0);
        CHECK(detail::retreat_boundary_vertices(s.x, s.tets, s.plain, s.boundary, options, dirty) == 0);
        CHECK(s.x == start);
    }
    {
        CutSliver s = cut_sliver(false);
        s.boundary[1] = 0;  // b may not retreat (a coarse vertex)
        const std::vector<Vec3> start = s.x;
        std::vector<char> dirty(s.x.size(), 0);
        CHECK(detail::retreat_boundary_vertices(s.x, s.tets, s.plain, s.boundary, options, dirty) == 0);
        CHECK(s.x == start);
    }
}
