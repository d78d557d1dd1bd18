// A program outside the bpm source tree that uses an installed bpm: built by
// tests/consumer/run.sh with find_package(bpm) (CMakeLists.txt here) and with pkg-config.
// The part between the README markers is shown verbatim in README.md ("Using bpm from a
// solver"); tests/consumer/check_readme.sh keeps the two equal.
//
//   consumer FILE.bpm    prints phi at the centre of coarse triangle 0 and checks that
//                        inverse phi takes it back, and that every coarse centroid maps
//                        to a finite point in the bounding box of the original surface;
//                        exit 0 ok, 1 check failed,
//                        3 the file could not be read (bpm::Error caught across libbpm.so)
#include <cmath>
#include <cstdio>
#include <vector>

#include "bpm/bpm_file.h"
#include "bpm/errors.h"
#include "bpm/phi_evaluation.h"
#include "bpm/phi_inverse.h"

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: consumer FILE.bpm\n");
        return 2;
    }
    try {
        // README-BEGIN
        bpm::BpmFile file = bpm::read_bpm(argv[1]);     // throws bpm::InputError
        const bpm::Parametrization& param = file.param;  // coarse S, original S0, phi
        bpm::PhiEvaluator phi(param);                   // keeps a reference to param

        // One point of S: coarse triangle 0 at barycentric (1/3, 1/3, 1/3).
        bpm::PhiSample s = phi.evaluate(0, {1.0 / 3, 1.0 / 3, 1.0 / 3});
        std::printf("phi = %.6f %.6f %.6f (original triangle %d)\n", s.position[0], s.position[1],
                    s.position[2], s.original_triangle);

        // Many points at once (what a solver does after refining): the centroid of every
        // coarse triangle, on 2 threads.
        std::vector<bpm::SurfacePoint> points;  // {coarse triangle, barycentric}
        for (int32_t t = 0; t < param.coarse.num_triangles(); ++t) points.push_back({t, {1.0 / 3, 1.0 / 3, 1.0 / 3}});
        std::vector<bpm::Vec3> positions;
        phi.evaluate_positions(points, positions, /*threads=*/2);

        // Back from S0 to S (data given on the original surface, or a solver's physical point).
        bpm::PhiInverse inverse(param);
        bpm::SurfacePoint p = inverse.from_original({s.original_triangle, s.original_barycentric});
        bpm::PhiInverseSample q = inverse.from_position(s.position);  // closest point of S0 first
        // README-END
        const bpm::Vec3 back = phi.evaluate(p).position, back2 = phi.evaluate(q.point).position;
        if (bpm::distance(back, s.position) > 1e-9 * bpm::bounding_box_diagonal(param.original) ||
            bpm::distance(back2, s.position) > 1e-9 * bpm::bounding_box_diagonal(param.original)) {
            std::fprintf(stderr, "consumer: phi(inverse phi(x)) is not x\n");
            return 1;
        }

        // Every image must be a point of S0: finite and inside its bounding box.
        bpm::Vec3 lo = param.original.vertices.at(0), hi = lo;
        for (const bpm::Vec3& v : param.original.vertices)
            for (int k = 0; k < 3; ++k) lo[k] = std::fmin(lo[k], v[k]), hi[k] = std::fmax(hi[k], v[k]);
        const double slack = 1e-9 * bpm::bounding_box_diagonal(param.original);
        positions.push_back(s.position);
        for (const bpm::Vec3& p : positions)
            for (int k = 0; k < 3; ++k)
                if (!std::isfinite(p[k]) || p[k] < lo[k] - slack || p[k] > hi[k] + slack) {
                    std::fprintf(stderr, "consumer: phi = (%g, %g, %g) is not on the original surface's bounding box\n",
                                 p[0], p[1], p[2]);
                    return 1;
                }
        std::printf("%zu coarse centroids mapped into the original surface's bounding box\n", positions.size() - 1);
    } catch (const bpm::Error& e) {
        std::fprintf(stderr, "consumer: %s: %s\n", argv[1], e.what());
        return 3;
    }
    return 0;
}
