// The refined surface as a parametrized surface (.bpm): S' = refined surface as coarse
// surface, phi' = phi o (S' -> S).
//
// In the parameter triangle of every coarse triangle t, the pieces of phi and the
// refined triangles are two triangulations; their overlay consists of the convex
// polygons (piece q) ∩ (refined triangle r). phi is affine on each polygon. The new
// original surface is S0 cut along the images of those polygons (flat, same geometry),
// so every polygon (fanned into triangles by ear clipping) is one new original triangle
// and one piece of phi' at the same time.
//
// All decisions (is a node inside a refined triangle, do two edges cross properly) use
// the exact orientation of barycentric triples: sign det[p; q; x] is the orientation of
// (p, q, x) in the parameter plane for any positive scaling of the rows, so it is exact
// even when stored coordinates sum to 1 only up to rounding.

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include "bpm/errors.h"
#include "bpm/predicates.h"
#include "bpm/refine.h"

namespace bpm {

namespace {

int orient_bary(const Vec3& p, const Vec3& q, const Vec3& x) {
    static const int sign = orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
    return sign * orient3d({0, 0, 0}, p, q, x);
}

inline double area2(const Vec3& p, const Vec3& q, const Vec3& x) {  // in the (b1, b2) plane
    return (q[1] - p[1]) * (x[2] - p[2]) - (q[2] - p[2]) * (x[1] - p[1]);
}

using Key = std::array<int64_t, 5>;

struct OverlayPoint {
    Vec3 b;           // barycentric in the coarse triangle
    Vec3 image;       // phi(b)
    int32_t vertex;   // vertex of the new original surface
    int corner = -1;  // corner of the refined triangle, or -1
    int on_edge[3] = {0, 0, 0};  // on local edge k of the refined triangle
    int strict[3] = {0, 0, 0};   // strictly inside with respect to local edge k (exact decision)
};

class Overlay {
public:
    Overlay(const Parametrization& p, const RefinedSurface& r) : p_(p), r_(r) {
        out_.original.vertices = p.original.vertices;
        refined_vertex_.assign(r.surface.vertices.size(), -1);
    }

    int32_t vertex_for(const Key& key, const Vec3& x) {
        auto it = vertices_.find(key);
        if (it != vertices_.end()) return it->second;
        const int32_t id = int32_t(out_.original.vertices.size());
        out_.original.vertices.push_back(x);
        vertices_.emplace(key, id);
        return id;
    }

    int32_t node_vertex(int64_t g) {
        const size_t i = size_t(g);
        if (p_.node_kind[i] != NodeKind::EdgeCrossing) return p_.node_original_vertex[i];
        const auto& e = p_.node_original_edge[i];
        int64_t bits;
        const double s = p_.node_edge_parameter[i];
        std::memcpy(&bits, &s, sizeof bits);
        return vertex_for({1, e[0], e[1], bits, 0}, p_.node_image[i]);
    }

    void run(const Context& context) {
        const int32_t nct = p_.coarse.num_triangles();
        std::vector<std::vector<int32_t>> by_coarse(static_cast<size_t>(nct));
        for (size_t i = 0; i < r_.triangle_coarse.size(); ++i) by_coarse[size_t(r_.triangle_coarse[i])].push_back(int32_t(i));
        const size_t nrt = r_.triangle_coarse.size();
        polys_.assign(nrt, {});
        for (int32_t t = 0; t < nct; ++t) {
            if (t % 256 == 0) context.report(double(t) / std::max(1, nct), "overlay with phi");
            const int64_t n0 = p_.node_offsets[size_t(t)], n1 = p_.node_offsets[size_t(t) + 1];
            std::vector<int32_t> nv(size_t(n1 - n0));
            for (int64_t g = n0; g < n1; ++g) nv[size_t(g - n0)] = node_vertex(g);
            for (int32_t ri : by_coarse[size_t(t)]) overlay_triangle(t, ri, nv);
        }
        assemble();
    }

    Parametrization take() { return std::move(out_); }

private:
    // Vertex of the new original surface for corner k of refined triangle ri.
    int32_t corner_vertex(int32_t t, int32_t ri, int k, const std::vector<int32_t>& nv) {
        const int32_t rv = r_.surface.triangles[size_t(ri)][size_t(k)];
        if (refined_vertex_[size_t(rv)] >= 0) return refined_vertex_[size_t(rv)];
        const Vec3& b = r_.triangle_barycentric[size_t(ri)][size_t(k)];
        const int64_t n0 = p_.node_offsets[size_t(t)], n1 = p_.node_offsets[size_t(t) + 1];
        int32_t id = -1;
        for (int64_t g = n0; g < n1 && id < 0; ++g)
            if (p_.node_barycentric[size_t(g)] == b) id = nv[size_t(g - n0)];
        if (id < 0) id = vertex_for({2, rv, 0, 0, 0}, r_.surface.vertices[size_t(rv)]);
        refined_vertex_[size_t(rv)] = id;
        return id;
    }

    void overlay_triangle(int32_t t, int32_t ri, const std::vector<int32_t>& nv) {
        const auto& R = r_.triangle_barycentric[size_t(ri)];
        const Tri& rt = r_.surface.triangles[size_t(ri)];
        int32_t rc[3];
        for (int k = 0; k < 3; ++k) rc[k] = corner_vertex(t, ri, k, nv);
        double lo1 = std::min({R[0][1], R[1][1], R[2][1]}), hi1 = std::max({R[0][1], R[1][1], R[2][1]});
        double lo2 = std::min({R[0][2], R[1][2], R[2][2]}), hi2 = std::max({R[0][2], R[1][2], R[2][2]});
        const double margin = 1e-12;
        const int64_t n0 = p_.node_offsets[size_t(t)];
        for (int64_t q = p_.piece_offsets[size_t(t)]; q < p_.piece_offsets[size_t(t) + 1]; ++q) {
            const Tri& pc = p_.pieces[size_t(q)];
            Vec3 N[3], I[3];
            int32_t id[3];
            for (int k = 0; k < 3; ++k) {
                N[k] = p_.node_barycentric[size_t(n0 + pc[size_t(k)])];
                I[k] = p_.node_image[size_t(n0 + pc[size_t(k)])];
                id[k] = nv[size_t(pc[size_t(k)])];
            }
            if (std::max({N[0][1], N[1][1], N[2][1]}) < lo1 - margin ||
                std::min({N[0][1], N[1][1], N[2][1]}) > hi1 + margin ||
                std::max({N[0][2], N[1][2], N[2][2]}) < lo2 - margin ||
                std::min({N[0][2], N[1][2], N[2][2]}) > hi2 + margin)
                continue;
            std::vector<OverlayPoint> pts;
            // Piece nodes inside or on the refined triangle.
            for (int k = 0; k < 3; ++k) {
                // A node that is a corner of the refined triangle is that corner, even if the
                // node's coordinates in this coarse triangle differ from the corner's by rounding.
                int corner = -1;
                for (int j = 0; j < 3; ++j)
                    if (id[k] == rc[j]) corner = j;
                if (corner >= 0) {
                    OverlayPoint x{R[size_t(corner)], I[k], id[k]};
                    x.corner = corner;
                    x.on_edge[corner] = x.on_edge[(corner + 2) % 3] = 1;
                    pts.push_back(x);
                    continue;
                }
                int o[3];
                for (int j = 0; j < 3; ++j) o[j] = orient_bary(R[size_t(j)], R[size_t((j + 1) % 3)], N[k]);
                if (o[0] < 0 || o[1] < 0 || o[2] < 0) continue;
                OverlayPoint x{N[k], I[k], id[k]};
                for (int j = 0; j < 3; ++j) x.on_edge[j] = o[j] == 0, x.strict[j] = o[j] > 0;
                pts.push_back(x);
            }
            // Refined corners inside or on the piece (unless they are one of its nodes).
            for (int j = 0; j < 3; ++j) {
                if (rc[j] == id[0] || rc[j] == id[1] || rc[j] == id[2]) continue;
                int o[3];
                for (int k = 0; k < 3; ++k) o[k] = orient_bary(N[k], N[(k + 1) % 3], R[size_t(j)]);
                if (o[0] < 0 || o[1] < 0 || o[2] < 0) continue;
                OverlayPoint x{R[size_t(j)], r_.surface.vertices[size_t(rt[size_t(j)])], rc[j]};
                x.corner = j;
                x.on_edge[j] = x.on_edge[(j + 2) % 3] = 1;
                pts.push_back(x);
            }
            // Proper crossings of piece edges with refined edges.
            for (int k = 0; k < 3; ++k) {
                const int k1 = (k + 1) % 3;
                for (int j = 0; j < 3; ++j) {
                    const int j1 = (j + 1) % 3;
                    const int a1 = orient_bary(R[size_t(j)], R[size_t(j1)], N[k]);
                    const int a2 = orient_bary(R[size_t(j)], R[size_t(j1)], N[k1]);
                    if (a1 * a2 >= 0) continue;
                    const int c1 = orient_bary(N[k], N[k1], R[size_t(j)]);
                    const int c2 = orient_bary(N[k], N[k1], R[size_t(j1)]);
                    if (c1 * c2 >= 0) continue;
                    // Parameter along the piece edge in a canonical direction (lower vertex id first).
                    const int ka = id[k] < id[k1] ? k : k1, kb = ka == k ? k1 : k;
                    const double d1 = area2(R[size_t(j)], R[size_t(j1)], N[ka]);
                    const double d2 = area2(R[size_t(j)], R[size_t(j1)], N[kb]);
                    double s = d1 / (d1 - d2);
                    s = std::min(1.0, std::max(0.0, s));
                    const Vec3 b = N[ka] + s * (N[kb] - N[ka]);
                    const Vec3 image = I[ka] + s * (I[kb] - I[ka]);
                    const int32_t ra = std::min(rt[size_t(j)], rt[size_t(j1)]);
                    const int32_t rb = std::max(rt[size_t(j)], rt[size_t(j1)]);
                    OverlayPoint x{b, image, vertex_for({3, id[ka], id[kb], ra, rb}, image)};
                    x.on_edge[j] = 1;
                    x.strict[j1] = x.strict[(j + 2) % 3] = 1;
                    pts.push_back(x);
                }
            }
            if (pts.size() < 3) continue;
            // Order counter-clockwise around the centroid.
            double c1 = 0, c2 = 0;
            for (const auto& x : pts) c1 += x.b[1], c2 += x.b[2];
            c1 /= double(pts.size()), c2 /= double(pts.size());
            std::sort(pts.begin(), pts.end(), [&](const OverlayPoint& a, const OverlayPoint& b) {
                return std::atan2(a.b[2] - c2, a.b[1] - c1) < std::atan2(b.b[2] - c2, b.b[1] - c1);
            });
            // Drop a repeated vertex (cannot happen with exact decisions; be safe).
            pts.erase(std::unique(pts.begin(), pts.end(),
                                  [](const OverlayPoint& a, const OverlayPoint& b) { return a.vertex == b.vertex; }),
                      pts.end());
            if (pts.size() < 3) continue;
            double area = 0;
            for (size_t i = 0; i < pts.size(); ++i) area += area2(pts[0].b, pts[i].b, pts[(i + 1) % pts.size()].b);
            if (!(area > 0)) continue;
            Polygon poly;
            poly.original_triangle = p_.piece_original_triangle[size_t(q)];
            poly.points = std::move(pts);
            polys_[size_t(ri)].push_back(std::move(poly));
        }
    }

    struct Polygon {
        int32_t original_triangle;
        std::vector<OverlayPoint> points;
    };

    // Barycentric coordinates of x (in the coarse triangle) in refined triangle R, with
    // exact zeros on its edges and unit vectors at its corners.
    static Vec3 to_refined(const std::array<Vec3, 3>& R, const OverlayPoint& x) {
        if (x.corner >= 0) {
            Vec3 e{0, 0, 0};
            e[size_t(x.corner)] = 1;
            return e;
        }
        const double u1 = R[1][1] - R[0][1], u2 = R[1][2] - R[0][2];
        const double v1 = R[2][1] - R[0][1], v2 = R[2][2] - R[0][2];
        const double w1 = x.b[1] - R[0][1], w2 = x.b[2] - R[0][2];
        const double det = u1 * v2 - u2 * v1;
        double l1 = (w1 * v2 - w2 * v1) / det, l2 = (u1 * w2 - u2 * w1) / det;
        Vec3 l{1 - l1 - l2, l1, l2};
        for (int k = 0; k < 3; ++k)
            if (x.on_edge[k]) l[size_t((k + 2) % 3)] = 0;
        double sum = 0;
        for (double& c : l) c = std::max(c, 0.0), sum += c;
        for (double& c : l) c /= sum;
        for (int k = 0; k < 3; ++k)
            if (x.on_edge[k]) l[size_t((k + 2) % 3)] = 0;
        // A point decided (exactly) to be strictly inside keeps a positive coordinate even
        // when it is within rounding of the edge, so that thin overlay pieces keep their
        // orientation.
        for (int k = 0; k < 3; ++k)
            if (x.strict[k] && !(l[size_t((k + 2) % 3)] > 0)) l[size_t((k + 2) % 3)] = 1e-300;
        return l;
    }

    void assemble() {
        const size_t nrt = polys_.size();
        Parametrization& o = out_;
        o.coarse = r_.surface;
        o.coarse_vertex_origin.assign(r_.surface.vertices.size(), -1);
        o.node_offsets.assign(1, 0);
        o.piece_offsets.assign(1, 0);
        const double nan = std::numeric_limits<double>::quiet_NaN();
        for (size_t ri = 0; ri < nrt; ++ri) {
            const Tri& rt = r_.surface.triangles[ri];
            const auto& R = r_.triangle_barycentric[ri];
            std::map<int32_t, int32_t> local;
            auto add_node = [&](const OverlayPoint& x, NodeKind kind) {
                auto it = local.find(x.vertex);
                if (it != local.end()) return it->second;
                const int32_t l = int32_t(local.size());
                local.emplace(x.vertex, l);
                o.node_barycentric.push_back(to_refined(R, x));
                o.node_image.push_back(o.original.vertices[size_t(x.vertex)]);
                o.node_kind.push_back(kind);
                o.node_original_vertex.push_back(x.vertex);
                o.node_original_edge.push_back({-1, -1});
                o.node_edge_parameter.push_back(nan);
                return l;
            };
            // The corners first, in corner order.
            for (int k = 0; k < 3; ++k) {
                int32_t v = -1;
                for (const auto& poly : polys_[ri])
                    for (const auto& x : poly.points)
                        if (x.corner == k) v = x.vertex;
                if (v < 0) throw AlgorithmError(degenerate_message(ri));  // its pieces were all too thin
                OverlayPoint c{R[size_t(k)], {}, v};
                c.corner = k;
                add_node(c, NodeKind::CoarseCorner);
                o.coarse_vertex_origin[size_t(rt[size_t(k)])] = v;
            }
            for (const auto& poly : polys_[ri]) {
                std::vector<int32_t> ring;
                std::vector<Vec3> rb;
                for (const auto& x : poly.points) {
                    ring.push_back(add_node(x, NodeKind::OriginalVertex));
                    rb.push_back(o.node_barycentric[size_t(o.node_offsets.back()) + size_t(ring.back())]);
                }
                triangulate(ring, rb, poly, ri);
            }
            o.node_offsets.push_back(int64_t(o.node_kind.size()));
            o.piece_offsets.push_back(int64_t(o.pieces.size()));
        }
        // Coarse vertices exactly at their original positions.
        for (size_t v = 0; v < o.coarse.vertices.size(); ++v) {
            if (o.coarse_vertex_origin[v] < 0) throw AlgorithmError("refine: refined vertex " + std::to_string(v) + " unused");
            o.coarse.vertices[v] = o.original.vertices[size_t(o.coarse_vertex_origin[v])];
        }
    }

    static std::string degenerate_message(size_t ri) {
        return "refine: cannot express the refined phi as a .bpm file: in refined triangle " + std::to_string(ri) +
               " a piece of phi and the refined triangle overlap in a sliver too thin for double precision (the "
               "input phi has a node within rounding distance of a refined edge); write a surface format instead";
    }

    // Ear clipping of a convex polygon whose boundary may hold collinear points: cut
    // only strictly convex ears whose removal leaves a polygon of positive area.
    void triangulate(std::vector<int32_t> ring, std::vector<Vec3> rb, const Polygon& poly, size_t ri) {
        Parametrization& o = out_;
        std::vector<int32_t> verts;
        for (const auto& x : poly.points) verts.push_back(x.vertex);
        auto o2 = [&](size_t a, size_t b, size_t c) {
            return orient2d(Vec2{rb[a][1], rb[a][2]}, Vec2{rb[b][1], rb[b][2]}, Vec2{rb[c][1], rb[c][2]});
        };
        auto emit = [&](size_t a, size_t b, size_t c) {
            o.pieces.push_back(Tri{ring[a], ring[b], ring[c]});
            o.piece_original_triangle.push_back(o.original.num_triangles());
            o.original.triangles.push_back(Tri{verts[a], verts[b], verts[c]});
            o.original.patches.push_back(p_.original.patches[size_t(poly.original_triangle)]);
        };
        while (ring.size() > 3) {
            const size_t n = ring.size();
            bool cut = false;
            for (size_t i = 0; i < n && !cut; ++i) {
                const size_t a = (i + n - 1) % n, c = (i + 1) % n;
                if (o2(a, i, c) <= 0) continue;
                // Is something left with positive area?
                bool flat = true;
                for (size_t k = 0; k < n && flat; ++k)
                    if (k != i && k != a && k != c && o2(a, c, k) != 0) flat = false;
                if (flat) continue;
                emit(a, i, c);
                ring.erase(ring.begin() + long(i));
                rb.erase(rb.begin() + long(i));
                verts.erase(verts.begin() + long(i));
                cut = true;
            }
            if (!cut) throw AlgorithmError(degenerate_message(ri));
        }
        if (o2(0, 1, 2) <= 0)
            throw AlgorithmError(degenerate_message(ri));
        emit(0, 1, 2);
    }

    const Parametrization& p_;
    const RefinedSurface& r_;
    Parametrization out_;
    std::map<Key, int32_t> vertices_;
    std::vector<int32_t> refined_vertex_;
    std::vector<std::vector<Polygon>> polys_;
};

}  // namespace

Parametrization refined_parametrization(const Parametrization& param, const RefinedSurface& refined,
                                        const Context& context) {
    Overlay overlay(param, refined);
    overlay.run(context);
    context.report(1.0, "overlay with phi");
    return overlay.take();
}

}  // namespace bpm
