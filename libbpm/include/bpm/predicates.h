#pragma once
// Exact geometric predicates on double-precision input (CGAL's filtered
// Exact_predicates_inexact_constructions_kernel underneath, kept out of this header).
// Every decision that changes topology or validity goes through these.
//
// orient2d, orient3d and in_circle are inline floating-point filters (Shewchuk, "Adaptive
// precision floating-point arithmetic and fast robust geometric predicates", 1997) in front
// of the exact predicates: the simplifier asks millions of times. Being inline, they are
// compiled with the caller's flags, not with libbpm's -ffp-contract=off, and Shewchuk's
// error bounds are proven for products rounded to double. GCC contracts a * b + c into a
// fused multiply-add by default in C++ (-ffp-contract=fast, also with -std=c++17) wherever
// the target has FMA (-march=native, -mfma, aarch64), and clang does within an expression.
// So every product that feeds a sum goes through detail::rounded_product, which no
// compiler can fuse: the filters evaluate the same, to the bit, in every translation unit.
// (A fused evaluation only leaves out roundings, and the bounds hold for it too, as far as
// tests/unit/core/predicates_fma_test.cpp finds; the barrier keeps correctness from resting
// on which fusions a compiler picks. __attribute__((optimize("fp-contract=off"))) or
// #pragma GCC optimize would stop GCC from inlining the filters, and clang's
// -ffp-contract=fast ignores #pragma clang fp contract.)
// The bounds also assume no underflow: the filters decide only with the permanent (orient2d:
// the determinant) above 1e-250, far above the denormals, whose rounding errors are absolute.

#include <cmath>

#include "bpm/geometry.h"

namespace bpm {

namespace detail {
// x as the double it was rounded to: an empty asm statement (no instruction) that the
// compiler must assume reads and rewrites x in a floating-point register, so the product
// that made x cannot be fused with the addition that uses it.
inline double rounded(double x) {
#if defined(__GNUC__) && defined(__x86_64__)
    __asm__("" : "+x"(x));
#elif defined(__GNUC__) && defined(__aarch64__)
    __asm__("" : "+w"(x));
#elif defined(__GNUC__)
    __asm__("" : "+m"(x));  // through memory: stored as a double
#else
    volatile double stored = x;
    x = stored;
#endif
    return x;
}
inline double rounded_product(double a, double b) { return rounded(a * b); }
}  // namespace detail

// Sign of the signed area of (a,b,c): +1 counter-clockwise, -1 clockwise, 0 collinear.
// Inline floating-point filter (Shewchuk's orient2d error bound); the rare uncertain
// cases go to the exact predicate.
int orient2d_exact(const Vec2& a, const Vec2& b, const Vec2& c);
inline int orient2d(const Vec2& a, const Vec2& b, const Vec2& c) {
    const double left = detail::rounded_product(a[0] - c[0], b[1] - c[1]);
    const double right = detail::rounded_product(a[1] - c[1], b[0] - c[0]);
    const double det = left - right;
    // Products of opposite signs (or one zero) make |det| their sum, rounded alike, far
    // above the bound: Shewchuk's early exits are the bound test. His bound assumes no
    // underflow; the 1e-250 added (rounding can only raise the bound) leaves every |det|
    // that small to the exact predicate, as orient3d's guard does: the rounding errors of
    // denormals are absolute, up to 2^-1075. A NaN (inf * 0) fails both tests. Both
    // products zero (repeated points, an axis) go to orient2d_exact, which answers those
    // at once.
    const double bound = 3.3306690738754716e-16 * (std::abs(left) + std::abs(right)) + 1e-250;  // (3 + 16 eps) eps
    if (det >= bound) return 1;
    if (-det >= bound) return -1;
    return orient2d_exact(a, b, c);
}
// Sign of the signed volume of (a,b,c,d), CGAL::orientation's: +1 if d is on the side
// of the plane of (a,b,c) that the normal (b - a) x (c - a) points to ((a,b,c) is then
// counter-clockwise seen from d), -1 on the other side, 0 coplanar.
// Inline floating-point filter (Shewchuk's orient3d error bound; his sign is the
// opposite), exact otherwise: the simplifier's intersection tests ask millions of times,
// and CGAL's filter took about twice the instructions.
int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
inline int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
    const double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];
    const double adz = a[2] - d[2], bdz = b[2] - d[2], cdz = c[2] - d[2];
    using detail::rounded_product;
    const double bdxcdy = rounded_product(bdx, cdy), cdxbdy = rounded_product(cdx, bdy);
    const double cdxady = rounded_product(cdx, ady), adxcdy = rounded_product(adx, cdy);
    const double adxbdy = rounded_product(adx, bdy), bdxady = rounded_product(bdx, ady);
    const double det = rounded_product(adz, bdxcdy - cdxbdy) + rounded_product(bdz, cdxady - adxcdy) +
                       rounded_product(cdz, adxbdy - bdxady);
    const double permanent = rounded_product(std::abs(bdxcdy) + std::abs(cdxbdy), std::abs(adz)) +
                             rounded_product(std::abs(cdxady) + std::abs(adxcdy), std::abs(bdz)) +
                             rounded_product(std::abs(adxbdy) + std::abs(bdxady), std::abs(cdz));
    // The bound assumes no underflow: far above the denormals, whose rounding is absolute.
    if (permanent > 1e-250) {
        const double bound = 7.771561172376103e-16 * permanent;  // (7 + 56 eps) eps
        if (det > bound) return -1;
        if (-det > bound) return 1;
    }
    return orient3d_exact(a, b, c, d);
}
// +1 if d is strictly inside the circle through counter-clockwise (a,b,c), 0 on it, -1 outside.
// Inline floating-point filter (Shewchuk's incircle error bound), exact otherwise.
int in_circle_exact(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d);
inline int in_circle(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
    const double adx = a[0] - d[0], ady = a[1] - d[1];
    const double bdx = b[0] - d[0], bdy = b[1] - d[1];
    const double cdx = c[0] - d[0], cdy = c[1] - d[1];
    using detail::rounded_product;
    const double alift = rounded_product(adx, adx) + rounded_product(ady, ady);
    const double blift = rounded_product(bdx, bdx) + rounded_product(bdy, bdy);
    const double clift = rounded_product(cdx, cdx) + rounded_product(cdy, cdy);
    const double bdxcdy = rounded_product(bdx, cdy), cdxbdy = rounded_product(cdx, bdy);
    const double cdxady = rounded_product(cdx, ady), adxcdy = rounded_product(adx, cdy);
    const double adxbdy = rounded_product(adx, bdy), bdxady = rounded_product(bdx, ady);
    const double det = rounded_product(alift, bdxcdy - cdxbdy) + rounded_product(blift, cdxady - adxcdy) +
                       rounded_product(clift, adxbdy - bdxady);
    const double permanent = rounded_product(std::abs(bdxcdy) + std::abs(cdxbdy), alift) +
                             rounded_product(std::abs(cdxady) + std::abs(adxcdy), blift) +
                             rounded_product(std::abs(adxbdy) + std::abs(bdxady), clift);
    if (permanent > 1e-250) {  // no underflow, as in orient3d
        const double bound = 1.1102230246251577e-15 * permanent;  // (10 + 96 eps) eps
        if (det > bound) return 1;
        if (-det > bound) return -1;
    }
    return in_circle_exact(a, b, c, d);
}
// Exact: are the three points collinear?
bool collinear3d(const Vec3& a, const Vec3& b, const Vec3& c);

// Do the closed triangles (a0,a1,a2) and (b0,b1,b2) intersect anywhere other than in
// the vertices / edge they share? Shared corners are given by index: shared[i] = j
// means corner i of the first triangle is the same vertex as corner j of the second,
// -1 otherwise. Coplanar overlaps and folds count as intersections.
bool triangles_intersect_improperly(const Vec3 a[3], const Vec3 b[3], const int shared[3]);

}  // namespace bpm
