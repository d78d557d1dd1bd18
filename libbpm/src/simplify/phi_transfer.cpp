#include "simplify/phi_transfer.h"

#include <algorithm>
#include <limits>

#include "bpm/predicates.h"

namespace bpm::detail {

namespace {
// The margin (barycentric, or a fraction of a segment) within which a node or a cut is
// too near a side or an end for double precision downstream.
constexpr double kMargin = 1e-9;
// An original triangle whose height is below this fraction of its longest edge (R/r above
// ~1e11) is a sliver (original_sliver). Wider than kMargin: a node's barycentric distance
// to a side of a new triangle is the sliver's thinness times the sliver's size over the
// new triangle's, so a sliver somewhat thicker than the margin still puts it within it.
constexpr double kSliverThinness = 1e-6;
}  // namespace

bool original_sliver(const Embedding& emb, int32_t u, int32_t w, int32_t c) {
    const int32_t e = emb.find_edge(u, w);
    if (e < 0 || c < 0) return false;
    const auto& x = emb.original->vertices;
    for (int32_t k = emb.edge_triangle_offsets[e]; k < emb.edge_triangle_offsets[e + 1]; ++k) {
        const Tri& t = emb.original->triangles[emb.edge_triangles[k]];
        if (t[0] != c && t[1] != c && t[2] != c) continue;
        const double longest2 = std::max({dot(x[u] - x[w], x[u] - x[w]), dot(x[w] - x[c], x[w] - x[c]), dot(x[c] - x[u], x[c] - x[u])});
        // |cross| = 2 area = height * longest edge.
        const double twice_area = norm(cross(x[w] - x[u], x[c] - x[u]));
        return twice_area < kSliverThinness * longest2;
    }
    return false;
}

bool locate_free_nodes(const Embedding& emb, const Fan& fan, const std::vector<Vec2>& q, const FanTriangulation& tri, bool check_inside,
                       StarGraph& graph, std::vector<std::array<double, 4>>& boxes, std::string& why) {
    const int32_t n = fan.corners();
    const int32_t ntris = static_cast<int32_t>(tri.triangles.size());
    // Bounding boxes of the new triangles (counter-clockwise, non-degenerate: ears of
    // a strictly convex polygon). A point strictly outside a box is strictly outside
    // that triangle, so the exact tests below would find a negative orientation.
    boxes.resize(ntris);
    for (int32_t t = 0; t < ntris; ++t) {
        const Vec2 &p0 = q[tri.triangles[t][0]], &p1 = q[tri.triangles[t][1]], &p2 = q[tri.triangles[t][2]];
        boxes[t] = {std::min({p0[0], p1[0], p2[0]}), std::min({p0[1], p1[1], p2[1]}),
                    std::max({p0[0], p1[0], p2[0]}), std::max({p0[1], p1[1], p2[1]})};
    }
    // Free nodes strictly inside the polygon (by construction before straightening, so
    // only the full plan checks), then located in the new triangulation.
    for (StarNode& s : graph.nodes) {
        if (!s.free) continue;
        for (int32_t i = 0; check_inside && i < n; ++i)
            if (orient2d(q[i], q[mod(i + 1, n)], s.pos) <= 0) {
                why = "an original vertex would leave the star";
                return false;
            }
        s.new_triangle = -1;
        s.diagonal = -1;
        for (int32_t t = 0; t < ntris && s.new_triangle < 0 && s.diagonal < 0; ++t) {
            const auto& c = tri.triangles[t];
            const auto& box = boxes[t];
            if (s.pos[0] < box[0] || s.pos[1] < box[1] || s.pos[0] > box[2] || s.pos[1] > box[3]) continue;
            int zero = -1, negative = 0;
            for (int k = 0; k < 3 && !negative; ++k) {
                const int o = orient2d(q[c[k]], q[c[(k + 1) % 3]], s.pos);
                if (o < 0) ++negative;
                if (o == 0) zero = zero < 0 ? k : 3;
            }
            if (negative) continue;
            if (zero < 0) {
                s.new_triangle = t;
            } else if (zero < 3) {
                const int32_t a = c[zero], b = c[(zero + 1) % 3];
                for (int32_t d = 0; d < int32_t(tri.diagonals.size()); ++d) {
                    const auto& dg = tri.diagonals[d];
                    if ((dg[0] == a && dg[1] == b) || (dg[0] == b && dg[1] == a)) {
                        s.diagonal = d;
                        const Vec2 p0 = q[dg[0]], dir = q[dg[1]] - q[dg[0]];
                        double t_along = dot(s.pos - p0, dir) / dot(dir, dir);
                        t_along = std::min(std::max(t_along, 1e-300), std::nextafter(1.0, 0.0));
                        const SurfacePoint on = SurfacePoint::on_edge(fan.link[dg[0]], fan.link[dg[1]], t_along);
                        s.edge_lo = on.a;
                        s.edge_hi = on.b;
                        s.edge_s = on.s;
                    }
                }
            }
        }
        if (s.new_triangle < 0 && s.diagonal < 0) {
            why = "cannot locate an original vertex in the new triangles";
            return false;
        }
        if (s.new_triangle >= 0) {
            const auto& c = tri.triangles[s.new_triangle];
            const Vec2 p0 = q[c[0]], p1 = q[c[1]], p2 = q[c[2]];
            const double area = cross(p1 - p0, p2 - p0);
            const double b1 = cross(s.pos - p0, p2 - p0) / area;
            const double b2 = cross(p1 - p0, s.pos - p0) / area;
            s.bary = {1.0 - b1 - b2, b1, b2};
            // Within rounding distance of a side, a node would make slivers too thin for
            // double precision downstream. Near a new edge (diagonal) it is put on it
            // (symmetric stars put v exactly there); near a link edge, or a corner, the
            // transfer is refused.
            int near = -1, count = 0;
            for (int k = 0; k < 3; ++k)
                if (!(s.bary[k] > kMargin)) {
                    near = k;
                    ++count;
                }
            if (count > 1) {
                why = "an original vertex would sit (almost) on a coarse vertex";
                return false;
            }
            if (count == 1) {
                const int32_t a = c[(near + 1) % 3], b = c[(near + 2) % 3];
                int32_t on = -1;
                for (int32_t d = 0; d < int32_t(tri.diagonals.size()); ++d)
                    if ((tri.diagonals[d][0] == a && tri.diagonals[d][1] == b) || (tri.diagonals[d][0] == b && tri.diagonals[d][1] == a))
                        on = d;
                // An original sliver on the link edge (the node is as near the side as
                // the original triangle it makes with it is thin): the node stays inside.
                if (on < 0 && s.bary[near] > 0.0 && original_sliver(emb, fan.link[a], fan.link[b], s.vertex)) continue;
                if (on < 0) {
                    why = "an original vertex would sit (almost) on a link edge";
                    return false;
                }
                const double ba = s.bary[(near + 1) % 3], bb = s.bary[(near + 2) % 3];
                double t_along = tri.diagonals[on][0] == a ? bb / (ba + bb) : ba / (ba + bb);
                if (!(t_along > kMargin && t_along < 1.0 - kMargin)) {
                    why = "an original vertex would sit (almost) on a coarse vertex";
                    return false;
                }
                s.new_triangle = -1;
                s.diagonal = on;
                const SurfacePoint p = SurfacePoint::on_edge(fan.link[tri.diagonals[on][0]], fan.link[tri.diagonals[on][1]], t_along);
                s.edge_lo = p.a;
                s.edge_hi = p.b;
                s.edge_s = p.s;
                // The straight-line position on the diagonal, for the cuts.
                s.pos = (1.0 - t_along) * q[tri.diagonals[on][0]] + t_along * q[tri.diagonals[on][1]];
            }
        }
    }

    return true;
}

bool cut_segments(const Embedding& emb, const Fan& fan, const std::vector<Vec2>& q, const FanTriangulation& tri, const StarGraph& graph,
                  RecutEdges& cuts, std::string& why) {
    const int32_t n = fan.corners();
    cuts.crossings.clear();
    cuts.cut_begin.clear();
    for (const StraightSegment& seg : graph.segments) {
        cuts.cut_begin.push_back(static_cast<int32_t>(cuts.crossings.size()));
        const Vec2 A = graph.nodes[seg.a].pos, B = graph.nodes[seg.b].pos;
        if (!(A[0] != B[0] || A[1] != B[1])) {
            why = "degenerate straightened edge";
            return false;
        }
        // Polygon corners on the segment would put a coarse vertex on an original edge.
        // A corner strictly outside the segment's bounding box cannot be: exactly on the
        // line AB but beyond an end, both factors of every term of the dot product
        // below have one sign (rounding keeps signs of differences), so it is >= 0.
        const double box_lo[2] = {std::min(A[0], B[0]), std::min(A[1], B[1])};
        const double box_hi[2] = {std::max(A[0], B[0]), std::max(A[1], B[1])};
        auto outside_box = [&](const Vec2& p) {
            return p[0] < box_lo[0] || p[0] > box_hi[0] || p[1] < box_lo[1] || p[1] > box_hi[1];
        };
        for (int32_t i = 0; i < n; ++i) {
            if (i == graph.nodes[seg.a].poly_corner || i == graph.nodes[seg.b].poly_corner) continue;
            if (outside_box(q[i])) continue;
            if (orient2d(A, B, q[i]) == 0 && dot(q[i] - A, q[i] - B) < 0) {
                why = "an original edge would pass through a coarse vertex";
                return false;
            }
        }
        const size_t first = cuts.crossings.size();
        for (int32_t d = 0; d < int32_t(tri.diagonals.size()); ++d) {
            // A segment that starts on a diagonal does not cut it (it leaves it).
            if ((graph.nodes[seg.a].free && graph.nodes[seg.a].diagonal == d) || (graph.nodes[seg.b].free && graph.nodes[seg.b].diagonal == d))
                continue;
            const Vec2 P = q[tri.diagonals[d][0]], Q = q[tri.diagonals[d][1]];
            // Segments whose bounding boxes are apart cannot cross properly (the exact
            // tests below would say so too).
            if (std::max(P[0], Q[0]) < box_lo[0] || std::min(P[0], Q[0]) > box_hi[0] ||
                std::max(P[1], Q[1]) < box_lo[1] || std::min(P[1], Q[1]) > box_hi[1])
                continue;
            const int oa = orient2d(P, Q, A), ob = orient2d(P, Q, B);
            if (oa == 0 || ob == 0 || oa == ob) continue;
            const int op = orient2d(A, B, P), oq = orient2d(A, B, Q);
            if (op == 0 || oq == 0 || op == oq) continue;
            const Vec2 r = B - A, s = Q - P;
            const double denom = cross(r, s);
            const double lambda = cross(P - A, s) / denom;  // along A->B
            double mu = cross(P - A, r) / denom;            // along P->Q
            // Cuts within rounding distance of an end of the segment or of the diagonal
            // would make pieces too thin for double precision downstream (evaluation,
            // refinement); such a transfer is refused, and the shape-preserving map gets a
            // chance to move the nodes away.
            // Exception, an input sliver (original_sliver): a cut near corner c of the
            // diagonal where the segment's original edge and c form an original sliver is as
            // near c as the sliver is thin. It must still be a point of the original edge
            // other than the segment's ends: near those (lambda) it stays refused, since for a
            // sliver at rounding level (1e-16) that made two nodes of phi one point of the
            // original edge (a snapped vertex in a cube face; bpm-check's bijectivity failed).
            const bool mu_ok = (mu > kMargin && mu < 1.0 - kMargin) ||
                               (mu > 0.0 && mu < 1.0 &&
                                original_sliver(emb, emb.edges[seg.edge][0], emb.edges[seg.edge][1],
                                                fan.link[tri.diagonals[d][mu < 0.5 ? 0 : 1]]));
            if (!(lambda > kMargin && lambda < 1.0 - kMargin) || !mu_ok) {
                why = "a cut of an original edge falls (almost) on a node";
                return false;
            }
            mu = std::min(std::max(mu, std::numeric_limits<double>::min()), std::nextafter(1.0, 0.0));
            const SurfacePoint on = SurfacePoint::on_edge(fan.link[tri.diagonals[d][0]], fan.link[tri.diagonals[d][1]], mu);
            cuts.crossings.push_back({d, on.a, on.b, on.s, seg.sigma_a + lambda * (seg.sigma_b - seg.sigma_a), seg.edge,
                                  lambda});
        }
        std::sort(cuts.crossings.begin() + static_cast<long>(first), cuts.crossings.end(),
                  [](const NewCrossing& p, const NewCrossing& q) { return p.lambda < q.lambda; });
        for (size_t i = first; i + 1 < cuts.crossings.size(); ++i)
            if (!(cuts.crossings[i].lambda < cuts.crossings[i + 1].lambda) ||
                cuts.crossings[i].sigma == cuts.crossings[i + 1].sigma) {
                why = "two cuts of an original edge coincide";
                return false;
            }
    }
    cuts.cut_begin.push_back(static_cast<int32_t>(cuts.crossings.size()));
    return true;
}

double transfer_deviation(const std::vector<Vec3>& x, const Embedding& emb, const Fan& fan,
                          const FanTriangulation& tri, const StarGraph& graph, const RecutEdges& cuts) {
    const int32_t n = fan.corners();
    // Deviation |phi(x) - x| is piecewise linear; its maximum is at the nodes. Nodes on
    // the link edges keep their place and their deviation, so only moved ones count.
    double max_deviation = 0.0;
    auto deviation_on_side = [&](const Vec3& image, int32_t lo, int32_t hi, double s) {
        return distance(image, (1.0 - s) * x[lo] + s * x[hi]);
    };
    auto image_of = [&](const StarNode& s) {
        return x[s.vertex];  // free nodes and new-edge nodes are original vertices
    };
    for (const StarNode& s : graph.nodes) {
        if (s.free && s.new_triangle >= 0) {
            const auto& c = tri.triangles[s.new_triangle];
            max_deviation = std::max(max_deviation, distance(image_of(s), barycentric_point(x[fan.link[c[0]]], x[fan.link[c[1]]],
                                                                                                x[fan.link[c[2]]], s.bary)));
        } else if ((s.free && s.diagonal >= 0) || (!fan.closed && s.poly_edge == n - 1)) {
            max_deviation = std::max(max_deviation, deviation_on_side(image_of(s), s.edge_lo, s.edge_hi, s.edge_s));
        }
    }
    const auto& ox = emb.original->vertices;
    for (const NewCrossing& c : cuts.crossings) {
        const auto& e = emb.edges[c.edge];
        const Vec3 image = (1.0 - c.sigma) * ox[e[0]] + c.sigma * ox[e[1]];
        max_deviation = std::max(max_deviation, deviation_on_side(image, c.lo, c.hi, c.s));
    }
    return max_deviation;
}

}  // namespace bpm::detail
