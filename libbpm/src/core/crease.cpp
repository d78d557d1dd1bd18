// The crease test (core/crease.h).

#include "core/crease.h"

#include <algorithm>
#include <cmath>

#include "core/directed_edge.h"

namespace bpm::detail {

namespace {

// A triangle whose height is below this fraction of its longest edge has no direction
// either: its normal is set by where rounding put a corner that lies (almost) on the line
// of the others, e.g. a gmsh vertex snapped onto an edge (height 1e-16 of the edge). Such
// a sliver's edges made creases at random, so its corners became crease corners, which
// are never removed, and the sliver stayed in the coarse surface (R/r 1e30). Thicker
// triangles keep their normal: in double precision it is then within 1e-6 rad.
constexpr double kNoDirectionThinness = 1e-10;

bool has_direction(const std::vector<Vec3>& p, const Tri& t) {
    const Vec3 &a = p[size_t(t[0])], &b = p[size_t(t[1])], &c = p[size_t(t[2])];
    const double longest2 = std::max({dot(b - a, b - a), dot(c - b, c - b), dot(a - c, a - c)});
    return norm(cross(b - a, c - a)) >= kNoDirectionThinness * longest2;  // |cross| = height * longest
}

}  // namespace

bool oriented_normal_cosine(const std::vector<Vec3>& p, const Tri& t0, const Tri& t1, int32_t u, int32_t w,
                            double& cosine) {
    // The normals from the corners in stored order, so that they are the same bits as
    // triangle_normal() gives everywhere else for these triangles.
    const Vec3 n0 = triangle_normal(p[size_t(t0[0])], p[size_t(t0[1])], p[size_t(t0[2])]);
    Vec3 n1 = triangle_normal(p[size_t(t1[0])], p[size_t(t1[1])], p[size_t(t1[2])]);
    if (dot(n0, n0) == 0 || dot(n1, n1) == 0) return false;  // a degenerate triangle has no normal
    if (!has_direction(p, t0) || !has_direction(p, t1)) return false;
    if (runs_from(t0, u, w) == runs_from(t1, u, w)) n1 = -1.0 * n1;
    cosine = dot(n0, n1);
    return true;
}

CreaseTest::CreaseTest(double feature_angle_degrees)
    : cos_limit_(std::cos(feature_angle_degrees * M_PI / 180.0)), finds_creases_(feature_angle_degrees < 180.0) {}

bool CreaseTest::is_crease(const std::vector<Vec3>& p, const Tri& t0, const Tri& t1, int32_t u, int32_t w) const {
    if (!finds_creases_) return false;
    double cosine;
    return oriented_normal_cosine(p, t0, t1, u, w, cosine) && is_crease(cosine);
}

double ridge_angle_degrees(const std::vector<Vec3>& p, const Tri& t0, const Tri& t1, int32_t u, int32_t w) {
    double cosine;
    if (!oriented_normal_cosine(p, t0, t1, u, w, cosine)) return 180.0;
    return ridge_angle_degrees(cosine);
}

double ridge_angle_degrees(double cosine) { return 180.0 - std::acos(std::clamp(cosine, -1.0, 1.0)) * (180.0 / M_PI); }

}  // namespace bpm::detail
