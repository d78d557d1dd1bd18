#include "bpm/geometry.h"

#include <limits>

namespace bpm {

double aspect_ratio(const Vec3& a, const Vec3& b, const Vec3& c) {
    // R = abc / (4K), r = K / s  =>  R/r = abc * s / (4 K^2), with s the semi-perimeter.
    const double la = distance(b, c), lb = distance(a, c), lc = distance(a, b);
    const double s = 0.5 * (la + lb + lc);
    const double area2 = norm(cross(b - a, c - a));  // 2K
    if (!(area2 > 0.0)) return std::numeric_limits<double>::infinity();
    const double k = 0.5 * area2;
    return la * lb * lc * s / (4.0 * k * k);
}

Vec3 triangle_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
    Vec3 n = cross(b - a, c - a);
    const double l = norm(n);
    if (!(l > 0.0)) return {0.0, 0.0, 0.0};
    return (1.0 / l) * n;
}

double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * norm(cross(b - a, c - a)); }

}  // namespace bpm
