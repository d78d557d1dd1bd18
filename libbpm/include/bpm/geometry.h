#pragma once
// Small value types and vector helpers shared by all of libbpm. Coordinates are
// always double precision; decisions that change topology or validity go through
// the exact predicates in bpm/predicates.h, never through these helpers.

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace bpm {

using Vec2 = std::array<double, 2>;
using Vec3 = std::array<double, 3>;
using Tri = std::array<int32_t, 3>;  // three vertex indices, counter-clockwise seen from the front

inline Vec3 operator+(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 operator*(double s, const Vec3& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline double distance(const Vec3& a, const Vec3& b) { return norm(a - b); }

inline Vec2 operator+(const Vec2& a, const Vec2& b) { return {a[0] + b[0], a[1] + b[1]}; }
inline Vec2 operator-(const Vec2& a, const Vec2& b) { return {a[0] - b[0], a[1] - b[1]}; }
inline Vec2 operator*(double s, const Vec2& a) { return {s * a[0], s * a[1]}; }
inline double dot(const Vec2& a, const Vec2& b) { return a[0] * b[0] + a[1] * b[1]; }
inline double cross(const Vec2& a, const Vec2& b) { return a[0] * b[1] - a[1] * b[0]; }

// Point with barycentric coordinates `b` (b[0]+b[1]+b[2] == 1) in triangle (p0,p1,p2).
inline Vec3 barycentric_point(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& b) {
    return {b[0] * p0[0] + b[1] * p1[0] + b[2] * p2[0], b[0] * p0[1] + b[1] * p1[1] + b[2] * p2[1],
            b[0] * p0[2] + b[1] * p1[2] + b[2] * p2[2]};
}

// Aspect ratio R/r (circumradius over inradius) of a triangle; 2 for an equilateral
// triangle, +infinity for a degenerate one. Inline (as triangle_normal): the simplifier's
// planners ask for hundreds of thousands of each on a small input.
inline double aspect_ratio(const Vec3& a, const Vec3& b, const Vec3& c) {
    // R = abc / (4K), r = K / s  =>  R/r = abc * s / (4 K^2), with s the semi-perimeter.
    const double la = distance(b, c), lb = distance(a, c), lc = distance(a, b);
    const double s = 0.5 * (la + lb + lc);
    const double area2 = norm(cross(b - a, c - a));  // 2K
    if (!(area2 > 0.0)) return std::numeric_limits<double>::infinity();
    const double k = 0.5 * area2;
    return la * lb * lc * s / (4.0 * k * k);
}

// Unit normal of triangle (a,b,c) by the right-hand rule; zero vector if degenerate.
inline Vec3 triangle_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
    Vec3 n = cross(b - a, c - a);
    const double l = norm(n);
    if (!(l > 0.0)) return {0.0, 0.0, 0.0};
    return (1.0 / l) * n;
}

double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace bpm
