// The clearance guard of the simplifier (simplify/clearance_guard.h).

#include "simplify/clearance_guard.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace bpm::detail {

namespace {

// Squared distance from p to triangle (a, b, c) (Ericson, Real-Time Collision Detection 5.1.5).
double point_triangle_sq(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    auto sq = [&](const Vec3& q) { return dot(p - q, p - q); };
    if (d1 <= 0 && d2 <= 0) return sq(a);
    const Vec3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return sq(b);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return sq(a + (d1 / (d1 - d3)) * ab);
    const Vec3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return sq(c);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return sq(a + (d2 / (d2 - d6)) * ac);
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return sq(b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b));
    const double denom = 1.0 / (va + vb + vc);
    if (!std::isfinite(denom)) return std::min({sq(a), sq(b), sq(c)});  // no area
    return sq(a + (vb * denom) * ab + (vc * denom) * ac);
}

// Squared distance between segments p1-q1 and p2-q2 (Ericson 5.1.9).
double segment_segment_sq(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2) {
    const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
    const double a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
    double s = 0, t = 0;
    if (a <= 0 && e <= 0) return dot(r, r);
    if (a <= 0) {
        t = std::clamp(f / e, 0.0, 1.0);
    } else {
        const double c = dot(d1, r);
        if (e <= 0) {
            s = std::clamp(-c / a, 0.0, 1.0);
        } else {
            const double b = dot(d1, d2), denom = a * e - b * b;
            s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
            t = (b * s + f) / e;
            if (t < 0) t = 0, s = std::clamp(-c / a, 0.0, 1.0);
            else if (t > 1) t = 1, s = std::clamp((b - c) / a, 0.0, 1.0);
        }
    }
    const Vec3 w = (p1 + s * d1) - (p2 + t * d2);
    return dot(w, w);
}

// Squared distance from segment p-q to triangle (a, b, c), for a segment that does not
// cross the triangle (the intersection test has refused those).
double segment_triangle_sq(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
    return std::min({point_triangle_sq(p, a, b, c), point_triangle_sq(q, a, b, c), segment_segment_sq(p, q, a, b),
                     segment_segment_sq(p, q, b, c), segment_segment_sq(p, q, c, a)});
}

double longest_edge_sq(const std::vector<Vec3>& x, const Tri& t) {
    const Vec3 &a = x[size_t(t[0])], &b = x[size_t(t[1])], &c = x[size_t(t[2])];
    return std::max({dot(b - a, b - a), dot(c - b, c - b), dot(a - c, a - c)});
}

struct Box {
    Vec3 lo, hi;
};
Box box_of(const Vec3& a, const Vec3& b) {
    Box r;
    for (int k = 0; k < 3; ++k) r.lo[k] = std::min(a[k], b[k]), r.hi[k] = std::max(a[k], b[k]);
    return r;
}
Box box_of(const std::vector<Vec3>& x, const Tri& t) {
    Box r = box_of(x[size_t(t[0])], x[size_t(t[1])]);
    for (int k = 0; k < 3; ++k)
        r.lo[k] = std::min(r.lo[k], x[size_t(t[2])][k]), r.hi[k] = std::max(r.hi[k], x[size_t(t[2])][k]);
    return r;
}
bool apart(const Box& a, const Box& b, double margin) {
    for (int k = 0; k < 3; ++k)
        if (a.lo[k] > b.hi[k] + margin || b.lo[k] > a.hi[k] + margin) return true;
    return false;
}

// Whether the relative clearance of a and b may be below `floor`, judged by boxes: every
// distance it takes is at least the distance of the boxes of the parts it measures.
bool may_be_below(const std::vector<Vec3>& x, const Tri& a, const Tri& b, double floor) {
    const double margin = floor * std::sqrt(std::max(longest_edge_sq(x, a), longest_edge_sq(x, b)));
    int shared = 0, shared_a = -1, shared_b = -1;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (a[i] == b[j]) ++shared, shared_a = i, shared_b = j;
    if (shared >= 2) return false;
    const Box ba = box_of(x, a), bb = box_of(x, b);
    if (shared == 0) return !apart(ba, bb, margin);
    const Box oa = box_of(x[size_t(a[(shared_a + 1) % 3])], x[size_t(a[(shared_a + 2) % 3])]);
    const Box ob = box_of(x[size_t(b[(shared_b + 1) % 3])], x[size_t(b[(shared_b + 2) % 3])]);
    return !apart(oa, bb, margin) || !apart(ob, ba, margin);
}

}  // namespace

double relative_clearance(const std::vector<Vec3>& x, const Tri& a, const Tri& b) {
    int shared = 0, shared_a = -1, shared_b = -1;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (a[i] == b[j]) ++shared, shared_a = i, shared_b = j;
    if (shared >= 2) return std::numeric_limits<double>::infinity();
    const auto P = [&](int32_t v) -> const Vec3& { return x[size_t(v)]; };
    double d2;
    if (shared == 0) {
        d2 = std::numeric_limits<double>::infinity();
        for (int i = 0; i < 3; ++i) {
            d2 = std::min(d2, segment_triangle_sq(P(a[i]), P(a[(i + 1) % 3]), P(b[0]), P(b[1]), P(b[2])));
            d2 = std::min(d2, segment_triangle_sq(P(b[i]), P(b[(i + 1) % 3]), P(a[0]), P(a[1]), P(a[2])));
        }
    } else {
        const int32_t a1 = a[(shared_a + 1) % 3], a2 = a[(shared_a + 2) % 3];
        const int32_t b1 = b[(shared_b + 1) % 3], b2 = b[(shared_b + 2) % 3];
        d2 = std::min(segment_triangle_sq(P(a1), P(a2), P(b[0]), P(b[1]), P(b[2])),
                      segment_triangle_sq(P(b1), P(b2), P(a[0]), P(a[1]), P(a[2])));
    }
    const double size2 = std::max(longest_edge_sq(x, a), longest_edge_sq(x, b));
    if (!(size2 > 0)) return 0.0;
    return std::sqrt(d2 / size2);
}

bool keeps_clearance(const CoarseMesh& mesh, const TriangleGrid& grid, const std::vector<int32_t>& removed,
                     const std::vector<Tri>& added, const std::vector<Tri>& also, double longest_edge,
                     std::vector<TriangleGrid::Entry>& scratch, double floor) {
    if (!(floor > 0) || added.empty()) return true;
    const auto& x = mesh.positions();
    const auto is_removed = [&](int32_t t) { return std::find(removed.begin(), removed.end(), t) != removed.end(); };
    // Every pair below the floor has its other triangle's box within floor * (the longer
    // of their longest edges) of the new triangle's box, and `longest_edge` bounds the
    // other's.
    Vec3 lo = x[size_t(added[0][0])], hi = lo;
    double reach = 0;
    for (const Tri& t : added) {
        for (int32_t v : t)
            for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], x[size_t(v)][k]), hi[k] = std::max(hi[k], x[size_t(v)][k]);
        reach = std::max(reach, std::sqrt(longest_edge_sq(x, t)));
    }
    reach = floor * std::max(reach, longest_edge);
    for (int k = 0; k < 3; ++k) lo[k] -= reach, hi[k] += reach;
    grid.query_boxes(lo, hi, scratch);
    double after = std::numeric_limits<double>::infinity();
    for (const TriangleGrid::Entry& e : scratch) {
        if (!mesh.alive(e.id) || is_removed(e.id)) continue;
        const Tri& other = mesh.triangle(e.id);
        for (const Tri& t : added)
            if (may_be_below(x, t, other, floor)) after = std::min(after, relative_clearance(x, t, other));
    }
    for (const Tri& other : also)
        for (const Tri& t : added)
            if (may_be_below(x, t, other, floor)) after = std::min(after, relative_clearance(x, t, other));
    if (after >= floor) return true;
    double before = std::numeric_limits<double>::infinity();
    for (const TriangleGrid::Entry& e : scratch) {
        if (!mesh.alive(e.id) || is_removed(e.id)) continue;
        const Tri& other = mesh.triangle(e.id);
        for (int32_t r : removed)
            if (may_be_below(x, mesh.triangle(r), other, floor))
                before = std::min(before, relative_clearance(x, mesh.triangle(r), other));
    }
    for (const Tri& other : also)
        for (int32_t r : removed)
            if (may_be_below(x, mesh.triangle(r), other, floor))
                before = std::min(before, relative_clearance(x, mesh.triangle(r), other));
    return !(after < before);
}

}  // namespace bpm::detail
