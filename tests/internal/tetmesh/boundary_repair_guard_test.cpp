// The dihedral angle guard of the boundary repair's line search
// (tetmesh/boundary_repair_internal.h, behind bpm::repair_boundary and refine_tetmesh).
//
// After the passes that ask each tetrahedron below the bound not to lose angle, the
// widening pass (bpm/boundary_repair.h, step 4) compares the worst tetrahedron around the
// moving vertex before and after a move: on the femur at 10 % (bpm-torsion --adaptive,
// step 5) a new boundary vertex at its edge midpoint closed a 0.69 degree tetrahedron that
// moving it to phi widens to 1.64 degrees, while a neighbour below the 5 degree bound
// narrowed from 4.31 to 3.36 degrees. Judged tetrahedron by tetrahedron only, the
// neighbour losing angle below the bound refused every step, and the 0.69 degrees stayed
// the mesh's smallest angle.
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/boundary_repair.h"
#include "bpm/predicates.h"
#include "tetmesh/boundary_repair_internal.h"

using namespace bpm;

namespace {

// Vertex 6 (v, at (0.25, 0.25, 0.005)) lies just above the triangle a = 0 1 2 of the plane
// z = 0 and below the triangle b = 3 4 5 of the plane z = 0.035: tetrahedron A = (a, v)
// is thin (0.81 degrees) and widens as v rises; B = (b, v), 4.85 degrees, narrows.
// v's target is at height `target_height`.
struct Sandwich {
    std::vector<Vec3> x;
    std::vector<Tet> tets;
    detail::RepairSegments segments;
};

Sandwich sandwich(double target_height) {
    Sandwich s;
    const double top = 0.035;
    s.x = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, top}, {1, 0, top}, {0, 1, top}, {0.25, 0.25, 0.005}};
    s.tets = {Tet{0, 1, 2, 6}, Tet{3, 5, 4, 6}};
    s.segments.base = s.x;
    s.segments.target = s.x;
    s.segments.target[6] = {0.25, 0.25, target_height};
    s.segments.fraction.assign(s.x.size(), 1.0);
    s.segments.fraction[6] = 0;
    return s;
}

double min_dihedral_degrees(const Sandwich& s) { return detail::tet_quality(s.x, s.tets, {}).min_dihedral_degrees; }

// Returns how many vertices the widening pass moved on.
int64_t repair(Sandwich& s, bool widen = true) {
    BoundaryRepairOptions options;  // min_dihedral_degrees = 5
    options.smooth = false;
    options.widen = widen;
    const std::vector<Vec3> reference = s.x;
    const std::vector<char> movable(s.x.size(), 0);
    int64_t widened = -1;
    detail::repair_boundary_vertices(s.x, s.tets, {}, reference, {6}, movable, s.segments, options, Context{}, 0, 1,
                                     "test", &widened);
    return widened;
}

}  // namespace

TEST_CASE("boundary_repair guard: a move that widens the worst tetrahedron around the vertex is taken, though a "
          "neighbour below the bound narrows",
          "[boundary_repair][boundary_repair_guard]") {
    Sandwich s = sandwich(0.015);  // A 0.81 -> 2.43 degrees, B 4.85 -> 3.24 degrees
    const double before = min_dihedral_degrees(s);
    REQUIRE(before == Approx(0.81).margin(0.01));
    CHECK(repair(s) == 1);  // the one vertex, by the widening pass
    CHECK(s.segments.fraction[6] == 1.0);
    CHECK(s.x[6] == s.segments.target[6]);
    CHECK(min_dihedral_degrees(s) == Approx(2.43).margin(0.01));
    for (const Tet& t : s.tets) CHECK(orient3d(s.x[t[0]], s.x[t[1]], s.x[t[2]], s.x[t[3]]) == 1);
}

TEST_CASE("boundary_repair guard: the worst tetrahedron around the vertex never gets worse below the bound",
          "[boundary_repair][boundary_repair_guard]") {
    // At the target B is 0.32 degrees, worse than A's 0.81 at the start: v stops on the way,
    // where the worse of A and B is no worse than 0.81 degrees (B's height 0.005, v's 0.03).
    Sandwich s = sandwich(0.033);
    const double before = min_dihedral_degrees(s);
    repair(s);
    CHECK(s.segments.fraction[6] > 0.5);
    CHECK(s.segments.fraction[6] < 1.0);
    CHECK(s.x[6][2] <= 0.03 + 1e-9);
    CHECK(min_dihedral_degrees(s) >= before);
    for (const Tet& t : s.tets) CHECK(orient3d(s.x[t[0]], s.x[t[1]], s.x[t[2]], s.x[t[3]]) == 1);
}

TEST_CASE("boundary_repair guard: without widening (refine_tetmesh) a neighbour below the bound that narrows keeps "
          "the vertex where it is",
          "[boundary_repair][boundary_repair_guard]") {
    Sandwich s = sandwich(0.015);
    const std::vector<Vec3> start = s.x;
    CHECK(repair(s, false) == -1);  // the pass did not run: nothing counted
    CHECK(s.segments.fraction[6] == 0.0);
    CHECK(s.x == start);
}
