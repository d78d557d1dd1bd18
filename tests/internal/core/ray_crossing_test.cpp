// Inside/outside by the parity of a ray's crossings (core/ray_crossing.h): a cube of 12
// triangles, and points whose rays along +x run exactly through its vertices, along its
// edges and in the planes of its faces. The symbolic perturbation must count every
// crossing once, so the parity is the truth for every point not on the cube; a point on
// it is reported as touching where the perturbed ray runs through its triangle.
#include <array>
#include <vector>

#include <catch2/catch.hpp>

#include "core/ray_crossing.h"

using namespace bpm;
using namespace bpm::detail;

namespace {

// [0,2]^3, each face split along a diagonal, orientations mixed on purpose (parity does
// not depend on them).
struct Cube {
    std::vector<Vec3> x;
    std::vector<std::array<int, 3>> t;
    Cube() {
        for (int k = 0; k < 8; ++k) x.push_back({2.0 * (k & 1), 2.0 * (k >> 1 & 1), 2.0 * (k >> 2 & 1)});
        t = {{0, 1, 3}, {0, 3, 2}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
             {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 3, 7}, {1, 7, 5}};
    }
    // -1: touches, else the parity.
    int parity(const Vec3& p) const {
        int odd = 0;
        for (const auto& c : t) {
            const RayHit h = ray_crosses(p, x[c[0]], x[c[1]], x[c[2]]);
            if (h == RayHit::Touches) return -1;
            if (h == RayHit::Cross) odd ^= 1;
        }
        return odd;
    }
};

}  // namespace

TEST_CASE("ray crossings: parity inside and outside a cube, rays through its vertices, edges and faces",
          "[internal][core][islands]") {
    const Cube cube;
    // Coordinates on the cube's planes (0, 2), on its diagonals' lines (1) and off them.
    const double values[] = {-1.0, 0.0, 0.5, 1.0, 2.0, 3.0};
    int inside = 0, outside = 0, touching = 0;
    for (double px : values)
        for (double py : values)
            for (double pz : values) {
                const Vec3 p{px, py, pz};
                const auto in = [](double c) { return c > 0.0 && c < 2.0; };
                const auto on = [](double c) { return c >= 0.0 && c <= 2.0; };
                const bool strictly_inside = in(px) && in(py) && in(pz);
                const bool on_cube = on(px) && on(py) && on(pz) && !strictly_inside;
                const int got = cube.parity(p);
                INFO("p = (" << px << ", " << py << ", " << pz << ")");
                if (on_cube) {
                    // Either it says so, or it answers for the perturbed point (off the cube).
                    if (got == -1) ++touching;
                } else {
                    CHECK(got == (strictly_inside ? 1 : 0));
                    ++(strictly_inside ? inside : outside);
                }
            }
    CHECK(inside == 8);
    CHECK(outside == 216 - 64);
    CHECK(touching > 0);  // e.g. the centres of the faces x = 0 and x = 2
    CHECK(cube.parity({0, 1, 0.5}) == -1);
}

TEST_CASE("ray crossings: a triangle without area or seen edge-on is never crossed", "[internal][core][islands]") {
    // Collinear corners across the ray's line.
    CHECK(ray_crosses({0, 0, 0}, {1, -1, -1}, {1, 0, 0}, {1, 1, 1}) == RayHit::Miss);
    // In a plane that holds the +x direction, p's line in that plane.
    CHECK(ray_crosses({0, 0, 0}, {1, -1, 0}, {3, 1, 0}, {2, 1, 0}) == RayHit::Miss);
    // A plain crossing ahead, and the same triangle behind p.
    CHECK(ray_crosses({0, 0.2, 0.3}, {1, -1, -1}, {1, 1, -1}, {1, 0, 1}) == RayHit::Cross);
    CHECK(ray_crosses({2, 0.2, 0.3}, {1, -1, -1}, {1, 1, -1}, {1, 0, 1}) == RayHit::Miss);
}
