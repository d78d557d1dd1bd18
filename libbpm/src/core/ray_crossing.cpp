#include "core/ray_crossing.h"

#include <algorithm>

#include "bpm/predicates.h"

namespace bpm::detail {

namespace {

Vec2 yz(const Vec3& q) { return Vec2{q[1], q[2]}; }

// The sign of orient2d(a, b, p') for p' = p + (e, e^2) in the (y, z) plane. orient2d is
// affine in its last point: orient2d(a, b, p + d) = orient2d(a, b, p) + d_y (a_z - b_z) +
// d_z (b_y - a_y), so where the first term is 0 the signs of the coefficients of e and
// e^2 decide (both exact: comparisons). 0 only when a and b project onto one point.
int perturbed_side(const Vec2& a, const Vec2& b, const Vec2& p) {
    const int s = orient2d(a, b, p);
    if (s != 0) return s;
    if (a[1] != b[1]) return a[1] > b[1] ? 1 : -1;
    if (a[0] != b[0]) return b[0] > a[0] ? 1 : -1;
    return 0;
}

}  // namespace

RayHit ray_crosses(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    // The triangle's box first: p' = p + (0, e, e^2) lies in [lo, hi] in y exactly when
    // lo <= p_y < hi, and so in z; a crossing ahead needs a corner at x >= p_x.
    if (a[0] < p[0] && b[0] < p[0] && c[0] < p[0]) return RayHit::Miss;
    for (int k = 1; k < 3; ++k) {
        const double lo = std::min({a[k], b[k], c[k]}), hi = std::max({a[k], b[k], c[k]});
        if (p[k] < lo || !(p[k] < hi)) return RayHit::Miss;
    }
    const Vec2 A = yz(a), B = yz(b), C = yz(c), P = yz(p);
    // s: the sign of the x component of the normal (b - a) x (c - a); 0: seen edge-on.
    const int s = orient2d(A, B, C);
    if (s == 0) return RayHit::Miss;
    if (perturbed_side(A, B, P) != s || perturbed_side(B, C, P) != s || perturbed_side(C, A, P) != s)
        return RayHit::Miss;
    // p' projects strictly inside: the line of the ray meets the triangle once. Ahead of
    // p when p lies on the side of the plane the normal turns away from +x:
    // orient3d(a, b, c, p) is the sign of (p - a) . n, and n_x has sign s.
    const int o = orient3d(a, b, c, p);
    if (o == 0) return RayHit::Touches;  // p in the plane, within the closed triangle
    return o == -s ? RayHit::Cross : RayHit::Miss;
}

}  // namespace bpm::detail
