// The slide of the boundary repair (bpm/boundary_repair.h, step 6;
// tetmesh/boundary_repair_internal.h, slide_boundary_vertices).
//
// Four boundary vertices close together on a smooth surface are nearly coplanar. On the
// femur at 10 % (bpm-torsion --adaptive, step 5) the mesh's smallest angle, 3.49 degrees,
// was such a tetrahedron: a face on one coarse triangle, the fourth corner on the
// neighbouring one, all four inverted at phi, held at 3.49 degrees by the remedy (a corner
// short of phi) and by its neighbour; neither retreat nor smoothing widens it. A corner that
// moves along the surface (a new parameter point on the same coarse edge) does.
#include <algorithm>
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/boundary_repair.h"
#include "bpm/predicates.h"
#include "tetmesh/boundary_repair_internal.h"

using namespace bpm;

namespace {

// The paraboloid z = 0.3 (u^2 + v^2) over coarse triangle 0, whose corners are (u, v) =
// (-2, -2), (6, -2), (-2, 6): the point with barycentric coordinates b is at
// u = -2 + 8 b1, v = -2 + 8 b2.
Vec3 paraboloid(const SurfacePoint& p) {
    const double u = -2 + 8 * p.barycentric[1], v = -2 + 8 * p.barycentric[2];
    return {u, v, 0.3 * (u * u + v * v)};
}

SurfacePoint at_uv(double u, double v) { return {0, {1 - (u + 2) / 8 - (v + 2) / 8, (u + 2) / 8, (v + 2) / 8}}; }

// The tetrahedron of the surface points over (0, 0), (1, 0), (0, 1) and (1.02, 1.02): the
// last is just outside the circle through the first three, so it is just above their
// plane (a sliver, 0.9 degrees).
struct SurfaceSliver {
    std::vector<Vec3> x;
    std::vector<SurfacePoint> points;
    std::vector<Tet> tets{{0, 1, 2, 3}};
};

SurfaceSliver surface_sliver() {
    SurfaceSliver s;
    s.points = {at_uv(0, 0), at_uv(1, 0), at_uv(0, 1), at_uv(1.02, 1.02)};
    for (const SurfacePoint& p : s.points) s.x.push_back(paraboloid(p));
    return s;
}

double min_dihedral_degrees(const std::vector<Vec3>& x, const std::vector<Tet>& tets) {
    return detail::tet_quality(x, tets, {}).min_dihedral_degrees;
}

}  // namespace

TEST_CASE("boundary_repair slide: a sliver of four vertices on a smooth surface widens when its corners move along "
          "the surface",
          "[boundary_repair][boundary_repair_slide]") {
    SurfaceSliver s = surface_sliver();
    REQUIRE(orient3d(s.x[0], s.x[1], s.x[2], s.x[3]) == 1);
    const double before = min_dihedral_degrees(s.x, s.tets);
    REQUIRE(before < 1);
    const std::vector<SurfacePoint> points_before = s.points;

    BoundaryRepairOptions options;  // min_dihedral_degrees = 5
    std::vector<char> may_slide(4, 1), dirty(4, 0);
    CHECK(detail::slide_boundary_vertices(s.x, s.tets, s.points, paraboloid, may_slide, options, dirty) >= 1);
    CHECK(orient3d(s.x[0], s.x[1], s.x[2], s.x[3]) == 1);
    const double after = min_dihedral_degrees(s.x, s.tets);
    CHECK(after > 2 * before);
    for (int v = 0; v < 4; ++v) {
        // Every vertex is still exactly on the surface, at its (possibly new) parameter point,
        // in the same coarse triangle.
        CHECK(s.x[v] == paraboloid(s.points[v]));
        CHECK(s.points[v].triangle == 0);
    }
    CHECK(s.points != points_before);
    CHECK(std::count(dirty.begin(), dirty.end(), 1) == 4);
}

TEST_CASE("boundary_repair slide: a vertex on a coarse edge stays on it, a held-back vertex keeps its offset, coarse "
          "vertices and vertices that may not slide stay",
          "[boundary_repair][boundary_repair_slide]") {
    BoundaryRepairOptions options;
    {
        // The sliver's fourth corner on the coarse edge b0 = 0 (u + v = 4), the others fixed.
        SurfaceSliver s = surface_sliver();
        s.points[3] = {0, {0, 0.5 + 0.5 * 0.02 / 8, 0.5 - 0.5 * 0.02 / 8}};  // (u, v) = (2.01, 1.99)
        s.points[1] = {0, {0.5, 0.5, 0}};  // (2, -2), on the edge b2 = 0
        s.points[2] = {0, {0.5, 0, 0.5}};  // (-2, 2), on the edge b1 = 0
        s.points[0] = {0, {1, 0, 0}};      // a coarse vertex, (-2, -2)
        s.x.clear();
        for (const SurfacePoint& p : s.points) s.x.push_back(paraboloid(p));
        s.x[3][2] -= 0.5;  // held back 0.5 below the surface
        if (orient3d(s.x[0], s.x[1], s.x[2], s.x[3]) != 1) std::swap(s.tets[0][2], s.tets[0][3]);
        const Vec3 offset = s.x[3] - paraboloid(s.points[3]);
        options.min_dihedral_degrees = 89;  // every move that widens the tetrahedron is wanted
        std::vector<char> may_slide{1, 1, 0, 1}, dirty(4, 0);
        const std::vector<SurfacePoint> points_before = s.points;
        const std::vector<Vec3> x_before = s.x;
        const double before = min_dihedral_degrees(s.x, s.tets);
        CHECK(detail::slide_boundary_vertices(s.x, s.tets, s.points, paraboloid, may_slide, options, dirty) >= 1);
        CHECK(min_dihedral_degrees(s.x, s.tets) > before);
        CHECK(s.points[0] == points_before[0]);  // coarse vertex
        CHECK(s.x[0] == x_before[0]);
        CHECK(s.points[2] == points_before[2]);  // may not slide
        CHECK(s.x[2] == x_before[2]);
        CHECK(s.points[1].barycentric[2] == 0);  // on its edge
        CHECK(s.points[3].barycentric[0] == 0);  // on its edge
        CHECK(s.points[3] != points_before[3]);
        const Vec3 now = s.x[3] - paraboloid(s.points[3]);
        for (int k = 0; k < 3; ++k) CHECK(now[k] == Approx(offset[k]).margin(1e-12));
    }
    {
        // Nothing below the bound: nothing moves.
        SurfaceSliver s = surface_sliver();
        options.min_dihedral_degrees = 0.5;
        const std::vector<Vec3> start = s.x;
        std::vector<char> may_slide(4, 1), dirty(4, 0);
        CHECK(detail::slide_boundary_vertices(s.x, s.tets, s.points, paraboloid, may_slide, options, dirty) == 0);
        CHECK(s.x == start);
        CHECK(std::count(dirty.begin(), dirty.end(), 1) == 0);
    }
}
