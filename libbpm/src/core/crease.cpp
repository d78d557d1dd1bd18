// The crease test (core/crease.h).

#include "core/crease.h"

#include <algorithm>
#include <cmath>

#include "core/directed_edge.h"

namespace bpm::detail {

namespace {

// The cosine of the angle between the normals of t0 and t1, the second turned over when
// the two run the edge (u, w) in the same direction; false for a degenerate triangle.
bool oriented_normal_cosine(const std::vector<Vec3>& p, const Tri& t0, const Tri& t1, int32_t u, int32_t w,
                            double& cosine) {
    // The normals from the corners in stored order, so that they are the same bits as
    // triangle_normal() gives everywhere else for these triangles.
    const Vec3 n0 = triangle_normal(p[size_t(t0[0])], p[size_t(t0[1])], p[size_t(t0[2])]);
    Vec3 n1 = triangle_normal(p[size_t(t1[0])], p[size_t(t1[1])], p[size_t(t1[2])]);
    if (dot(n0, n0) == 0 || dot(n1, n1) == 0) return false;  // a degenerate triangle has no normal
    if (runs_from(t0, u, w) == runs_from(t1, u, w)) n1 = -1.0 * n1;
    cosine = dot(n0, n1);
    return true;
}

}  // namespace

CreaseTest::CreaseTest(double feature_angle_degrees)
    : cos_limit_(std::cos(feature_angle_degrees * M_PI / 180.0)), finds_creases_(feature_angle_degrees < 180.0) {}

bool CreaseTest::is_crease(const std::vector<Vec3>& p, const Tri& t0, const Tri& t1, int32_t u, int32_t w) const {
    if (!finds_creases_) return false;
    double cosine;
    return oriented_normal_cosine(p, t0, t1, u, w, cosine) && cosine < cos_limit_;
}

double ridge_angle_degrees(const std::vector<Vec3>& p, const Tri& t0, const Tri& t1, int32_t u, int32_t w) {
    double cosine;
    if (!oriented_normal_cosine(p, t0, t1, u, w, cosine)) return 180.0;
    return 180.0 - std::acos(std::clamp(cosine, -1.0, 1.0)) * (180.0 / M_PI);
}

}  // namespace bpm::detail
