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

// A triangle as the filters below see it, set up once per keeps_clearance call (a new
// star meets 10-40 triangles of the grid query) instead of once per pair.
struct Shape {
    Box box;
    double size2 = 0, size = 0;  // longest edge squared, and its root
    // Set up by with_axes, for the triangles that come within the box margin of another:
    bool has_axes = false;
    double area2 = 0;      // |(b - a) x (c - a)|^2
    double magnitude = 0;  // largest |coordinate| of a corner
    Vec3 axis[4]{};        // the unit normal, then the unit normal in the plane of edge i (corners i, i + 1)
    double proj[4][3]{};   // axis[k] . corner v
    double lo[4]{}, hi[4]{};  // the least and the greatest of proj[k]
};

void set_shape(const std::vector<Vec3>& x, const Tri& t, Shape& s) {
    s.box = box_of(x, t);
    s.size2 = longest_edge_sq(x, t);
    s.size = std::sqrt(s.size2);
    s.has_axes = false;
}

// The shapes of triangles `tris` (without axes) in `shapes`.
template <class Tris, class F>
void set_shapes(const std::vector<Vec3>& x, const Tris& tris, F&& triangle, std::vector<Shape>& shapes) {
    if (shapes.size() < tris.size()) shapes.resize(tris.size());  // in place: a Shape is 300 bytes
    for (size_t i = 0; i < tris.size(); ++i) set_shape(x, triangle(tris[i]), shapes[i]);
}

const Shape& with_axes(const std::vector<Vec3>& x, const Tri& t, Shape& s) {
    if (s.has_axes) return s;
    s.has_axes = true;
    const Vec3* p[3] = {&x[size_t(t[0])], &x[size_t(t[1])], &x[size_t(t[2])]};
    const Vec3 n = cross(*p[1] - *p[0], *p[2] - *p[0]);
    s.area2 = dot(n, n);
    for (int v = 0; v < 3; ++v)
        for (int k = 0; k < 3; ++k) s.magnitude = std::max(s.magnitude, std::abs((*p[v])[k]));
    s.axis[0] = (1.0 / std::sqrt(s.area2)) * n;  // not finite for a degenerate triangle: never used then
    for (int i = 0; i < 3; ++i) {
        const Vec3 m = cross(*p[(i + 1) % 3] - *p[i], s.axis[0]);
        s.axis[i + 1] = (1.0 / norm(m)) * m;
    }
    for (int k = 0; k < 4; ++k) {
        for (int v = 0; v < 3; ++v) s.proj[k][v] = dot(s.axis[k], *p[v]);
        s.lo[k] = std::min({s.proj[k][0], s.proj[k][1], s.proj[k][2]});
        s.hi[k] = std::max({s.proj[k][0], s.proj[k][1], s.proj[k][2]});
    }
    return s;
}

// How far apart two sets are along a unit axis, from their projections [lo1, hi1] and
// [lo2, hi2] onto it: a lower bound of their distance (negative when those overlap).
double gap(double lo1, double hi1, double lo2, double hi2) { return std::max(lo2 - hi1, lo1 - hi2); }
// The same for edge i (corners i, i + 1) of a triangle, from its corners' projections p.
double edge_gap(const double (&p)[3], int i, double lo2, double hi2) {
    const double p1 = p[i], p2 = p[(i + 1) % 3];
    return gap(std::min(p1, p2), std::max(p1, p2), lo2, hi2);
}

// relative_clearance(x, a, b) when that is below `floor`, bit for bit; otherwise some
// value >= floor (infinity). Measured are only the pairs whose boxes come within
// floor * size of each other (with a common corner: the box of one's opposite edge and
// the other's box; the box filter the guard had from the start), and of a pair only
// the parts relative_clearance takes the smallest of (an edge of one triangle against
// the other, all of them when no corner is common) that some axis does not show to lie
// farther apart than the floor * size (`reach`, with a margin for rounding): a part
// that surely measures above the floor is not the smallest when the result is below it.
// The axes: each triangle's normal and the normals of its edges in its plane (a
// separating-axis bound; the exact measure takes 5-10 times as long).
//
// Rounding: relative_clearance's distances are those of points it computes on the two
// parts, which lie on them up to rounding of the coordinates (1e-9 * magnitude covers
// that many times over), except the closest point inside a triangle (point_triangle_sq),
// whose barycentric coordinates lose digits as the triangle gets thin: about 1e-16 *
// (distance / height)^2 of its size. With the heights of both triangles at least 1e-3 of
// the larger size, that is below 1e-9 of the size (the points measured lie within twice
// the size); thinner pairs are measured in full.
double clearance_below(const std::vector<Vec3>& x, const Tri& a, Shape& sa, const Tri& b, Shape& sb,
                       double floor) {
    constexpr double kInfinity = std::numeric_limits<double>::infinity();
    // The box filter, with the boxes and sizes computed once (the root of the larger
    // square is the larger root: the same margin to the bit). A common corner lies in
    // both boxes.
    const double size = std::max(sa.size, sb.size), margin = floor * size;
    if (apart(sa.box, sb.box, margin)) return kInfinity;
    int shared = 0, shared_a = -1, shared_b = -1;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (a[i] == b[j]) ++shared, shared_a = i, shared_b = j;
    if (shared >= 2) return kInfinity;
    if (shared == 1 &&
        apart(box_of(x[size_t(a[(shared_a + 1) % 3])], x[size_t(a[(shared_a + 2) % 3])]), sb.box, margin) &&
        apart(box_of(x[size_t(b[(shared_b + 1) % 3])], x[size_t(b[(shared_b + 2) % 3])]), sa.box, margin))
        return kInfinity;
    const double size2 = std::max(sa.size2, sb.size2);
    const Shape& A = with_axes(x, a, sa);
    const Shape& B = with_axes(x, b, sb);
    const auto thick = [size2](const Shape& s) { return s.area2 > 0 && s.area2 >= 1e-6 * s.size2 * size2; };
    if (!thick(A) || !thick(B)) return relative_clearance(x, a, b);  // thin (or degenerate, or not finite)
    const double reach = margin * (1 + 1e-6) + 1e-6 * size + 1e-9 * (A.magnitude + B.magnitude);
    // The corners of each triangle on the other's axes; without a common corner, the
    // whole triangles are compared on the way (most pairs end here, at the first axis
    // that separates them).
    double b_on_a[4][3], a_on_b[4][3], b_lo[4], b_hi[4], a_lo[4], a_hi[4];
    for (int k = 0; k < 4; ++k) {
        for (int v = 0; v < 3; ++v) b_on_a[k][v] = dot(A.axis[k], x[size_t(b[v])]);
        b_lo[k] = std::min({b_on_a[k][0], b_on_a[k][1], b_on_a[k][2]});
        b_hi[k] = std::max({b_on_a[k][0], b_on_a[k][1], b_on_a[k][2]});
        if (shared == 0 && gap(A.lo[k], A.hi[k], b_lo[k], b_hi[k]) > reach) return kInfinity;
        for (int v = 0; v < 3; ++v) a_on_b[k][v] = dot(B.axis[k], x[size_t(a[v])]);
        a_lo[k] = std::min({a_on_b[k][0], a_on_b[k][1], a_on_b[k][2]});
        a_hi[k] = std::max({a_on_b[k][0], a_on_b[k][1], a_on_b[k][2]});
        if (shared == 0 && gap(a_lo[k], a_hi[k], B.lo[k], B.hi[k]) > reach) return kInfinity;
    }
    // Lower bounds of the distance from edge i of a to b, and from edge i of b to a.
    const auto bound_a = [&](int i) {
        double d = -kInfinity;
        for (int k = 0; k < 4; ++k)
            d = std::max({d, edge_gap(A.proj[k], i, b_lo[k], b_hi[k]), edge_gap(a_on_b[k], i, B.lo[k], B.hi[k])});
        return d;
    };
    const auto bound_b = [&](int i) {
        double d = -kInfinity;
        for (int k = 0; k < 4; ++k)
            d = std::max({d, edge_gap(B.proj[k], i, a_lo[k], a_hi[k]), edge_gap(b_on_a[k], i, A.lo[k], A.hi[k])});
        return d;
    };
    const auto P = [&](int32_t v) -> const Vec3& { return x[size_t(v)]; };
    double d2 = kInfinity;
    if (shared == 0) {
        for (int i = 0; i < 3; ++i) {  // relative_clearance's order
            if (!(bound_a(i) > reach))
                d2 = std::min(d2, segment_triangle_sq(P(a[i]), P(a[(i + 1) % 3]), P(b[0]), P(b[1]), P(b[2])));
            if (!(bound_b(i) > reach))
                d2 = std::min(d2, segment_triangle_sq(P(b[i]), P(b[(i + 1) % 3]), P(a[0]), P(a[1]), P(a[2])));
        }
    } else {
        const int ia = (shared_a + 1) % 3, ib = (shared_b + 1) % 3;  // the edges opposite the common corner
        const double da = bound_a(ia) > reach
                              ? kInfinity
                              : segment_triangle_sq(P(a[ia]), P(a[(ia + 1) % 3]), P(b[0]), P(b[1]), P(b[2]));
        const double db = bound_b(ib) > reach
                              ? kInfinity
                              : segment_triangle_sq(P(b[ib]), P(b[(ib + 1) % 3]), P(a[0]), P(a[1]), P(a[2]));
        d2 = std::min(da, db);
    }
    if (d2 == kInfinity) return kInfinity;
    return std::sqrt(d2 / size2);  // size2 > 0: both triangles have an area
}

}  // namespace

double longest_edge(const std::vector<Vec3>& x, const Tri& t) { return std::sqrt(longest_edge_sq(x, t)); }

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
    static thread_local std::vector<Shape> added_shapes, removed_shapes, other_shapes;
    static thread_local std::vector<Tri> others;
    const auto same = [](const Tri& t) -> const Tri& { return t; };
    const auto of_mesh = [&](int32_t r) -> const Tri& { return mesh.triangle(r); };
    set_shapes(x, added, same, added_shapes);
    set_shapes(x, removed, of_mesh, removed_shapes);
    // Every pair below the floor has its other triangle's box within floor * (the longer
    // of their longest edges) of its own box, and `longest_edge` bounds the other's. One
    // query serves both: the removed triangles' box holds the new ones' (their corners are
    // the link's), so it finds every triangle near the star as it is and as it will be
    // (the star's old contacts may lie beyond the new triangles, e.g. at a peak's tip).
    Vec3 lo = added_shapes[0].box.lo, hi = added_shapes[0].box.hi;
    double reach = 0;
    for (size_t i = 0; i < added.size(); ++i) {
        const Shape& s = added_shapes[i];
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], s.box.lo[k]), hi[k] = std::max(hi[k], s.box.hi[k]);
        reach = std::max(reach, s.size);
    }
    for (size_t i = 0; i < removed.size(); ++i) {
        const Shape& s = removed_shapes[i];
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], s.box.lo[k]), hi[k] = std::max(hi[k], s.box.hi[k]);
        reach = std::max(reach, s.size);
    }
    reach = floor * std::max(reach, longest_edge);
    for (int k = 0; k < 3; ++k) lo[k] -= reach, hi[k] += reach;
    grid.query_boxes(lo, hi, scratch);
    // The triangles to compare with: those of the grid (by id) that are alive and stay,
    // then `also`.
    others.clear();
    for (const TriangleGrid::Entry& e : scratch)
        if (mesh.alive(e.id) && !is_removed(e.id)) others.push_back(mesh.triangle(e.id));
    others.insert(others.end(), also.begin(), also.end());
    set_shapes(x, others, same, other_shapes);
    double after = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < others.size(); ++j)
        for (size_t i = 0; i < added.size(); ++i)
            after = std::min(after, clearance_below(x, added[i], added_shapes[i], others[j], other_shapes[j], floor));
    // And the new triangles among themselves: a removal along a junction line makes a fan
    // per sheet, and two sheets' fans meet only at the line's ends (pairs sharing an edge
    // are the wedge guard's).
    for (size_t i = 0; i < added.size(); ++i)
        for (size_t j = 0; j < i; ++j)
            after = std::min(after, clearance_below(x, added[i], added_shapes[i], added[j], added_shapes[j], floor));
    if (after >= floor) return true;
    double before = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < others.size(); ++j)
        for (size_t i = 0; i < removed.size(); ++i)
            before = std::min(before, clearance_below(x, mesh.triangle(removed[i]), removed_shapes[i], others[j],
                                                      other_shapes[j], floor));
    for (size_t i = 0; i < removed.size(); ++i)
        for (size_t j = 0; j < i; ++j)
            before = std::min(before, clearance_below(x, mesh.triangle(removed[i]), removed_shapes[i],
                                                      mesh.triangle(removed[j]), removed_shapes[j], floor));
    return !(after < before);
}

}  // namespace bpm::detail
