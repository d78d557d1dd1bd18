// Exact predicates over CGAL's filtered kernel. This is one of the few translation
// units that include CGAL, to keep build times low.
#include "bpm/predicates.h"
#include "core/triangle_intersection.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>

namespace bpm {

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using P2 = K::Point_2;
using P3 = K::Point_3;

inline P2 p2(const Vec2& v) { return P2(v[0], v[1]); }
inline P3 p3(const Vec3& v) { return P3(v[0], v[1], v[2]); }

int sign_of(CGAL::Sign s) { return s == CGAL::POSITIVE ? 1 : (s == CGAL::NEGATIVE ? -1 : 0); }
}  // namespace

int orient2d_exact(const Vec2& a, const Vec2& b, const Vec2& c) {
    // Both products of orient2d zero because a factor of each is: points repeated or on a
    // line parallel to an axis. The filter (its bound has a margin for underflow) sends
    // those here, often (27088 calls on elephant --vertices 1000), and CGAL took about 8
    // times the instructions to say 0 (183 against 22 a call).
    if ((a[0] == c[0] || b[1] == c[1]) && (a[1] == c[1] || b[0] == c[0])) return 0;
    return sign_of(CGAL::orientation(p2(a), p2(b), p2(c)));
}

int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    return sign_of(CGAL::orientation(p3(a), p3(b), p3(c), p3(d)));
}

int in_circle_exact(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
    // CGAL::side_of_oriented_circle is POSITIVE inside for counter-clockwise (a,b,c).
    return sign_of(CGAL::side_of_oriented_circle(p2(a), p2(b), p2(c), p2(d)));
}

bool collinear3d(const Vec3& a, const Vec3& b, const Vec3& c) { return CGAL::collinear(p3(a), p3(b), p3(c)); }

bool triangles_intersect_improperly(const Vec3 a[3], const Vec3 b[3], const int shared[3]) {
    // A degenerate triangle is never acceptable; report it as an intersection so that
    // callers that forgot to reject it do not pass it on.
    if (collinear3d(a[0], a[1], a[2]) || collinear3d(b[0], b[1], b[2])) return true;
    return detail::nondegenerate_triangles_intersect_improperly(a, b, shared);
}

bool detail::nondegenerate_triangles_intersect_improperly(const Vec3 a[3], const Vec3 b[3], const int shared[3]) {
    int count = 0;
    for (int i = 0; i < 3; ++i) count += shared[i] >= 0 ? 1 : 0;
    const K::Triangle_3 ta(p3(a[0]), p3(a[1]), p3(a[2]));
    const K::Triangle_3 tb(p3(b[0]), p3(b[1]), p3(b[2]));
    if (count == 0) return CGAL::do_intersect(ta, tb);
    if (count == 3) return true;  // the same triangle twice
    if (count == 2) {
        // Shared edge (p,q) with opposite corners ra, rb: the triangles overlap beyond the
        // edge exactly when they are coplanar and ra, rb lie on the same side of pq.
        int ia = 0;
        while (shared[ia] >= 0) ++ia;  // corner of a not shared
        const int ip = (ia + 1) % 3, iq = (ia + 2) % 3;
        int ib = 3 - shared[ip] - shared[iq];  // corner of b not shared
        const P3 p = p3(a[ip]), q = p3(a[iq]), ra = p3(a[ia]), rb = p3(b[ib]);
        if (CGAL::orientation(p, q, ra, rb) != CGAL::COPLANAR) return false;
        return CGAL::coplanar_orientation(p, q, ra, rb) == CGAL::POSITIVE;
    }
    // One shared vertex: the triangles meet in more than that vertex exactly when the
    // edge opposite the shared vertex of one triangle meets the other triangle.
    int ia = 0;
    while (shared[ia] < 0) ++ia;
    const int ib = shared[ia];
    const K::Segment_3 opposite_a(p3(a[(ia + 1) % 3]), p3(a[(ia + 2) % 3]));
    const K::Segment_3 opposite_b(p3(b[(ib + 1) % 3]), p3(b[(ib + 2) % 3]));
    return CGAL::do_intersect(opposite_a, tb) || CGAL::do_intersect(opposite_b, ta);
}

}  // namespace bpm
