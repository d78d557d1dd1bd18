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
//
// Nodes within rounding distance of a refined vertex or edge. A node of phi that is
// meant to lie on a refined edge (an original vertex exactly on a midline of a regular
// mesh, an edge crossing at the midpoint of a coarse edge) is stored a few units in the
// last place off it; the exact predicates then see a polygon a few 1e-17 wide, whose
// corners cannot be told apart in double precision. Such nodes are first snapped, in a
// copy of the node positions used only here, onto the refined vertex (exact dyadic
// coordinates) or onto the refined edge (the point p + t (q - p) with t rounded to a
// multiple of 2^-40: the endpoints are dyadic fractions with at most 11 bits, so the
// result is exact and lies exactly on the edge). A snap moves a node by at most
// kSnapDistance in barycentric units, is applied to every copy of a node on a coarse
// edge alike, and is undone if any piece would lose its positive orientation. After
// that, "on the edge" is again an exact decision.

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include "bpm/errors.h"
#include "bpm/predicates.h"
#include "bpm/refine.h"
#include "core/barycentric_orientation.h"
#include "core/convex_ear_clipping.h"
#include "phi/phi_triangle_data.h"

namespace bpm {

namespace {

using detail::orient_barycentric;

inline double area2(const Vec3& p, const Vec3& q, const Vec3& x) {  // in the (b1, b2) plane
    return (q[1] - p[1]) * (x[2] - p[2]) - (q[2] - p[2]) * (x[1] - p[1]);
}

// A vertex of the new original surface, by what it is: {0, v} an original vertex,
// {1, u, w, bits of s} an edge crossing of phi, {2, v} a refined vertex off S0,
// {3, a, b, ra, rb} where the piece edge (a, b) crosses the refined edge (ra, rb).
using Key = std::array<int64_t, 5>;

// Largest distance, in barycentric units of the coarse triangle, over which a node is
// snapped onto a refined vertex or edge. Well above the rounding of stored node
// positions (~1e-16), far below anything geometric.
constexpr double kSnapDistance = 1e-12;

// Distance in the (b1, b2) plane from x to the segment (p, q), and the parameter of the
// closest point.
double segment_distance(const Vec3& p, const Vec3& q, const Vec3& x, double& t) {
    const double d1 = q[1] - p[1], d2 = q[2] - p[2];
    const double len2 = d1 * d1 + d2 * d2;
    t = len2 > 0 ? ((x[1] - p[1]) * d1 + (x[2] - p[2]) * d2) / len2 : 0.0;
    t = std::min(1.0, std::max(0.0, t));
    const double e1 = x[1] - (p[1] + t * d1), e2 = x[2] - (p[2] + t * d2);
    return std::sqrt(e1 * e1 + e2 * e2);
}

// p + t (q - p) with t rounded to a multiple of 2^-40: exact for dyadic p, q with few
// bits (refined vertices), so the result lies exactly on the line through p and q and
// its coordinates sum to exactly 1.
Vec3 point_on_segment(const Vec3& p, const Vec3& q, double t) {
    const double scale = 1099511627776.0;  // 2^40
    t = std::round(t * scale) / scale;
    return {p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]), p[2] + t * (q[2] - p[2])};
}

struct OverlayPoint {
    Vec3 b;           // barycentric in the coarse triangle
    Vec3 image;       // phi(b)
    int32_t vertex;   // vertex of the new original surface
    int corner = -1;  // corner of the refined triangle, or -1
    bool crossing = false;  // where a piece edge crosses a refined edge
    int on_edge[3] = {0, 0, 0};  // on local edge k of the refined triangle
    int strict[3] = {0, 0, 0};   // strictly inside with respect to local edge k (exact decision)
};

// Builds phi' (see the file comment): the overlay of phi's pieces with the refined
// triangles, per coarse triangle, assembled into a new Parametrization.
class RefinedParametrizationBuilder {
public:
    RefinedParametrizationBuilder(const Parametrization& p, const RefinedSurface& r) : p_(p), r_(r) {
        out_.original.vertices = p.original.vertices;
        refined_vertex_.assign(r.surface.vertices.size(), -1);
        by_coarse_.resize(size_t(p.coarse.num_triangles()));
        for (size_t i = 0; i < r.triangle_coarse.size(); ++i) by_coarse_[size_t(r.triangle_coarse[i])].push_back(int32_t(i));
        nb_ = p.node_barycentric;
    }

    // See the file comment. Returns the number of nodes snapped (each copy counted).
    int64_t snap_nodes() {
        const int32_t nct = p_.coarse.num_triangles();
        // Proposals: node -> target position. Copies of a node on a coarse edge share a key.
        std::vector<char> has_target(nb_.size(), 0);
        std::vector<Vec3> target(nb_.size());
        std::map<Key, std::vector<int64_t>> copies;  // key of a node on a coarse edge -> its copies
        std::map<Key, int> proposals;                // how many copies found a target
        for (int32_t t = 0; t < nct; ++t) {
            const int64_t n0 = p_.node_offsets[size_t(t)], n1 = p_.node_offsets[size_t(t) + 1];
            for (int32_t ri : by_coarse_[size_t(t)]) {
                const auto& R = r_.triangle_barycentric[size_t(ri)];
                const double lo1 = std::min({R[0][1], R[1][1], R[2][1]}) - kSnapDistance;
                const double hi1 = std::max({R[0][1], R[1][1], R[2][1]}) + kSnapDistance;
                const double lo2 = std::min({R[0][2], R[1][2], R[2][2]}) - kSnapDistance;
                const double hi2 = std::max({R[0][2], R[1][2], R[2][2]}) + kSnapDistance;
                for (int64_t g = n0; g < n1; ++g) {
                    if (p_.node_kind[size_t(g)] == NodeKind::CoarseCorner || has_target[size_t(g)]) continue;
                    const Vec3& b = p_.node_barycentric[size_t(g)];
                    if (b[1] < lo1 || b[1] > hi1 || b[2] < lo2 || b[2] > hi2) continue;
                    const bool interior = b[0] > 0 && b[1] > 0 && b[2] > 0;
                    // A refined corner within reach: snap onto it (unless it is that point already).
                    for (int k = 0; k < 3 && !has_target[size_t(g)]; ++k) {
                        // (A copy already exactly at the corner counts as snapped: its copies in
                        // other coarse triangles may be a rounding error away from it.)
                        const Vec3& c = R[size_t(k)];
                        double dummy;
                        if (segment_distance(c, c, b, dummy) > kSnapDistance) continue;
                        // A node must stay where it is combinatorially: inside, or on its coarse edge.
                        const bool c_interior = c[0] > 0 && c[1] > 0 && c[2] > 0;
                        bool same_edge = true;
                        for (int j = 0; j < 3; ++j)
                            if (b[size_t(j)] == 0 && c[size_t(j)] != 0) same_edge = false;
                        if (interior != c_interior || !same_edge) continue;
                        has_target[size_t(g)] = 1;
                        target[size_t(g)] = c;
                    }
                    if (has_target[size_t(g)] || !interior) continue;
                    // An interior node within reach of a refined edge (not a coarse edge).
                    for (int k = 0; k < 3 && !has_target[size_t(g)]; ++k) {
                        const Vec3& a = R[size_t(k)];
                        const Vec3& c = R[size_t((k + 1) % 3)];
                        if (orient_barycentric(a, c, b) == 0) continue;
                        double tt;
                        if (segment_distance(a, c, b, tt) > kSnapDistance) continue;
                        const Vec3 x = point_on_segment(a, c, tt);
                        if (!(x[0] > 0 && x[1] > 0 && x[2] > 0) || x == a || x == c) continue;
                        has_target[size_t(g)] = 1;
                        target[size_t(g)] = x;
                    }
                }
            }
            for (int64_t g = n0; g < n1; ++g) {
                const Vec3& b = p_.node_barycentric[size_t(g)];
                if (p_.node_kind[size_t(g)] == NodeKind::CoarseCorner || (b[0] > 0 && b[1] > 0 && b[2] > 0)) continue;
                const Key key = node_key(g);
                copies[key].push_back(g);
                if (has_target[size_t(g)]) ++proposals[key];
            }
        }
        // Copies on coarse edges move only together: all of them or none.
        for (const auto& [key, list] : copies) {
            auto it = proposals.find(key);
            if (it == proposals.end()) continue;
            if (size_t(it->second) != list.size())
                for (int64_t g : list) has_target[size_t(g)] = 0;
        }
        std::vector<Vec3> snapped = nb_;
        for (size_t g = 0; g < nb_.size(); ++g)
            if (has_target[g]) snapped[g] = target[g];
        // Undo snaps that would flip or flatten a piece (with all other snaps applied),
        // until every piece is positively oriented again.
        for (bool again = true; again;) {
            again = false;
            for (int32_t t = 0; t < nct; ++t) {
                const int64_t n0 = p_.node_offsets[size_t(t)];
                for (int64_t q = p_.piece_offsets[size_t(t)]; q < p_.piece_offsets[size_t(t) + 1]; ++q) {
                    const Tri& pc = p_.pieces[size_t(q)];
                    const size_t a = size_t(n0 + pc[0]), b = size_t(n0 + pc[1]), c = size_t(n0 + pc[2]);
                    if (!has_target[a] && !has_target[b] && !has_target[c]) continue;
                    if (orient_barycentric(snapped[a], snapped[b], snapped[c]) > 0) continue;
                    for (size_t g : {a, b, c}) {
                        if (!has_target[g]) continue;
                        const Vec3& x = p_.node_barycentric[g];
                        if (x[0] > 0 && x[1] > 0 && x[2] > 0) {
                            has_target[g] = 0;
                            snapped[g] = nb_[g];
                        } else {
                            for (int64_t h : copies[node_key(int64_t(g))]) {
                                has_target[size_t(h)] = 0;
                                snapped[size_t(h)] = nb_[size_t(h)];
                            }
                        }
                    }
                    again = true;
                }
            }
        }
        int64_t count = 0;
        for (size_t g = 0; g < nb_.size(); ++g) count += has_target[g];
        nb_ = std::move(snapped);
        return count;
    }

    int32_t vertex_for(const Key& key, const Vec3& x) {
        auto it = vertices_.find(key);
        if (it != vertices_.end()) return it->second;
        const int32_t id = int32_t(out_.original.vertices.size());
        out_.original.vertices.push_back(x);
        vertices_.emplace(key, id);
        return id;
    }

    // What node g of phi is, the same for all its copies in the coarse triangles that
    // share it: {0, v} for an original vertex, {1, u, w, bits of s} for an edge crossing.
    Key node_key(int64_t g) const {
        const size_t i = size_t(g);
        if (p_.node_kind[i] != NodeKind::EdgeCrossing) return {0, p_.node_original_vertex[i], 0, 0, 0};
        int64_t bits;
        const double s = p_.node_edge_parameter[i];
        std::memcpy(&bits, &s, sizeof bits);
        return {1, p_.node_original_edge[i][0], p_.node_original_edge[i][1], bits, 0};
    }

    int32_t node_vertex(int64_t g) {
        const size_t i = size_t(g);
        if (p_.node_kind[i] != NodeKind::EdgeCrossing) return p_.node_original_vertex[i];
        return vertex_for(node_key(g), p_.node_image[i]);
    }

    void run(const Context& context) {
        const int32_t nct = p_.coarse.num_triangles();
        const int64_t snapped = snap_nodes();
        if (snapped > 0)
            context.debug("refine: " + std::to_string(snapped) +
                          " nodes of phi within rounding distance of a refined vertex or edge snapped onto it");
        const auto& by_coarse = by_coarse_;
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
            if (nb_[size_t(g)] == b) id = nv[size_t(g - n0)];
        // A vertex held back from phi (RefineOptions::prevent_intersections) is off S0: it
        // becomes a vertex of the new original surface at its own position, and the overlay
        // cells around it follow it (spec/refinement.md §3). It cannot be an original vertex
        // of S0 at the same time.
        const bool held_back = size_t(rv) < r_.vertex_phi_fraction.size() && r_.vertex_phi_fraction[size_t(rv)] < 1.0;
        if (id >= 0 && held_back)
            throw AlgorithmError("refine: refined vertex " + std::to_string(rv) +
                                 " is held back from phi to avoid a self-intersection but is an original vertex "
                                 "of S0 as well; it cannot be written as a .bpm file (write a surface format)");
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
                N[k] = nb_[size_t(n0 + pc[size_t(k)])];
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
                for (int j = 0; j < 3; ++j) o[j] = orient_barycentric(R[size_t(j)], R[size_t((j + 1) % 3)], N[k]);
                if (o[0] < 0 || o[1] < 0 || o[2] < 0) continue;
                OverlayPoint x{N[k], I[k], id[k]};
                for (int j = 0; j < 3; ++j) x.on_edge[j] = o[j] == 0, x.strict[j] = o[j] > 0;
                pts.push_back(x);
            }
            // Side of refined corner j of piece edge k: exact, except that a corner within
            // rounding distance of the edge (an original edge through a refined vertex of a
            // regular mesh) is on it. Decided the same way from both pieces of the edge.
            const auto corner_side = [&](int k, int j) {
                const int k1 = (k + 1) % 3;
                const int o = orient_barycentric(N[k], N[k1], R[size_t(j)]);
                if (o == 0) return 0;
                const int ka = id[k] < id[k1] ? k : k1, kb = ka == k ? k1 : k;
                double t;
                return segment_distance(N[ka], N[kb], R[size_t(j)], t) <= kSnapDistance && t > 0 && t < 1 ? 0 : o;
            };
            // Refined corners inside or on the piece (unless they are one of its nodes).
            for (int j = 0; j < 3; ++j) {
                if (rc[j] == id[0] || rc[j] == id[1] || rc[j] == id[2]) continue;
                int o[3];
                for (int k = 0; k < 3; ++k) o[k] = corner_side(k, j);
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
                    const int a1 = orient_barycentric(R[size_t(j)], R[size_t(j1)], N[k]);
                    const int a2 = orient_barycentric(R[size_t(j)], R[size_t(j1)], N[k1]);
                    if (a1 * a2 >= 0) continue;
                    const int c1 = corner_side(k, j);
                    const int c2 = corner_side(k, j1);
                    if (c1 * c2 >= 0) continue;
                    // Parameter along the piece edge in a canonical direction (lower vertex id
                    // first), against the refined edge in a canonical direction too (lower
                    // refined vertex first): the two refined triangles of an edge compute the
                    // crossing bit for bit the same. (With the edge's own order, a piece edge
                    // almost parallel to it got positions 7e-11 apart on the two sides: two
                    // cubes at 5 %, bijectivity check failed.)
                    const int ka = id[k] < id[k1] ? k : k1, kb = ka == k ? k1 : k;
                    const int ja = rt[size_t(j)] < rt[size_t(j1)] ? j : j1, jb = ja == j ? j1 : j;
                    const double d1 = area2(R[size_t(ja)], R[size_t(jb)], N[ka]);
                    const double d2 = area2(R[size_t(ja)], R[size_t(jb)], N[kb]);
                    double s = d1 / (d1 - d2);
                    s = std::min(1.0, std::max(0.0, s));
                    const Vec3 b = N[ka] + s * (N[kb] - N[ka]);
                    const Vec3 image = I[ka] + s * (I[kb] - I[ka]);
                    const int32_t ra = std::min(rt[size_t(j)], rt[size_t(j1)]);
                    const int32_t rb = std::max(rt[size_t(j)], rt[size_t(j1)]);
                    OverlayPoint x{b, image, vertex_for({3, id[ka], id[kb], ra, rb}, image)};
                    x.on_edge[j] = 1;
                    x.strict[j1] = x.strict[(j + 2) % 3] = 1;
                    x.crossing = true;
                    pts.push_back(x);
                }
            }
            // Two piece edges meeting at a small angle near a refined edge cross it a few
            // 1e-17 apart: the sliver between them cannot be represented. Such crossings
            // become one vertex (everywhere, through the union-find), the sliver vanishes.
            for (size_t a = 0; a < pts.size(); ++a)
                for (size_t c = a + 1; c < pts.size(); ++c) {
                    if (!pts[a].crossing || !pts[c].crossing || pts[a].vertex == pts[c].vertex) continue;
                    bool same_edge = false;
                    for (int j = 0; j < 3; ++j) same_edge |= pts[a].on_edge[j] && pts[c].on_edge[j];
                    const Vec3 d = pts[a].b - pts[c].b;
                    if (same_edge && std::max({std::abs(d[0]), std::abs(d[1]), std::abs(d[2])}) <= kSnapDistance)
                        unite(pts[a].vertex, pts[c].vertex);
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

    int32_t find(int32_t v) {
        if (size_t(v) >= parent_.size()) return v;
        while (parent_[size_t(v)] != v) v = parent_[size_t(v)] = parent_[size_t(parent_[size_t(v)])];
        return v;
    }

    void unite(int32_t a, int32_t b) {
        const size_t need = size_t(std::max(a, b)) + 1;
        for (size_t i = parent_.size(); i < need; ++i) parent_.push_back(int32_t(i));
        a = find(a), b = find(b);
        if (a != b) parent_[size_t(std::max(a, b))] = std::min(a, b);  // the smaller id represents
    }

    // Applies the merges of close crossings to every polygon: vertex ids by their
    // representative, repeated points removed, polygons that collapsed dropped.
    void merge_close_crossings() {
        if (parent_.empty()) return;
        for (auto& list : polys_) {
            std::vector<Polygon> kept;
            for (Polygon& poly : list) {
                std::vector<OverlayPoint> pts;
                for (OverlayPoint x : poly.points) {
                    x.vertex = find(x.vertex);
                    if (pts.empty() || pts.back().vertex != x.vertex) pts.push_back(x);
                }
                while (pts.size() > 1 && pts.front().vertex == pts.back().vertex) pts.pop_back();
                if (pts.size() < 3) continue;
                double area = 0;
                for (size_t i = 0; i < pts.size(); ++i) area += area2(pts[0].b, pts[i].b, pts[(i + 1) % pts.size()].b);
                if (!(area > 0)) continue;
                poly.points = std::move(pts);
                kept.push_back(std::move(poly));
            }
            list = std::move(kept);
        }
    }

    // Drops vertices of the new original surface that no triangle uses (merged
    // crossings), keeping the order of the others (those of S0 come first, unchanged).
    void compact_original() {
        Parametrization& o = out_;
        std::vector<int32_t> index(o.original.vertices.size(), -1);
        for (const Tri& t : o.original.triangles)
            for (int32_t v : t) index[size_t(v)] = 0;
        for (size_t v = 0; v < p_.original.vertices.size(); ++v) index[v] = 0;  // S0 keeps its indices
        int32_t next = 0;
        std::vector<Vec3> vertices;
        for (size_t v = 0; v < index.size(); ++v)
            if (index[v] == 0) index[v] = next++, vertices.push_back(o.original.vertices[v]);
        if (size_t(next) == index.size()) return;
        o.original.vertices = std::move(vertices);
        for (Tri& t : o.original.triangles)
            for (int32_t& v : t) v = index[size_t(v)];
        for (int32_t& v : o.node_original_vertex) v = index[size_t(v)];
        for (int32_t& v : o.coarse_vertex_origin) v = index[size_t(v)];
    }

    void assemble() {
        merge_close_crossings();
        const size_t nrt = polys_.size();
        Parametrization& o = out_;
        o.coarse = r_.surface;
        o.coarse_vertex_origin.assign(r_.surface.vertices.size(), -1);
        detail::clear_phi(o);
        const double nan = std::numeric_limits<double>::quiet_NaN();
        for (size_t ri = 0; ri < nrt; ++ri) {
            const Tri& rt = r_.surface.triangles[ri];
            const auto& R = r_.triangle_barycentric[ri];
            detail::PhiTriangleData phi;  // of refined triangle ri
            std::map<int32_t, int32_t> local;
            auto add_node = [&](const OverlayPoint& x, NodeKind kind) {
                auto it = local.find(x.vertex);
                if (it != local.end()) return it->second;
                const int32_t l = phi.add_node(to_refined(R, x), o.original.vertices[size_t(x.vertex)], kind, x.vertex,
                                               {-1, -1}, nan);
                local.emplace(x.vertex, l);
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
                    rb.push_back(phi.barycentric[size_t(ring.back())]);
                }
                triangulate(ring, rb, poly, ri, phi);
            }
            detail::append_phi_triangle(o, phi);
        }
        for (size_t v = 0; v < o.coarse.vertices.size(); ++v)
            if (o.coarse_vertex_origin[v] < 0) throw AlgorithmError("refine: refined vertex " + std::to_string(v) + " unused");
        compact_original();
        carry_vertex_data();
        // Coarse vertices exactly at their original positions.
        for (size_t v = 0; v < o.coarse.vertices.size(); ++v)
            o.coarse.vertices[v] = o.original.vertices[size_t(o.coarse_vertex_origin[v])];
    }

    // The new original surface is S0 cut into smaller triangles: its vertices of S0 keep
    // their data, every new one (on an edge or inside a triangle of S0) gets the data
    // interpolated linearly in the S0 triangle it lies in, like phi itself.
    void carry_vertex_data() {
        Parametrization& o = out_;
        if (p_.original.vertex_data.empty()) return;
        const size_t nv0 = p_.original.vertices.size(), nv = o.original.vertices.size();
        std::vector<int32_t> host(nv, -1);  // S0 triangle holding each new vertex
        for (size_t t = 0; t < o.original.triangles.size(); ++t)
            for (int32_t v : o.original.triangles[t])
                if (size_t(v) >= nv0 && host[size_t(v)] < 0) host[size_t(v)] = parent_triangle_[t];
        o.original.vertex_data.clear();
        for (const VertexArray& a : p_.original.vertex_data) {
            const size_t k = size_t(a.components);
            VertexArray b{a.name, a.components, std::vector<double>(nv * k, 0.0)};
            std::copy(a.values.begin(), a.values.end(), b.values.begin());
            for (size_t v = nv0; v < nv; ++v) {
                if (host[v] < 0) continue;  // unused: compact_original() dropped all of those
                const Tri& t = p_.original.triangles[size_t(host[v])];
                const auto& x = p_.original.vertices;
                const Vec3 w = barycentric_of(x[size_t(t[0])], x[size_t(t[1])], x[size_t(t[2])], o.original.vertices[v]);
                for (int c = 0; c < 3; ++c)
                    for (size_t j = 0; j < k; ++j) b.values[v * k + j] += w[size_t(c)] * a.values[size_t(t[size_t(c)]) * k + j];
            }
            o.original.vertex_data.push_back(std::move(b));
        }
    }
    // Barycentric coordinates of p (on or within rounding distance of triangle abc)
    // by least squares in the triangle's plane, clamped to the triangle.
    static Vec3 barycentric_of(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
        const Vec3 e0 = b - a, e1 = c - a, d = p - a;
        const double d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1), d20 = dot(d, e0), d21 = dot(d, e1);
        const double det = d00 * d11 - d01 * d01;
        if (!(det > 0)) return {1.0, 0.0, 0.0};
        double v = (d11 * d20 - d01 * d21) / det, w = (d00 * d21 - d01 * d20) / det;
        v = std::clamp(v, 0.0, 1.0);
        w = std::clamp(w, 0.0, 1.0);
        if (v + w > 1.0) {
            const double sum = v + w;
            v /= sum, w /= sum;
        }
        return {1.0 - v - w, v, w};
    }

    static std::string degenerate_message(size_t ri) {
        return "refine: cannot express the refined phi as a .bpm file: in refined triangle " + std::to_string(ri) +
               " a piece of phi and the refined triangle overlap in a sliver too thin for double precision (the "
               "input phi has a node within rounding distance of a refined edge); write a surface format instead";
    }

    // Ear clipping of the convex overlay polygon (core/convex_ear_clipping.h); its
    // boundary may hold collinear points.
    // The pieces go to `phi`, the new original triangles (one per piece) to the output.
    void triangulate(const std::vector<int32_t>& ring, const std::vector<Vec3>& rb, const Polygon& poly, size_t ri,
                     detail::PhiTriangleData& phi) {
        Parametrization& o = out_;
        std::vector<int32_t> verts;
        for (const auto& x : poly.points) verts.push_back(x.vertex);
        auto o2 = [&](int a, int b, int c) {
            return orient2d(Vec2{rb[size_t(a)][1], rb[size_t(a)][2]}, Vec2{rb[size_t(b)][1], rb[size_t(b)][2]},
                            Vec2{rb[size_t(c)][1], rb[size_t(c)][2]});
        };
        auto emit = [&](int a, int b, int c) {
            phi.add_piece(Tri{ring[size_t(a)], ring[size_t(b)], ring[size_t(c)]}, o.original.num_triangles());
            o.original.triangles.push_back(Tri{verts[size_t(a)], verts[size_t(b)], verts[size_t(c)]});
            o.original.patches.push_back(p_.original.patches[size_t(poly.original_triangle)]);
            parent_triangle_.push_back(poly.original_triangle);
            return true;
        };
        std::vector<int> corners(ring.size());
        for (size_t i = 0; i < corners.size(); ++i) corners[i] = int(i);
        if (!detail::clip_convex_ears(corners, o2, emit) || o2(corners[0], corners[1], corners[2]) <= 0)
            throw AlgorithmError(degenerate_message(ri));
        emit(corners[0], corners[1], corners[2]);
    }

    const Parametrization& p_;
    const RefinedSurface& r_;
    Parametrization out_;
    std::map<Key, int32_t> vertices_;
    std::vector<int32_t> refined_vertex_;
    std::vector<std::vector<Polygon>> polys_;
    std::vector<std::vector<int32_t>> by_coarse_;  // refined triangles per coarse triangle
    std::vector<Vec3> nb_;  // node barycentrics, snapped onto refined vertices and edges
    std::vector<int32_t> parent_triangle_;  // S0 triangle of every new original triangle
    std::vector<int32_t> parent_;  // union-find over vertex ids: crossings merged because they are too close
};

}  // namespace

Parametrization refined_parametrization(const Parametrization& param, const RefinedSurface& refined,
                                        const Context& context) {
    RefinedParametrizationBuilder builder(param, refined);
    builder.run(context);
    context.report(1.0, "overlay with phi");
    return builder.take();
}

}  // namespace bpm
