// The exact decision of check_intersections for one pair of triangles; see improper_pair.h.
#include "check/improper_pair.h"

#include <algorithm>
#include <cmath>

#include "bpm/predicates.h"
#include "core/triangle_intersection.h"

namespace bpm::detail {

namespace {
// orient3d with an exact shortcut for four points in one axis-aligned plane (flat
// faces of CAD and voxel models), where the filtered predicate cannot certify the zero
// and falls back to slow exact arithmetic.
int orient3d_flat(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    for (int k = 0; k < 3; ++k)
        if (a[k] == b[k] && a[k] == c[k] && a[k] == d[k]) return 0;
    return orient3d(a, b, c, d);
}

int drop_axis(const Vec3& p, const Vec3& q, const Vec3& r) {
    const Vec3 n = cross(q - p, r - p);
    int order[3] = {0, 1, 2};
    std::sort(order, order + 3, [&](int i, int j) { return std::abs(n[i]) > std::abs(n[j]); });
    for (int k : order) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        if (orient2d({p[i], p[j]}, {q[i], q[j]}, {r[i], r[j]}) != 0) return k;
    }
    return -1;  // degenerate triangle (excluded before)
}

// Is x (coplanar with triangle (s, a1, a2)) in the closed wedge at s spanned by a1, a2,
// other than at s itself? Projected along axis k.
bool in_wedge(int k, const Vec3& s, const Vec3& a1, const Vec3& a2, const Vec3& x) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const Vec2 S{s[i], s[j]}, A1{a1[i], a1[j]}, A2{a2[i], a2[j]}, X{x[i], x[j]};
    const int sigma = orient2d(S, A1, A2);  // non-zero: a is not degenerate
    return sigma * orient2d(S, A1, X) >= 0 && sigma * orient2d(S, A2, X) <= 0;
}

// Triangles sharing exactly one vertex s are decided here with orientation tests
// only (the common case in every mesh; CGAL's general test is much slower, above all
// for coplanar neighbours). b meets the plane of a in {s} if both other corners of b
// are strictly on one side; in the segment [s, b1] if only b1 is in the plane; in all
// of b if b is coplanar. A segment or triangle starting at s meets a beyond s exactly
// when one of its directions from s lies in a's closed corner wedge at s (a is convex
// and contains a neighbourhood of s within that wedge). The wedge tests run in a
// coordinate plane onto which a's plane projects bijectively (checked exactly).
// Returns -1 when undecided (b crosses a's plane transversally): the caller then uses
// the general predicate.
int one_shared_vertex(const Vec3 a[3], int ia, const Vec3 b[3], int ib) {
    const Vec3 &s = a[ia], &a1 = a[(ia + 1) % 3], &a2 = a[(ia + 2) % 3];
    const Vec3 &b1 = b[(ib + 1) % 3], &b2 = b[(ib + 2) % 3];
    const int o1 = orient3d_flat(s, a1, a2, b1), o2 = orient3d_flat(s, a1, a2, b2);
    if (o1 != 0 && o1 == o2) return 0;
    if (o1 == 0 || o2 == 0) {
        // b meets a's plane in a segment from s or in all of b (coplanar).
        const int k = drop_axis(s, a1, a2);
        if (k < 0) return -1;
        if (o1 == 0 && o2 == 0) {
            // coplanar: the two corner wedges at s overlap or touch beyond s
            return (in_wedge(k, s, a1, a2, b1) || in_wedge(k, s, a1, a2, b2) || in_wedge(k, s, b1, b2, a1) ||
                    in_wedge(k, s, b1, b2, a2))
                       ? 1
                       : 0;
        }
        return in_wedge(k, s, a1, a2, o1 == 0 ? b1 : b2) ? 1 : 0;
    }
    // b crosses a's plane; look from b's side.
    const int p1 = orient3d_flat(b[ib], b1, b2, a1), p2 = orient3d_flat(b[ib], b1, b2, a2);
    if (p1 != 0 && p1 == p2) return 0;
    if (p1 != 0 && p2 != 0) return -1;
    // a meets b's plane in a segment from s (p1 == p2 == 0 would make a and b coplanar).
    const int k = drop_axis(b[ib], b1, b2);
    if (k < 0) return -1;
    return in_wedge(k, b[ib], b1, b2, p1 == 0 ? a1 : a2) ? 1 : 0;
}

// Triangles sharing the edge (p, q): they meet beyond it exactly when they are
// coplanar and their third corners lie on the same side of the line pq.
int shared_edge(const Vec3 a[3], const Vec3 b[3], const int shared[3]) {
    int ia = 0;
    while (shared[ia] >= 0) ++ia;
    const int ip = (ia + 1) % 3, iq = (ia + 2) % 3;
    const int ib = 3 - shared[ip] - shared[iq];
    const Vec3 &p = a[ip], &q = a[iq], &ra = a[ia], &rb = b[ib];
    if (orient3d_flat(p, q, ra, rb) != 0) return 0;
    const int k = drop_axis(p, q, ra);
    if (k < 0) return -1;
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const Vec2 P{p[i], p[j]}, Q{q[i], q[j]};
    return orient2d(P, Q, {ra[i], ra[j]}) == orient2d(P, Q, {rb[i], rb[j]}) ? 1 : 0;
}

}  // namespace

bool surface_triangles_meet_improperly(const std::vector<Vec3>& V, const Tri& A, const Tri& B) {
    int shared[3] = {-1, -1, -1};
    int count = 0, shared_a = -1, shared_b = -1;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (A[i] == B[j]) {
                shared[i] = j;
                ++count;
                shared_a = i;
                shared_b = j;
            }
    const Vec3 a[3] = {V[A[0]], V[A[1]], V[A[2]]};
    const Vec3 b[3] = {V[B[0]], V[B[1]], V[B[2]]};
    const int fast = count == 1 ? one_shared_vertex(a, shared_a, b, shared_b)
                     : count == 2 ? shared_edge(a, b, shared)
                                  : -1;
    return fast == 1 || (fast < 0 && nondegenerate_triangles_intersect_improperly(a, b, shared));
}

}  // namespace bpm::detail
