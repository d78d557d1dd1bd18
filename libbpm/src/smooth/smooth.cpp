// Parametrization smoothing by edge relaxation (Krause & Sander §2.5).
//
// For a pair of coarse triangles A, B sharing edge E = (p, q):
//  1. Unfold A ∪ B isometrically into the plane (p at the origin, q on the x axis, A
//     above); if a corner at p or q is reflex, move it along the continuation of E until
//     the quadrangle is convex. Parameter points map to this "domain" affinely per
//     triangle through their barycentric coordinates.
//  2. The graph: for every original triangle T that phi maps pieces of A ∪ B into, its
//     region T ∩ phi(A ∪ B) is a convex polygon whose corners are the vertices of T inside
//     the quadrangle and the edge crossings on the four outer edges (crossings on E are
//     dropped: the original edges become straight). Its corners are ordered in T's own
//     barycentric plane. Nodes on the outer edges are fixed; the original vertices inside
//     A, inside B or on E are free.
//  3. Free vertices are placed by mean value coordinates (Floater 2003) computed from the
//     3D star in S0: the weight of a neighbour along original edge (v, u) is
//     (tan(a1/2) + tan(a2/2)) / |y - x_v|, a1, a2 the angles of the triangles at v beside
//     that edge. Positive weights and a convex boundary make every region convex again
//     (Tutte, Floater). One sparse LU solve (Eigen) per pair.
//  4. Each region is cut by the line E (new EdgeCrossing nodes where an original edge
//     crosses it; region edges are original edges or lie on outer coarse edges, so every
//     crossing is on an original edge) and each side is triangulated by ear clipping in
//     T's barycentric plane: new pieces of A and B.
//  5. The update is kept only if every free vertex is strictly inside the quadrangle,
//     every region stays strictly convex and every new piece is positively oriented both
//     in its coarse triangle and in T (exact predicates); otherwise the pair is left as it
//     was. Node images never change, so phi(S) stays S0 exactly.

#include "bpm/smooth.h"

#include <Eigen/Sparse>
#include <Eigen/SparseLU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <unordered_map>
#include <unordered_set>

#include "bpm/errors.h"
#include "bpm/predicates.h"
#include "bpm/refine.h"
#include "core/barycentric_orientation.h"
#include "core/convex_ear_clipping.h"
#include "core/crease.h"
#include "core/crease_chains.h"
#include "core/edge_key.h"
#include "core/number_text.h"
#include "phi/phi_layout.h"
#include "phi/phi_triangle_data.h"

namespace bpm {

namespace {

using detail::PhiTriangleData;
using detail::orient_barycentric;

double tri_area_b(const Vec3& a, const Vec3& b, const Vec3& c) {  // signed, (b1, b2) plane
    return 0.5 * ((b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]));
}

// Smallest barycentric distance of a moved node from a coarse edge or another node on E.
constexpr double kMinGap = 1e-10;
// A reflex corner of the unfolded quadrangle moves along E until it is this fraction of
// |E| past the line through the two other corners (small: moving it distorts the chart).
// 0.01 measured best on fandisk / femur / elephant among 0.25, 0.05, 0.01.
constexpr double kReflexMargin = 0.01;
// Closest a smoothing update may bring a node to a corner of its coarse triangle
// (barycentric units; see "No collapse into a corner" in relax()).
constexpr double kCornerGap = 1e-2;

using NodeId = std::array<int64_t, 3>;  // {-1, v, 0} for a vertex, {u, w, bits(s)} for a crossing

NodeId node_id(const PhiTriangleData& t, size_t i) {
    if (t.kind[i] != NodeKind::EdgeCrossing) return {-1, t.original_vertex[i], 0};
    int64_t bits;
    std::memcpy(&bits, &t.edge_parameter[i], sizeof bits);
    return {t.original_edge[i][0], t.original_edge[i][1], bits};
}

struct QNode {
    NodeId id;
    NodeKind kind;
    int32_t ov;
    std::array<int32_t, 2> edge;
    double s;
    Vec3 image;
    bool fixed = false;
    bool has_old[2] = {false, false};
    Vec3 old_b[2];   // old barycentrics in A (0) and B (1)
    Vec2 pos;        // domain position (new for free nodes after the solve)
    Vec2 old_pos;
    int side = 0;    // orientation against E: +1 in A, -1 in B, 0 on E
    double mu = -1;  // position along E from p to q, for nodes on E that are not corners
    bool on_e = false;  // free vertex snapped onto E
    bool prescribed = false;  // a vertex on a feature line E, moved along it by arc length
};

// One triangle of the star of a free vertex v: its neighbours a and c (QNode indices)
// in counter-clockwise order, the angle at v in S0, and the 3D distances from v.
struct StarWedge {
    int a, c;
    double angle, len_a, len_c;
};

// The weights of the convex combination that places a free vertex among its neighbours
// (sum 1, all >= 0), from its star in S0 (one wedge per original triangle):
// - MeanValue: Floater 2003, w_j ~ (tan(a_{j-1}/2) + tan(a_j/2)) / |x_j - x_v|. Exact
//   for planar stars, but an angle near 180 degrees (slivers of S0) makes tan(a/2)
//   explode and can pull a vertex onto a neighbour by orders of magnitude.
// - ShapePreserving: Floater 1997 (the paper's reference [19]): the star is flattened
//   by the geodesic polar map (lengths kept, angles scaled to sum 2 pi); for every
//   neighbour q_k the line from q_k through the centre leaves the flattened star through
//   an edge (q_r, q_r+1), and the barycentric coordinates of the centre in the triangle
//   (q_k, q_r, q_r+1) are added to the weights of those three; the sum is divided by the
//   degree. Every weight is at most 1. Where the centre is not strictly inside such a
//   triangle (a flattened angle of pi or more) the vertex gets mean value weights.
// false if the wedges do not form one closed fan or a wedge is degenerate.
bool star_weights(const std::vector<StarWedge>& wedges, SmoothWeights mode, std::vector<std::pair<int, double>>& out) {
    out.clear();
    const size_t d = wedges.size();
    if (d < 3) return false;
    // Order the wedges around v: wedge k ends at the neighbour where wedge k+1 starts.
    std::map<int, size_t> starting;
    for (size_t k = 0; k < d; ++k)
        if (!starting.emplace(wedges[k].a, k).second) return false;
    std::vector<size_t> order;
    size_t k = 0;
    for (size_t step = 0; step < d; ++step) {
        order.push_back(k);
        auto it = starting.find(wedges[k].c);
        if (it == starting.end()) return false;
        k = it->second;
    }
    if (k != order.front()) return false;
    std::vector<int> ring(d);
    std::vector<double> len(d), angle(d);
    for (size_t i = 0; i < d; ++i) {
        const StarWedge& w = wedges[order[i]];
        ring[i] = w.a, len[i] = w.len_a, angle[i] = w.angle;  // angle between ring[i] and ring[i+1]
        if (!(w.len_a > 0) || !(w.len_c > 0) || !(w.angle > 0) || !(w.angle < M_PI)) return false;
    }
    std::vector<double> weight(d, 0.0);
    bool mean_value = mode == SmoothWeights::MeanValue;
    if (!mean_value) {
        double total = 0;
        for (double a : angle) total += a;
        std::vector<Vec2> q(d);
        double phi = 0;
        for (size_t i = 0; i < d; ++i) {
            q[i] = {len[i] * std::cos(phi), len[i] * std::sin(phi)};
            const double scaled = angle[i] * 2 * M_PI / total;
            if (scaled >= M_PI) mean_value = true;
            phi += scaled;
        }
        for (size_t i = 0; i < d && !mean_value; ++i) {
            bool found = false;
            for (size_t r = 0; r < d && !found; ++r) {
                const size_t r1 = (r + 1) % d;
                if (r == i || r1 == i) continue;
                const Vec2 a = q[i], b = q[r], c = q[r1];
                const double area = cross(b - a, c - a);
                if (!(area > 0)) continue;
                const double la = cross(b, c) / area, lb = cross(c, a) / area, lc = cross(a, b) / area;
                if (la < 0 || lb < 0 || lc < 0) continue;
                weight[i] += la, weight[r] += lb, weight[r1] += lc;
                found = true;
            }
            if (!found) mean_value = true;
        }
    }
    if (mean_value) {
        std::fill(weight.begin(), weight.end(), 0.0);
        for (size_t i = 0; i < d; ++i) {
            const double t = std::tan(angle[i] / 2);  // wedge between ring[i] and ring[i+1]
            weight[i] += t / len[i];
            weight[(i + 1) % d] += t / len[(i + 1) % d];
        }
    }
    double sum = 0;
    for (double x : weight) sum += x;
    if (!(sum > 0) || !std::isfinite(sum)) return false;
    for (size_t i = 0; i < d; ++i)
        if (weight[i] > 0) out.emplace_back(ring[i], weight[i] / sum);
    return true;
}

// What the K-times refined surface looks like over one coarse triangle with this phi
// (the refinement of bpm/refine.h: the regular grid of 4^K sub-triangles in barycentric
// coordinates, every grid point placed on S0 through phi). Used to accept a smoothing
// update only if it makes no coarse triangle worse (see relax()).
// - max_aspect: the largest aspect ratio of the refined triangles;
// - max_error: the largest |flat - phi|, flat being the refined surface (linear over
//   each sub-triangle). Both are affine over each cell of the overlay of the pieces of
//   phi with the sub-triangles, so the maximum lies at an overlay vertex: a node, a grid
//   point (where it is 0) or a crossing of a piece edge with a grid line (bpm-refine's
//   max |flat - phi| for this triangle, up to rounding; its proven bound can be lower on
//   planar regions, see refine.cpp PLANAR REGIONS).
struct TriangleQuality {
    double max_aspect = 0;
    double max_error = 0;
};

// phi at barycentric point b of the coarse triangle: the piece that holds b (the largest
// smallest coordinate, so points on piece edges find one), affine over it.
Vec3 phi_at(const PhiTriangleData& t, const Vec3& b) {
    double best = -std::numeric_limits<double>::infinity();
    Vec3 out = {0, 0, 0};
    for (const Tri& piece : t.pieces) {
        const Vec3& a = t.barycentric[size_t(piece[0])];
        const Vec3& c1 = t.barycentric[size_t(piece[1])];
        const Vec3& c2 = t.barycentric[size_t(piece[2])];
        const double area = tri_area_b(a, c1, c2);
        if (!(area > 0)) continue;
        const double l0 = tri_area_b(b, c1, c2) / area, l1 = tri_area_b(a, b, c2) / area, l2 = tri_area_b(a, c1, b) / area;
        const double m = std::min({l0, l1, l2});
        if (m > best) {
            best = m;
            const Vec3& x0 = t.image[size_t(piece[0])];
            const Vec3& x1 = t.image[size_t(piece[1])];
            const Vec3& x2 = t.image[size_t(piece[2])];
            out = {l0 * x0[0] + l1 * x1[0] + l2 * x2[0], l0 * x0[1] + l1 * x1[1] + l2 * x2[1],
                   l0 * x0[2] + l1 * x1[2] + l2 * x2[2]};
        }
    }
    return out;
}

TriangleQuality triangle_quality(const PhiTriangleData& t, int levels) {
    const int n = 1 << std::max(0, levels);
    auto idx = [n](int i, int j) { return size_t(j * (n + 1) + i); };  // grid point (i, j): b = (1 - (i+j)/n, i/n, j/n)
    std::vector<Vec3> x(size_t((n + 1) * (n + 1)));
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i + j <= n; ++i) {
            const double b1 = double(i) / n, b2 = double(j) / n;
            x[idx(i, j)] = phi_at(t, {1 - b1 - b2, b1, b2});
        }
    TriangleQuality q;
    auto aspect = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
        const double r = aspect_ratio(a, b, c);
        q.max_aspect = std::max(q.max_aspect, std::isfinite(r) ? r : std::numeric_limits<double>::infinity());
    };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i + j < n; ++i) {
            aspect(x[idx(i, j)], x[idx(i + 1, j)], x[idx(i, j + 1)]);
            if (i + j + 1 < n) aspect(x[idx(i + 1, j)], x[idx(i + 1, j + 1)], x[idx(i, j + 1)]);
        }
    // The refined surface at barycentric point b (linear over the sub-triangle holding b).
    auto flat_at = [&](const Vec3& b) -> Vec3 {
        const double u = b[1] * n, v = b[2] * n;
        int i = std::min(n - 1, std::max(0, int(std::floor(u)))), j = std::min(n - 1, std::max(0, int(std::floor(v))));
        if (i + j > n - 1) i = std::max(0, n - 1 - j);
        const double fu = u - i, fv = v - j;
        if (fu + fv <= 1 || i + j + 1 >= n) {  // lower sub-triangle (i,j), (i+1,j), (i,j+1)
            const Vec3 &a = x[idx(i, j)], &c1 = x[idx(i + 1, j)], &c2 = x[idx(i, j + 1)];
            return a + fu * (c1 - a) + fv * (c2 - a);
        }
        const Vec3 &a = x[idx(i + 1, j + 1)], &c1 = x[idx(i, j + 1)], &c2 = x[idx(i + 1, j)];  // upper
        return a + (1 - fu) * (c1 - a) + (1 - fv) * (c2 - a);
    };
    // Overlay vertices: the nodes ...
    for (size_t k = 0; k < t.barycentric.size(); ++k) q.max_error = std::max(q.max_error, distance(flat_at(t.barycentric[k]), t.image[k]));
    // ... and the crossings of piece edges with the grid lines b_k = m / n.
    for (const Tri& piece : t.pieces)
        for (int e = 0; e < 3; ++e) {
            const size_t ia = size_t(piece[size_t(e)]), ic = size_t(piece[size_t((e + 1) % 3)]);
            const Vec3 &ba = t.barycentric[ia], &bc = t.barycentric[ic];
            for (size_t k = 0; k < 3; ++k) {
                const double va = ba[k] * n, vc = bc[k] * n;
                if (va == vc) continue;
                const int lo = int(std::floor(std::min(va, vc))) + 1, hi = int(std::ceil(std::max(va, vc))) - 1;
                for (int m = lo; m <= hi; ++m) {
                    const double s = (m - va) / (vc - va);
                    if (!(s > 0 && s < 1)) continue;
                    const Vec3 b = ba + s * (bc - ba);
                    const Vec3 phi = t.image[ia] + s * (t.image[ic] - t.image[ia]);
                    q.max_error = std::max(q.max_error, distance(flat_at(b), phi));
                }
            }
        }
    return q;
}

// Smoothing of phi by relaxing every pair of coarse triangles across their shared edge
// (see the file comment); the tet-mesh smoother is tetmesh/tetmesh_smooth.cpp.
class ParametrizationSmoother {
public:
    ParametrizationSmoother(Parametrization& p, const SmoothOptions& o) : p_(p), o_(o) {
        const int32_t nt = p.coarse.num_triangles();
        tris_.resize(size_t(nt));
        quality_.resize(size_t(nt));
        for (int32_t t = 0; t < nt; ++t) tris_[size_t(t)] = detail::load_phi_triangle(p, t);
        // Original edges -> triangles, vertex -> triangles.
        vertex_tris_.resize(p.original.vertices.size());
        for (int32_t t = 0; t < p.original.num_triangles(); ++t) {
            const Tri& tri = p.original.triangles[size_t(t)];
            for (int k = 0; k < 3; ++k) {
                vertex_tris_[size_t(tri[size_t(k)])].push_back(t);
                original_edges_[detail::edge_key(tri[size_t(k)], tri[size_t((k + 1) % 3)])].push_back(t);
            }
        }
        find_original_creases();
        // Coarse edges with exactly two triangles.
        std::map<uint64_t, std::vector<std::pair<int32_t, int>>> ce;
        for (int32_t t = 0; t < nt; ++t) {
            const Tri& tri = p.coarse.triangles[size_t(t)];
            for (int k = 0; k < 3; ++k) ce[detail::edge_key(tri[size_t(k)], tri[size_t((k + 1) % 3)])].push_back({t, k});
        }
        for (auto& [k, list] : ce) {
            if (list.size() != 2) {
                ++skipped_static_;
                continue;
            }
            auto [ta, ka] = list[0];
            auto [tb, kb] = list[1];
            const Tri& A = p.coarse.triangles[size_t(ta)];
            const Tri& B = p.coarse.triangles[size_t(tb)];
            if (A[size_t(ka)] != B[size_t((kb + 1) % 3)]) {
                ++skipped_static_;
                continue;
            }
            // A patch border is a feature line of S0: its pair may only slide along it.
            pairs_.push_back({ta, ka, tb, kb, p.coarse.patches[size_t(ta)] != p.coarse.patches[size_t(tb)]});
        }
    }

    struct Pair {
        int32_t a;
        int ka;
        int32_t b;
        int kb;
        bool border;  // the two triangles belong to different patches
    };

    SmoothResult run(const Context& context) {
        SmoothResult result;
        result.pairs = int64_t(pairs_.size()) + skipped_static_;
        for (int sweep = 0; sweep < o_.iterations; ++sweep) {
            context.report(double(sweep) / std::max(1, o_.iterations), "smoothing");
            double change = 0;
            int64_t skipped = skipped_static_;
            reasons_.clear();
            if (skipped_static_ > 0) reasons_["edge not shared by exactly two consistently oriented triangles"] = skipped_static_;
            for (const Pair& pr : pairs_) {
                double c = 0;
                const int r = relax(pr, c);
                if (r == 1) ++result.updates, change = std::max(change, c);
                else if (r == 0) ++skipped;
                else ++result.rejected;
            }
            result.skipped = skipped;
            result.sweeps = sweep + 1;
            result.last_change = change;
            context.debug("sweep " + std::to_string(sweep + 1) + ": largest move " + detail::three_digit_text(change) +
                         " of the edge length, " + std::to_string(result.rejected) + " updates rejected so far");
            if (change < o_.tolerance) break;
        }
        write_back();
        return result;
    }

private:
    int skip(const char* reason) {
        ++reasons_[reason];
        return 0;
    }

    int reject(const char* reason) {
        ++rejected_reasons_[reason];
        return -1;
    }

    // 1 = updated, 0 = left alone (not applicable), -1 = rejected (would break phi).
    int relax(const Pair& pr, double& change) {
        PhiTriangleData* X[2] = {&tris_[size_t(pr.a)], &tris_[size_t(pr.b)]};
        const int kx[2] = {pr.ka, pr.kb};
        const Tri& A = p_.coarse.triangles[size_t(pr.a)];
        const Tri& B = p_.coarse.triangles[size_t(pr.b)];
        const auto& cv = p_.coarse.vertices;
        const Vec3 xp = cv[size_t(A[size_t(pr.ka)])], xq = cv[size_t(A[size_t((pr.ka + 1) % 3)])];
        const Vec3 xa = cv[size_t(A[size_t((pr.ka + 2) % 3)])], xb = cv[size_t(B[size_t((pr.kb + 2) % 3)])];
        const double L = distance(xp, xq);
        if (!(L > 0)) return skip("degenerate pair");
        auto place = [&](const Vec3& x, double sign) -> Vec2 {
            const double dp = distance(x, xp), dq = distance(x, xq);
            const double u = (L * L + dp * dp - dq * dq) / (2 * L);
            return {u, sign * std::sqrt(std::max(dp * dp - u * u, 0.0))};
        };
        Vec2 P{0, 0}, Q{L, 0};
        const Vec2 Da = place(xa, 1), Db = place(xb, -1);
        if (!(Da[1] > 0) || !(Db[1] < 0)) return skip("degenerate pair");
        const double x_cross = Da[0] + (Db[0] - Da[0]) * (Da[1] / (Da[1] - Db[1]));  // line ab meets the x axis
        if (orient2d(Da, P, Db) <= 0) P[0] = std::min(0.0, x_cross) - kReflexMargin * L;
        if (orient2d(Db, Q, Da) <= 0) Q[0] = std::max(L, x_cross) + kReflexMargin * L;
        if (orient2d(Da, P, Db) <= 0 || orient2d(Db, Q, Da) <= 0) return skip("degenerate pair");
        // Domain corners per triangle, in corner order.
        std::array<Vec2, 3> D[2];
        D[0][size_t(pr.ka)] = P, D[0][size_t((pr.ka + 1) % 3)] = Q, D[0][size_t((pr.ka + 2) % 3)] = Da;
        D[1][size_t(pr.kb)] = Q, D[1][size_t((pr.kb + 1) % 3)] = P, D[1][size_t((pr.kb + 2) % 3)] = Db;
        auto to_domain = [&](int s, const Vec3& b) -> Vec2 {
            return {b[0] * D[s][0][0] + b[1] * D[s][1][0] + b[2] * D[s][2][0],
                    b[0] * D[s][0][1] + b[1] * D[s][1][1] + b[2] * D[s][2][1]};
        };

        // Nodes.
        std::vector<QNode> nodes;
        std::map<NodeId, int> index;
        std::vector<int> local[2];  // per triangle: node -> QNode index (-1 for E crossings)
        bool e_has_crossing = false;
        std::vector<int> e_chain;  // QNodes on E (for the feature test)
        for (int s = 0; s < 2; ++s) {
            const PhiTriangleData& t = *X[s];
            auto& loc = local[s];
            loc.assign(t.barycentric.size(), -1);
            const size_t ke = size_t((kx[s] + 2) % 3), k0 = size_t(kx[s]), k1 = size_t((kx[s] + 1) % 3);
            for (size_t i = 0; i < t.barycentric.size(); ++i) {
                const bool on_e = t.barycentric[i][ke] == 0;
                const bool outer = t.barycentric[i][k0] == 0 || t.barycentric[i][k1] == 0;
                if (on_e && !outer && t.kind[i] == NodeKind::EdgeCrossing) {
                    e_has_crossing = true;
                    continue;
                }
                const NodeId id = node_id(t, i);
                auto it = index.find(id);
                int qi;
                if (it == index.end()) {
                    qi = int(nodes.size());
                    index.emplace(id, qi);
                    QNode n;
                    n.id = id;
                    n.kind = t.kind[i];
                    n.ov = t.original_vertex[i];
                    n.edge = t.original_edge[i];
                    n.s = t.edge_parameter[i];
                    n.image = t.image[i];
                    n.fixed = outer;
                    n.pos = n.old_pos = to_domain(s, t.barycentric[i]);
                    nodes.push_back(n);
                    if (on_e) e_chain.push_back(qi);
                } else {
                    qi = it->second;
                }
                nodes[size_t(qi)].has_old[s] = true;
                nodes[size_t(qi)].old_b[s] = t.barycentric[i];
                loc[i] = qi;
            }
        }
        // Feature lines of S0 (E runs along original edges that are sharp) and patch
        // borders: the original vertices on E only slide along E, to where the arc length
        // of S0 along E puts them (the one-dimensional shape-preserving map); the rest of
        // A and B is then relaxed with them fixed. Nothing crosses E there, so the two
        // triangles are relaxed each on its own side.
        bool sliding = pr.border;
        if (sliding && e_has_crossing) return skip("patch border crossed by original edges");
        if (!e_has_crossing) {
            std::sort(e_chain.begin(), e_chain.end(),
                      [&](int i, int j) { return nodes[size_t(i)].old_pos[0] < nodes[size_t(j)].old_pos[0]; });
            for (size_t i = 0; i + 1 < e_chain.size() && !sliding; ++i) {
                const int32_t u = nodes[size_t(e_chain[i])].ov, w = nodes[size_t(e_chain[i + 1])].ov;
                if (u < 0 || w < 0) return skip("feature line");
                auto it = original_edges_.find(detail::edge_key(u, w));
                if (it == original_edges_.end()) continue;
                if (it->second.size() != 2) return skip("feature line with 3 or more sheets");
                if (original_creases_.count(it->first)) sliding = true;
            }
        }
        if (sliding) {
            // Chain P = c_0, c_1, ..., c_m+1 = Q of original vertices along E, consecutive
            // ones joined by original edges.
            if (e_chain.size() < 3) return skip("feature line without original vertex on it");
            std::vector<double> arc(e_chain.size(), 0.0);
            for (size_t i = 0; i + 1 < e_chain.size(); ++i) {
                const QNode& u = nodes[size_t(e_chain[i])];
                const QNode& w = nodes[size_t(e_chain[i + 1])];
                if (u.ov < 0 || w.ov < 0 || !original_edges_.count(detail::edge_key(u.ov, w.ov)))
                    return skip("feature line not along original edges");
                arc[i + 1] = arc[i] + distance(u.image, w.image);
            }
            if (!(arc.back() > 0)) return skip("degenerate pair");
            for (size_t i = 1; i + 1 < e_chain.size(); ++i) {
                QNode& v = nodes[size_t(e_chain[i])];
                if (v.fixed || v.kind != NodeKind::OriginalVertex) return skip("degenerate pair");
                v.prescribed = v.on_e = true;
                v.mu = arc[i] / arc.back();
                v.pos = {P[0] + v.mu * (Q[0] - P[0]), P[1] + v.mu * (Q[1] - P[1])};
            }
        }
        std::vector<int> free;
        std::vector<int> free_index(nodes.size(), -1);
        for (size_t i = 0; i < nodes.size(); ++i)
            if (!nodes[i].fixed && !nodes[i].prescribed) {
                if (nodes[i].kind != NodeKind::OriginalVertex) return skip("degenerate pair");
                free_index[i] = int(free.size());
                free.push_back(int(i));
            }
        if (free.empty() && !sliding) return skip("no original vertex inside");

        // Regions per original triangle, in T's barycentric plane.
        struct Region {
            int32_t T;
            std::vector<int> ring;
            std::vector<Vec3> beta;  // parallel to ring
            double piece_area = 0;
        };
        std::map<int32_t, Region> regions;
        auto beta_of = [&](int32_t T, const NodeId& id, Vec3& out) -> bool {
            const Tri& tri = p_.original.triangles[size_t(T)];
            out = {0, 0, 0};
            if (id[0] < 0) {
                for (int k = 0; k < 3; ++k)
                    if (tri[size_t(k)] == id[1]) return out[size_t(k)] = 1, true;
                return false;
            }
            double s;
            std::memcpy(&s, &id[2], sizeof s);
            int ku = -1, kw = -1;
            for (int k = 0; k < 3; ++k) {
                if (tri[size_t(k)] == id[0]) ku = k;
                if (tri[size_t(k)] == id[1]) kw = k;
            }
            if (ku < 0 || kw < 0) return false;
            out[size_t(ku)] = 1 - s;
            out[size_t(kw)] = s;
            return true;
        };
        for (int s = 0; s < 2; ++s) {
            const PhiTriangleData& t = *X[s];
            for (size_t q = 0; q < t.pieces.size(); ++q) {
                const int32_t T = t.piece_original_triangle[q];
                Region& r = regions[T];
                r.T = T;
                Vec3 bc[3];
                for (int k = 0; k < 3; ++k) {
                    const size_t i = size_t(t.pieces[q][size_t(k)]);
                    if (!beta_of(T, node_id(t, i), bc[k])) return skip("inconsistent node");
                    const int qi = local[s][i];
                    if (qi >= 0 && std::find(r.ring.begin(), r.ring.end(), qi) == r.ring.end()) {
                        r.ring.push_back(qi);
                        r.beta.push_back(bc[k]);
                    }
                }
                r.piece_area += tri_area_b(bc[0], bc[1], bc[2]);
            }
        }
        for (auto& [T, r] : regions) {
            if (r.ring.size() < 3) return skip("region not convex or not connected");
            double c1 = 0, c2 = 0;
            for (const Vec3& b : r.beta) c1 += b[1], c2 += b[2];
            c1 /= double(r.beta.size()), c2 /= double(r.beta.size());
            std::vector<size_t> order(r.ring.size());
            for (size_t i = 0; i < order.size(); ++i) order[i] = i;
            std::vector<double> ang(order.size());
            for (size_t i = 0; i < order.size(); ++i) ang[i] = std::atan2(r.beta[i][2] - c2, r.beta[i][1] - c1);
            std::sort(order.begin(), order.end(), [&](size_t i, size_t j) { return ang[i] < ang[j]; });
            std::vector<int> ring;
            std::vector<Vec3> beta;
            for (size_t i : order) ring.push_back(r.ring[i]), beta.push_back(r.beta[i]);
            r.ring = ring, r.beta = beta;
            double area = 0;
            const size_t n = ring.size();
            for (size_t i = 0; i < n; ++i) {
                if (orient_barycentric(beta[(i + n - 1) % n], beta[i], beta[(i + 1) % n]) <= 0) return skip("region not convex or not connected");  // not strictly convex
                area += tri_area_b(beta[0], beta[i], beta[(i + 1) % n]);
            }
            if (std::abs(area - r.piece_area) > 1e-9 * 0.5) return skip("region not convex or not connected");  // region not convex / connected
        }

        // Weights from the 3D stars (star_weights); one sparse solve. The star of a free
        // vertex is cut by the quadrangle: a neighbour outside is replaced by the node where
        // their original edge leaves the quadrangle (same direction, shorter), as in the
        // region rings. Every triangle of the star must meet the quadrangle.
        const auto& x0 = p_.original.vertices;
        const size_t nf = free.size();
        std::vector<std::vector<StarWedge>> star(nf);
        for (auto& [T, r] : regions) {
            const Tri& tri = p_.original.triangles[size_t(T)];
            const size_t n = r.ring.size();
            for (size_t i = 0; i < n; ++i) {
                const QNode& v = nodes[size_t(r.ring[i])];
                if (free_index[size_t(r.ring[i])] < 0) continue;
                int j = -1;
                for (int k = 0; k < 3; ++k)
                    if (tri[size_t(k)] == v.ov) j = k;
                if (j < 0) return skip("inconsistent node");
                const Vec3 e1 = x0[size_t(tri[size_t((j + 1) % 3)])] - x0[size_t(v.ov)];
                const Vec3 e2 = x0[size_t(tri[size_t((j + 2) % 3)])] - x0[size_t(v.ov)];
                const int a = r.ring[(i + 1) % n], c = r.ring[(i + n - 1) % n];  // counter-clockwise: a, then c
                star[size_t(free_index[size_t(r.ring[i])])].push_back(
                    {a, c, std::atan2(norm(cross(e1, e2)), dot(e1, e2)), distance(nodes[size_t(a)].image, x0[size_t(v.ov)]),
                     distance(nodes[size_t(c)].image, x0[size_t(v.ov)])});
            }
        }
        std::vector<Eigen::Triplet<double>> trip;
        Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(long(nf), 2);
        std::vector<std::pair<int, double>> w;
        for (size_t i = 0; i < nf; ++i) {
            if (star[i].size() != vertex_tris_[size_t(nodes[size_t(free[i])].ov)].size())
                return skip("star leaves the quadrangle");
            if (!star_weights(star[i], o_.weights, w)) return skip("degenerate original triangle");
            trip.emplace_back(int(i), int(i), 1.0);
            for (const auto& [qi, lambda] : w) {
                const QNode& nb = nodes[size_t(qi)];
                if (free_index[size_t(qi)] < 0) {
                    rhs(long(i), 0) += lambda * nb.pos[0];
                    rhs(long(i), 1) += lambda * nb.pos[1];
                } else {
                    trip.emplace_back(int(i), free_index[size_t(qi)], -lambda);
                }
            }
        }
        Eigen::MatrixXd sol(long(nf), 2);
        if (nf > 0) {
            Eigen::SparseMatrix<double> M(static_cast<long>(nf), static_cast<long>(nf));
            M.setFromTriplets(trip.begin(), trip.end());
            Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
            lu.compute(M);
            if (lu.info() != Eigen::Success) return reject("solver failed");
            sol = lu.solve(rhs);
            if (lu.info() != Eigen::Success) return reject("solver failed");
        }
        double moved = 0;
        for (const QNode& v : nodes)
            if (v.prescribed) moved = std::max(moved, std::hypot(v.pos[0] - v.old_pos[0], v.pos[1] - v.old_pos[1]) / L);
        for (size_t i = 0; i < nf; ++i) {
            QNode& v = nodes[size_t(free[i])];
            v.pos = {sol(long(i), 0), sol(long(i), 1)};
            if (!std::isfinite(v.pos[0]) || !std::isfinite(v.pos[1])) return reject("solver failed");
            moved = std::max(moved, std::hypot(v.pos[0] - v.old_pos[0], v.pos[1] - v.old_pos[1]) / L);
            // Strictly inside the quadrangle P, b, Q, a.
            if (orient2d(P, Db, v.pos) <= 0 || orient2d(Db, Q, v.pos) <= 0 || orient2d(Q, Da, v.pos) <= 0 ||
                orient2d(Da, P, v.pos) <= 0)
                return reject("vertex outside the quadrangle");
            // A vertex within rounding distance of E goes onto E: otherwise the crossings of
            // its edges with E would coincide in floating point.
            const double ex = Q[0] - P[0], ey = Q[1] - P[1];
            const double mu = ((v.pos[0] - P[0]) * ex + (v.pos[1] - P[1]) * ey) / (ex * ex + ey * ey);
            const double dist = std::abs(ex * (v.pos[1] - P[1]) - ey * (v.pos[0] - P[0])) / std::sqrt(ex * ex + ey * ey);
            if (!sliding && dist < 1e-9 * L && mu > 0 && mu < 1) {
                v.on_e = true;
                v.mu = mu;
                v.pos = {P[0] + mu * ex, P[1] + mu * ey};
            }
        }
        for (auto& [T, r] : regions) {
            const size_t n = r.ring.size();
            for (size_t i = 0; i < n; ++i)
                if (orient2d(nodes[size_t(r.ring[(i + n - 1) % n])].pos, nodes[size_t(r.ring[i])].pos,
                             nodes[size_t(r.ring[(i + 1) % n])].pos) <= 0)
                    return reject("region not convex after the solve");
        }
        // Sides of E, positions along E.
        const double LL = (Q[0] - P[0]) * (Q[0] - P[0]) + (Q[1] - P[1]) * (Q[1] - P[1]);
        for (QNode& v : nodes) {
            if (v.fixed) {  // known from the triangle it belongs to
                v.side = v.has_old[0] && v.has_old[1] ? 0 : (v.has_old[0] ? 1 : -1);
                continue;
            }
            v.side = v.on_e ? 0 : orient2d(P, Q, v.pos);
            if (sliding && !v.prescribed && v.side != (v.has_old[0] ? 1 : -1)) return reject("vertex crossed a feature line");
            if (v.side == 0 && !v.on_e) {
                v.mu = ((v.pos[0] - P[0]) * (Q[0] - P[0]) + (v.pos[1] - P[1]) * (Q[1] - P[1])) / LL;
                if (!(v.mu > 0 && v.mu < 1)) return reject("vertex on E outside the edge");
            }
        }
        // Cut the regions along E.
        std::map<uint64_t, int> crossings;
        struct Poly {
            int32_t T;
            int side;  // 0 = A, 1 = B
            std::vector<int> ring;
            std::vector<Vec3> beta;
        };
        std::vector<Poly> polys;
        for (auto& [T, r] : regions) {
            const Tri& tri = p_.original.triangles[size_t(T)];
            Poly pa{T, 0, {}, {}}, pb{T, 1, {}, {}};
            const size_t n = r.ring.size();
            for (size_t i = 0; i < n; ++i) {
                const int xi = r.ring[i], yi = r.ring[(i + 1) % n];
                const QNode& xn = nodes[size_t(xi)];
                const QNode& yn = nodes[size_t(yi)];
                if (xn.side >= 0) pa.ring.push_back(xi), pa.beta.push_back(r.beta[i]);
                if (xn.side <= 0) pb.ring.push_back(xi), pb.beta.push_back(r.beta[i]);
                if (xn.side * yn.side >= 0) continue;
                const Vec3& bx = r.beta[i];
                const Vec3& by = r.beta[(i + 1) % n];
                int kz = -1;
                for (int k = 0; k < 3; ++k)
                    if (bx[size_t(k)] == 0 && by[size_t(k)] == 0) kz = k;
                if (kz < 0) return reject("crossing not on an original edge");
                int32_t u = tri[size_t((kz + 1) % 3)], w = tri[size_t((kz + 2) % 3)];
                int ku = (kz + 1) % 3, kw = (kz + 2) % 3;
                if (u > w) std::swap(u, w), std::swap(ku, kw);
                const uint64_t ek = detail::edge_key(u, w);
                auto it = crossings.find(ek);
                int ci;
                if (it != crossings.end()) {
                    ci = it->second;
                } else {
                    // Canonical direction: from the node with the smaller id.
                    const bool fwd = xn.id < yn.id;
                    const QNode& s0 = fwd ? xn : yn;
                    const QNode& s1 = fwd ? yn : xn;
                    const Vec3& b0 = fwd ? bx : by;
                    const Vec3& b1 = fwd ? by : bx;
                    auto cr = [&](const Vec2& z) {
                        return (Q[0] - P[0]) * (z[1] - P[1]) - (Q[1] - P[1]) * (z[0] - P[0]);
                    };
                    const double d0 = cr(s0.pos), d1 = cr(s1.pos);
                    const double t = d0 / (d0 - d1);
                    if (!(t > 0 && t < 1)) return reject("crossing not on E");
                    const Vec2 z = s0.pos + t * (s1.pos - s0.pos);
                    const double sw = b0[size_t(kw)] + t * (b1[size_t(kw)] - b0[size_t(kw)]);
                    if (!(sw > 0 && sw < 1)) return reject("crossing not on E");
                    QNode c;
                    c.kind = NodeKind::EdgeCrossing;
                    c.ov = -1;
                    c.edge = {u, w};
                    c.s = sw;
                    const Vec3& xu = x0[size_t(u)];
                    const Vec3& xw = x0[size_t(w)];
                    c.image = {(1 - sw) * xu[0] + sw * xw[0], (1 - sw) * xu[1] + sw * xw[1],
                               (1 - sw) * xu[2] + sw * xw[2]};
                    int64_t bits;
                    std::memcpy(&bits, &sw, sizeof bits);
                    c.id = {u, w, bits};
                    c.pos = c.old_pos = z;
                    c.side = 0;
                    c.mu = ((z[0] - P[0]) * (Q[0] - P[0]) + (z[1] - P[1]) * (Q[1] - P[1])) / LL;
                    if (!(c.mu > 0 && c.mu < 1)) return reject("crossing not on E");
                    ci = int(nodes.size());
                    nodes.push_back(c);
                    crossings.emplace(ek, ci);
                }
                Vec3 bc{0, 0, 0};
                bc[size_t(ku)] = 1 - nodes[size_t(ci)].s;
                bc[size_t(kw)] = nodes[size_t(ci)].s;
                pa.ring.push_back(ci), pa.beta.push_back(bc);
                pb.ring.push_back(ci), pb.beta.push_back(bc);
            }
            if (pa.ring.size() >= 3) polys.push_back(pa);
            if (pb.ring.size() >= 3) polys.push_back(pb);
        }

        // New phi of A and B.
        PhiTriangleData out[2];
        std::vector<int> loc[2];
        loc[0].assign(nodes.size(), -1);
        loc[1].assign(nodes.size(), -1);
        auto bary_in = [&](int s, const QNode& v, Vec3& b) -> bool {
            if (v.fixed) {
                if (!v.has_old[s]) return false;
                b = v.old_b[s];
                return true;
            }
            const size_t k0 = size_t(kx[s]), k1 = size_t((kx[s] + 1) % 3), k2 = size_t((kx[s] + 2) % 3);
            if (v.side == 0) {
                b[k2] = 0;
                // A: corners (p, q) = (k0, k1); B: (q, p).
                b[k0] = s == 0 ? 1 - v.mu : v.mu;
                b[k1] = s == 0 ? v.mu : 1 - v.mu;
                return true;
            }
            const auto& d = D[s];
            const double u1 = d[1][0] - d[0][0], u2 = d[1][1] - d[0][1];
            const double w1 = d[2][0] - d[0][0], w2 = d[2][1] - d[0][1];
            const double z1 = v.pos[0] - d[0][0], z2 = v.pos[1] - d[0][1];
            const double det = u1 * w2 - u2 * w1;
            const double l1 = (z1 * w2 - z2 * w1) / det, l2 = (u1 * z2 - u2 * z1) / det;
            b = {1 - l1 - l2, l1, l2};
            // Keep clear of the edges by more than rounding (nearly degenerate pieces).
            return b[0] > kMinGap && b[1] > kMinGap && b[2] > kMinGap;
        };
        auto add = [&](int s, int qi) -> int {
            if (loc[s][size_t(qi)] >= 0) return loc[s][size_t(qi)];
            const QNode& v = nodes[size_t(qi)];
            Vec3 b;
            if (!bary_in(s, v, b)) return reject("node too close to a coarse edge");
            loc[s][size_t(qi)] = out[s].add_node(b, v.image, v.kind, v.ov, v.edge, v.s);
            return loc[s][size_t(qi)];
        };
        // Corners first, in corner order.
        for (int s = 0; s < 2; ++s) {
            const PhiTriangleData& t = *X[s];
            for (int k = 0; k < 3; ++k)
                for (size_t i = 0; i < t.barycentric.size(); ++i)
                    if (t.kind[i] == NodeKind::CoarseCorner && t.barycentric[i][size_t(k)] == 1)
                        if (add(s, local[s][i]) < 0) return reject("node too close to a coarse edge");
        }
        for (Poly& poly : polys) {
            const int s = poly.side;
            const std::vector<int>& ring = poly.ring;
            const std::vector<Vec3>& beta = poly.beta;
            auto emit = [&](int a, int b, int c) -> bool {
                int l[3] = {add(s, ring[size_t(a)]), add(s, ring[size_t(b)]), add(s, ring[size_t(c)])};
                if (l[0] < 0 || l[1] < 0 || l[2] < 0) return false;
                const std::vector<Vec3>& nb = out[s].barycentric;
                if (orient_barycentric(nb[size_t(l[0])], nb[size_t(l[1])], nb[size_t(l[2])]) <= 0) return false;
                out[s].add_piece(Tri{l[0], l[1], l[2]}, poly.T);
                return true;
            };
            auto orient = [&](int a, int b, int c) {
                return orient_barycentric(beta[size_t(a)], beta[size_t(b)], beta[size_t(c)]);
            };
            // Drop consecutive points that coincide in T (cannot happen; be safe) and check area.
            double area = 0;
            for (size_t i = 0; i < beta.size(); ++i) area += tri_area_b(beta[0], beta[i], beta[(i + 1) % beta.size()]);
            if (!(area > 0)) {
                bool flat = true;
                for (size_t i = 2; i < beta.size(); ++i)
                    if (orient_barycentric(beta[0], beta[1], beta[i]) != 0) flat = false;
                if (flat) continue;  // a region touching E only along an edge or a point
                return reject("piece flipped");
            }
            std::vector<int> corners(ring.size());
            for (size_t i = 0; i < corners.size(); ++i) corners[i] = int(i);
            if (!detail::clip_convex_ears(corners, orient, emit)) return reject("piece flipped");
            const int o = orient(corners[0], corners[1], corners[2]);
            if (o == 0) continue;
            if (o < 0) return reject("piece flipped");
            if (!emit(corners[0], corners[1], corners[2])) return reject("piece flipped");
        }
        // Nodes on E well apart (no nearly coincident crossings).
        {
            std::vector<double> mus = {0.0, 1.0};
            for (const QNode& v : nodes)
                if (!v.fixed && v.side == 0) mus.push_back(v.mu);
            std::sort(mus.begin(), mus.end());
            for (size_t i = 0; i + 1 < mus.size(); ++i)
                if (!(mus[i + 1] - mus[i] > kMinGap)) return reject("nodes on E too close");
        }
        // No collapse into a corner. Near a coarse vertex where the unfolded pair is wider
        // than the part of S0 it holds (a saddle of S, or a reflex corner moved to just
        // past 180 degrees), the straight original edges of the chart cross E closer to
        // the corner than before; repeated over the sweeps this contracts the whole star
        // of S0 around that vertex into the corner (measured on femur at 10%: a factor
        // ~60 per sweep, down to 1e-10 of the edge after five sweeps), where no
        // refinement can resolve it. So an update may not bring a node nearer to a
        // corner of A or B than kCornerGap (in barycentric units) unless one already was.
        {
            auto gap = [](const PhiTriangleData& t) {
                double g = 1;
                for (size_t i = 0; i < t.barycentric.size(); ++i)
                    if (t.kind[i] != NodeKind::CoarseCorner) g = std::min(g, 1 - std::max({t.barycentric[i][0], t.barycentric[i][1], t.barycentric[i][2]}));
                return g;
            };
            for (int s = 0; s < 2; ++s)
                if (gap(out[s]) < std::min(gap(*X[s]), kCornerGap)) return reject("collapse into a corner");
        }
        // Every node must be used by a piece; the pieces must cover both triangles; no two
        // nodes at the same parameter point.
        for (int s = 0; s < 2; ++s) {
            std::vector<Vec3> sorted = out[s].barycentric;
            std::sort(sorted.begin(), sorted.end());
            if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return reject("two nodes at one point");
            std::vector<char> used(out[s].barycentric.size(), 0);
            double area = 0;
            for (const Tri& t : out[s].pieces) {
                for (int32_t i : t) used[size_t(i)] = 1;
                area += tri_area_b(out[s].barycentric[size_t(t[0])], out[s].barycentric[size_t(t[1])], out[s].barycentric[size_t(t[2])]);
            }
            if (std::find(used.begin(), used.end(), 0) != used.end()) return reject("pieces do not tile");
            if (std::abs(area - 0.5) > 1e-9) return reject("pieces do not tile");
        }
        // Not worse than before, per coarse triangle: the relaxation places the original
        // vertices by the shape of S0 alone and knows neither where the refinement samples
        // phi nor how far phi(x) lies from x. On CAD-like shapes (flat faces meeting at
        // creases inside a pair, saddles) it measurably made the K-times refined surface
        // worse: larger max |flat - phi| and larger max aspect ratio. So an update is kept
        // only if, for A and for B, neither the largest aspect ratio of its refined
        // triangles nor its largest |flat - phi| over the overlay grows (triangle_quality).
        TriangleQuality after[2];
        if (o_.check_levels > 0) {
            const int32_t ids[2] = {pr.a, pr.b};
            for (int s = 0; s < 2; ++s) {
                const TriangleQuality& before = quality_of(ids[s]);
                after[s] = triangle_quality(out[s], o_.check_levels);
                if (after[s].max_aspect > before.max_aspect * (1 + 1e-9)) return reject("refined aspect ratio would grow");
                if (after[s].max_error > before.max_error * (1 + 1e-9) + 1e-15) return reject("distance |flat - phi| would grow");
            }
            quality_[size_t(pr.a)] = after[0];
            quality_[size_t(pr.b)] = after[1];
        }
        *X[0] = std::move(out[0]);
        *X[1] = std::move(out[1]);
        change = moved;
        if (sliding) ++slides_;
        return 1;
    }

    // triangle_quality of coarse triangle t's current phi, computed once and kept until an
    // accepted update replaces that phi (most updates are rejected, and a triangle is in
    // three pairs per sweep).
    const TriangleQuality& quality_of(int32_t t) {
        std::optional<TriangleQuality>& q = quality_[size_t(t)];
        if (!q) q = triangle_quality(tris_[size_t(t)], o_.check_levels);
        return *q;
    }

    // The creases of S0 as the simplifier found them (core/crease_chains.h, the same rule
    // over the same edges: two triangles of one patch); an edge of two triangles of
    // different patches is a crease where CreaseTest says so (a patch border slides anyway).
    void find_original_creases() {
        const Surface& s = p_.original;
        auto patch = [&](int32_t t) { return s.patches.empty() ? 0 : s.patches[size_t(t)]; };
        std::vector<uint64_t> keys;
        for (const auto& [key, ts] : original_edges_)
            if (ts.size() == 2) keys.push_back(key);
        std::sort(keys.begin(), keys.end());  // one order, whatever the hash map's
        const detail::CreaseTest border_test(o_.feature_angle_degrees);
        std::vector<detail::SheetEdge> sheet;
        std::vector<uint64_t> sheet_keys;
        for (const uint64_t key : keys) {
            const auto& ts = original_edges_.at(key);
            const int32_t u = detail::edge_key_first(key), w = detail::edge_key_second(key);
            const Tri &t0 = s.triangles[size_t(ts[0])], &t1 = s.triangles[size_t(ts[1])];
            if (patch(ts[0]) != patch(ts[1])) {
                if (border_test.is_crease(s.vertices, t0, t1, u, w)) original_creases_.insert(key);
                continue;
            }
            sheet.push_back({u, w, t0, t1});
            sheet_keys.push_back(key);
        }
        detail::CreaseRule rule;
        rule.feature_angle_degrees = o_.feature_angle_degrees;
        rule.chain_angle_degrees = o_.crease_chain_angle_degrees;
        rule.min_chain_length = o_.crease_chain_length * bounding_box_diagonal(s);
        const std::vector<uint8_t> crease = detail::find_creases(s.vertices, sheet, rule);
        for (size_t i = 0; i < sheet.size(); ++i)
            if (crease[i]) original_creases_.insert(sheet_keys[i]);
    }

    void write_back() {
        detail::clear_phi(p_);
        for (const PhiTriangleData& t : tris_) detail::append_phi_triangle(p_, t);
    }

    Parametrization& p_;
    const SmoothOptions& o_;
    std::vector<PhiTriangleData> tris_;
    std::vector<std::optional<TriangleQuality>> quality_;  // per coarse triangle, see quality_of()
    std::vector<std::vector<int32_t>> vertex_tris_;
    std::unordered_map<uint64_t, std::vector<int32_t>> original_edges_;
    std::unordered_set<uint64_t> original_creases_;  // edge keys of S0 (find_original_creases)
    std::vector<Pair> pairs_;
    int64_t skipped_static_ = 0;

public:
    int64_t slides_ = 0;  // updates of pairs along feature lines and patch borders (all sweeps)

private:

public:
    std::map<std::string, int64_t> reasons_;  // why pairs were left alone (last sweep)
    std::map<std::string, int64_t> rejected_reasons_;  // why updates were rejected (all sweeps)
};

}  // namespace

RefinedQuality refined_quality(const Parametrization& param, int levels) {
    RefinedSurface r;
    RefineOptions o;
    o.levels = levels;
    refine(param, o, Context{}, r);
    std::vector<double> q;
    q.reserve(r.surface.triangles.size());
    for (const Tri& t : r.surface.triangles)
        q.push_back(aspect_ratio(r.surface.vertices[size_t(t[0])], r.surface.vertices[size_t(t[1])],
                                 r.surface.vertices[size_t(t[2])]));
    RefinedQuality out;
    if (q.empty()) return out;
    std::sort(q.begin(), q.end());
    out.max_aspect_ratio = q.back();
    out.p99_aspect_ratio = q[std::min(q.size() - 1, size_t(0.99 * double(q.size())))];
    double sum = 0;
    for (double x : q) sum += std::isfinite(x) ? x : 0;
    out.mean_aspect_ratio = sum / double(q.size());
    return out;
}

SmoothResult smooth(Parametrization& param, const SmoothOptions& options, const Context& context) {
    const auto start = std::chrono::steady_clock::now();
    if (options.iterations < 0) throw OptionError("smooth: iterations must be >= 0");
    detail::check_crease_rule_numbers(options.feature_angle_degrees, options.crease_chain_angle_degrees,
                                      options.crease_chain_length, "smooth: ");
    if (!(options.tolerance >= 0)) throw OptionError("smooth: tolerance must be >= 0");
    if (options.measure_quality && (options.quality_levels < 0 || options.quality_levels > 6))
        throw OptionError("smooth: quality_levels must be in 0..6");
    if (options.check_levels < 0 || options.check_levels > 6) throw OptionError("smooth: check_levels must be in 0..6");
    detail::require_coordinates_in_range(param);
    SmoothResult result;
    if (options.measure_quality) result.before = refined_quality(param, options.quality_levels);
    {
        ParametrizationSmoother smoother(param, options);
        const SmoothResult r = smoother.run(context);
        result.sweeps = r.sweeps;
        result.pairs = r.pairs;
        result.skipped = r.skipped;
        result.updates = r.updates;
        result.rejected = r.rejected;
        result.last_change = r.last_change;
        result.skipped_reasons = smoother.reasons_;
        result.rejected_reasons = smoother.rejected_reasons_;
        result.slides = smoother.slides_;
    }
    if (options.measure_quality) result.after = refined_quality(param, options.quality_levels);
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    context.report(1.0, "smoothing");
    return result;
}

}  // namespace bpm
