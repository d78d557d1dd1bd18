// Points of the coarse surface across triangle boundaries; see bpm/coarse_surface.h.
//
// Midpoints unfold a path of coarse triangles T0 (a's), T1, ..., Tk (b's), consecutive
// ones sharing an edge, into the plane of T0: T0 is laid out isometrically, and each next
// triangle is hinged about its shared edge onto the side away from the previous one,
// keeping its edge lengths. In that plane the midpoint of a and b is the average of their
// positions; it is expressed in barycentric coordinates of the unfolded triangle of the
// path that contains it (the first in path order; the one it is least outside of when
// none does), which are its coordinates in that coarse triangle.

#include "bpm/coarse_surface.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "bpm/errors.h"

namespace bpm {

namespace {

// The corners of the triangle a point lies on the closure of: 1 (corner), 2 (edge) or 3
// (interior) corner indices with nonzero coordinate.
struct Support {
    int count = 0;
    int32_t vertices[3] = {-1, -1, -1};
};

Support support_of(const Surface& s, const SurfacePoint& p) {
    Support out;
    const Tri& t = s.triangles[static_cast<size_t>(p.triangle)];
    for (int k = 0; k < 3; ++k)
        if (p.barycentric[k] != 0) out.vertices[out.count++] = t[k];
    if (out.count == 0) out.vertices[out.count++] = t[0];  // all zero: not a point; treat as corner 0
    return out;
}

int corner_of(const Tri& t, int32_t v) {
    for (int k = 0; k < 3; ++k)
        if (t[k] == v) return k;
    return -1;
}

// A triangle laid out in the plane: its corners' 2D positions in corner order.
struct Flat {
    int32_t triangle;
    Vec2 corner[3];
};

Vec2 point_in(const Flat& f, const Vec3& b) {
    return b[0] * f.corner[0] + b[1] * f.corner[1] + b[2] * f.corner[2];
}

// Barycentric coordinates of m in the flat triangle.
Vec3 barycentric_in(const Flat& f, const Vec2& m) {
    const Vec2 e1 = f.corner[1] - f.corner[0], e2 = f.corner[2] - f.corner[0], d = m - f.corner[0];
    const double det = cross(e1, e2);
    const double l1 = cross(d, e2) / det, l2 = cross(e1, d) / det;
    return {1 - l1 - l2, l1, l2};
}

double corner_angle(const Vec3& apex, const Vec3& p, const Vec3& q) {
    const Vec3 u = p - apex, w = q - apex;
    return std::atan2(norm(cross(u, w)), dot(u, w));
}

}  // namespace

CoarseSurface::CoarseSurface(const Surface& coarse) : coarse_(coarse), connectivity_(build_connectivity(coarse)) {}

std::optional<SurfacePoint> CoarseSurface::express_in(const SurfacePoint& p, int32_t triangle) const {
    const int32_t nt = coarse_.num_triangles();
    if (p.triangle < 0 || p.triangle >= nt || triangle < 0 || triangle >= nt)
        throw std::out_of_range("CoarseSurface::express_in: coarse triangle index outside [0, " + std::to_string(nt) +
                                ")");
    if (triangle == p.triangle) return p;
    const Tri& from = coarse_.triangles[static_cast<size_t>(p.triangle)];
    const Tri& to = coarse_.triangles[static_cast<size_t>(triangle)];
    SurfacePoint out{triangle, {0, 0, 0}};
    for (int k = 0; k < 3; ++k) {
        if (p.barycentric[k] == 0) continue;
        const int c = corner_of(to, from[k]);
        if (c < 0) return std::nullopt;
        out.barycentric[c] = p.barycentric[k];
    }
    return out;
}

namespace {

// The triangles containing a point with this support, ascending.
std::vector<int32_t> triangles_containing(const SurfaceConnectivity& c, const Support& s, int32_t own) {
    if (s.count == 3) return {own};
    if (s.count == 2) {
        const int32_t e = c.find_edge(s.vertices[0], s.vertices[1]);
        if (e < 0) return {own};
        return std::vector<int32_t>(c.edge_triangles.begin() + c.edge_triangle_offsets[static_cast<size_t>(e)],
                                    c.edge_triangles.begin() + c.edge_triangle_offsets[static_cast<size_t>(e) + 1]);
    }
    const size_t v = static_cast<size_t>(s.vertices[0]);
    return std::vector<int32_t>(c.vertex_triangles.begin() + c.vertex_triangle_offsets[v],
                                c.vertex_triangles.begin() + c.vertex_triangle_offsets[v + 1]);
}

// The owner first, then the others ascending (deterministic preference for the frame the
// caller gave).
void own_first(std::vector<int32_t>& list, int32_t own) {
    auto it = std::find(list.begin(), list.end(), own);
    if (it != list.end()) std::rotate(list.begin(), it, it + 1);
}

}  // namespace

SurfacePoint CoarseSurface::midpoint(const SurfacePoint& a, const SurfacePoint& b) const {
    const int32_t nt = coarse_.num_triangles();
    if (a.triangle < 0 || a.triangle >= nt || b.triangle < 0 || b.triangle >= nt)
        throw std::out_of_range("CoarseSurface::midpoint: coarse triangle index outside [0, " + std::to_string(nt) +
                                ")");
    const auto average = [](const SurfacePoint& x, const SurfacePoint& y) {
        return SurfacePoint{x.triangle, 0.5 * (x.barycentric + y.barycentric)};
    };
    if (a.triangle == b.triangle) return average(a, b);
    std::vector<int32_t> ta = triangles_containing(connectivity_, support_of(coarse_, a), a.triangle);
    std::vector<int32_t> tb = triangles_containing(connectivity_, support_of(coarse_, b), b.triangle);
    own_first(ta, a.triangle);
    own_first(tb, b.triangle);
    // 1. A triangle containing both.
    if (std::find(ta.begin(), ta.end(), b.triangle) != ta.end()) return average(*express_in(a, b.triangle), b);
    for (int32_t t : ta)
        if (std::find(tb.begin(), tb.end(), t) != tb.end()) return average(*express_in(a, t), *express_in(b, t));

    const auto& x = coarse_.vertices;
    const auto pos = [&](int32_t v) { return x[static_cast<size_t>(v)]; };
    const auto tri = [&](int32_t t) -> const Tri& { return coarse_.triangles[static_cast<size_t>(t)]; };
    const auto shared = [&](int32_t s, int32_t t, int32_t* common) {
        int n = 0;
        for (int32_t v : tri(s))
            if (corner_of(tri(t), v) >= 0) common[n++] = v;
        return n;
    };

    // The path of triangles to unfold, from a triangle of a to a triangle of b.
    std::vector<int32_t> path;
    // 2. Two triangles sharing an edge.
    for (int32_t s : ta) {
        for (int32_t t : tb) {
            int32_t common[3];
            if (shared(s, t, common) == 2) {
                path = {s, t};
                break;
            }
        }
        if (!path.empty()) break;
    }
    // 3. Two triangles sharing a vertex: around its fan.
    if (path.empty()) {
        int32_t s = -1, t = -1, v = -1;
        for (int32_t s0 : ta) {
            for (int32_t t0 : tb) {
                int32_t common[3];
                if (shared(s0, t0, common) == 1) {
                    s = s0, t = t0, v = common[0];
                    break;
                }
            }
            if (v >= 0) break;
        }
        if (v < 0)
            throw AlgorithmError("midpoint: the points are in coarse triangles " + std::to_string(a.triangle) +
                                 " and " + std::to_string(b.triangle) +
                                 ", which share no vertex (not the ends of one edge of a refined grid)");
        // The fan of v must be one sheet: every edge at v has at most two triangles.
        const auto next_around = [&](int32_t from, int32_t over) -> int32_t {
            // The triangle across edge (v, over) from `from`; -1 at a boundary.
            const int32_t e = connectivity_.find_edge(v, over);
            const int64_t e0 = connectivity_.edge_triangle_offsets[static_cast<size_t>(e)];
            const int64_t e1 = connectivity_.edge_triangle_offsets[static_cast<size_t>(e) + 1];
            if (e1 - e0 > 2)
                throw AlgorithmError("midpoint: coarse vertex " + std::to_string(v) +
                                     " has no single fan of triangles: its edge to vertex " + std::to_string(over) +
                                     " has " + std::to_string(e1 - e0) + " triangles");
            for (int64_t k = e0; k < e1; ++k)
                if (connectivity_.edge_triangles[static_cast<size_t>(k)] != from)
                    return connectivity_.edge_triangles[static_cast<size_t>(k)];
            return -1;
        };
        const auto other_at_v = [&](int32_t triangle, int32_t not_this) {
            for (int32_t w : tri(triangle))
                if (w != v && w != not_this) return w;
            return int32_t(-1);
        };
        const auto angle_at_v = [&](int32_t triangle) {
            const Tri& t3 = tri(triangle);
            const int c = corner_of(t3, v);
            return corner_angle(pos(v), pos(t3[(c + 1) % 3]), pos(t3[(c + 2) % 3]));
        };
        std::vector<int32_t> best_path;
        double best_angle = std::numeric_limits<double>::infinity();
        const Tri& ts = tri(s);
        const int cs = corner_of(ts, v);
        for (int32_t first_edge : {ts[(cs + 1) % 3], ts[(cs + 2) % 3]}) {
            std::vector<int32_t> walk = {s};
            double angle = angle_at_v(s);
            int32_t current = s, over = first_edge;
            const size_t fan_size = static_cast<size_t>(
                connectivity_.vertex_triangle_offsets[static_cast<size_t>(v) + 1] -
                connectivity_.vertex_triangle_offsets[static_cast<size_t>(v)]);
            bool reached = false;
            while (walk.size() <= fan_size) {
                const int32_t next = next_around(current, over);
                if (next < 0 || next == s) break;
                walk.push_back(next);
                angle += angle_at_v(next);
                if (next == t) {
                    reached = true;
                    break;
                }
                over = other_at_v(next, over);
                current = next;
            }
            if (reached && angle < best_angle) {
                best_angle = angle;
                best_path = walk;
            }
        }
        if (best_path.empty())
            throw AlgorithmError("midpoint: coarse vertex " + std::to_string(v) +
                                 " has no single fan of triangles: coarse triangles " + std::to_string(s) + " and " +
                                 std::to_string(t) + " at it are not connected through its edges");
        path = best_path;
    }

    // Unfold the path into the plane of its first triangle.
    std::vector<Flat> flats(path.size());
    {
        const Tri& t0 = tri(path[0]);
        const Vec3 e1 = pos(t0[1]) - pos(t0[0]), e2 = pos(t0[2]) - pos(t0[0]);
        const double l1 = norm(e1);
        flats[0] = Flat{path[0], {Vec2{0, 0}, Vec2{l1, 0}, Vec2{dot(e2, e1) / l1, norm(cross(e1, e2)) / l1}}};
    }
    for (size_t i = 1; i < path.size(); ++i) {
        const Tri& prev = tri(path[i - 1]);
        const Tri& cur = tri(path[i]);
        Flat& f = flats[i];
        f.triangle = path[i];
        int opposite = -1;
        Vec2 previous_third{0, 0};
        for (int k = 0; k < 3; ++k) {
            const int c = corner_of(prev, cur[k]);
            if (c >= 0)
                f.corner[k] = flats[i - 1].corner[c];
            else
                opposite = k;
        }
        for (int k = 0; k < 3; ++k)
            if (corner_of(cur, prev[k]) < 0) previous_third = flats[i - 1].corner[k];
        const int ku = (opposite + 1) % 3, kw = (opposite + 2) % 3;
        const Vec3 u = pos(cur[ku]), w = pos(cur[kw]), d = pos(cur[opposite]);
        const Vec3 uw = w - u;
        const double s = dot(d - u, uw) / dot(uw, uw);
        const double height = norm(d - (u + s * uw));
        const Vec2 U = f.corner[ku], W = f.corner[kw];
        const Vec2 along = W - U;
        Vec2 normal{-along[1], along[0]};
        const double length = std::sqrt(dot(normal, normal));
        normal = (1 / length) * normal;
        if (dot(normal, previous_third - U) > 0) normal = -1.0 * normal;
        f.corner[opposite] = U + s * along + height * normal;
    }
    const SurfacePoint a0 = *express_in(a, path.front());
    const SurfacePoint b0 = *express_in(b, path.back());
    const Vec2 m = 0.5 * (point_in(flats.front(), a0.barycentric) + point_in(flats.back(), b0.barycentric));
    size_t best = 0;
    double best_min = -std::numeric_limits<double>::infinity();
    Vec3 best_bary{1, 0, 0};
    for (size_t i = 0; i < flats.size(); ++i) {
        const Vec3 l = barycentric_in(flats[i], m);
        const double mn = std::min({l[0], l[1], l[2]});
        if (mn > best_min) {
            best_min = mn, best = i, best_bary = l;
            if (mn >= 0) break;
        }
    }
    if (best_min < 0) {
        for (double& c : best_bary) c = std::max(c, 0.0);
        const double sum = best_bary[0] + best_bary[1] + best_bary[2];
        best_bary = (1 / sum) * best_bary;
    }
    return SurfacePoint{flats[best].triangle, best_bary};
}

}  // namespace bpm
