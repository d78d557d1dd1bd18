// Evaluating phi by point location among the pieces of a coarse triangle.
//
// The paper (Krause & Sander §2.2.3) locates points with the randomized walk of Brown
// and Faigle. Here every coarse triangle gets a small uniform grid over its parameter
// triangle in (b1, b2) coordinates instead; each cell lists the pieces that overlap it.
// A query looks at one cell and tests its few candidates, which is branch-light,
// needs no adjacency between pieces and is the same cost for every point
// (> 10 million evaluations per second for files with ~100 pieces per coarse triangle).
//
// Each piece stores the inverse of the matrix whose columns are its corners'
// barycentric coordinates in the coarse triangle: multiplying the query's coarse
// barycentrics by it gives the query's barycentrics in the piece directly. For the
// identity parametrization that matrix is exactly the identity, so phi reproduces the
// input point bit for bit.

#include "bpm/phi_evaluation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace bpm {

namespace {

using Mat3 = std::array<double, 9>;  // row-major

inline Vec3 mul(const Mat3& m, const Vec3& b) {
    return {m[0] * b[0] + m[1] * b[1] + m[2] * b[2], m[3] * b[0] + m[4] * b[1] + m[5] * b[2],
            m[6] * b[0] + m[7] * b[1] + m[8] * b[2]};
}

inline double min3(const Vec3& v) { return std::min(v[0], std::min(v[1], v[2])); }

// Does the closed triangle (a, b, c) in the (b1, b2) plane come within `tol` of the box
// [x0, x1] x [y0, y1]? Separating axis test with the triangle's edge normals; the box
// axes are covered by the caller's bounding-box range.
bool triangle_touches_box(const Vec2& a, const Vec2& b, const Vec2& c, double x0, double y0, double x1, double y1,
                          double tol) {
    const Vec2 corners[3] = {a, b, c};
    const double orientation = cross(b - a, c - a);
    if (orientation == 0) return true;  // degenerate: keep conservatively (it is never chosen anyway)
    const double sign = orientation > 0 ? 1.0 : -1.0;
    for (int k = 0; k < 3; ++k) {
        const Vec2& p = corners[k];
        const Vec2& q = corners[(k + 1) % 3];
        // Outward normal of edge p->q for a counter-clockwise triangle.
        const Vec2 n{sign * (q[1] - p[1]), -sign * (q[0] - p[0])};
        const double slack = tol * std::sqrt(dot(n, n));
        const double d = std::min({dot(n, Vec2{x0, y0} - p), dot(n, Vec2{x1, y0} - p), dot(n, Vec2{x0, y1} - p),
                                   dot(n, Vec2{x1, y1} - p)});
        if (d > slack) return false;
    }
    return true;
}

}  // namespace

// How a piece's corners sit in the piece's original triangle: corner k has
// barycentric coordinates (1 - s[k]) at original corner a[k] plus s[k] at b[k]
// (s = 0, a = b for an original vertex). Derived once from the node kinds so that a
// query does not chase the per-node arrays.
struct CornerCode {
    double s[3];
    uint8_t a[3];
    uint8_t b[3];
};

struct PhiEvaluator::Impl {
    const Parametrization& p;
    std::vector<Mat3> to_piece;        // #P coarse barycentrics -> piece barycentrics
    std::vector<CornerCode> corners;   // #P
    std::vector<Vec3> normals;         // #S0.T unit normals of the original triangles
    std::vector<int32_t> grid_size;    // #S.T cells per side g (g*g cells, row-major in (b1, b2))
    std::vector<int64_t> grid_begin;   // #S.T index of the triangle's first entry in cell_start
    std::vector<int64_t> cell_start;   // per triangle g*g+1 offsets into cell_pieces
    std::vector<int32_t> cell_pieces;  // global piece indices

    explicit Impl(const Parametrization& param) : p(param) { build(); }

    void build() {
        const int32_t nt = p.num_coarse_triangles();
        const auto& x = p.original.vertices;
        normals.resize(p.original.triangles.size());
        for (size_t i = 0; i < normals.size(); ++i) {
            const Tri& tri = p.original.triangles[i];
            normals[i] = triangle_normal(x[static_cast<size_t>(tri[0])], x[static_cast<size_t>(tri[1])],
                                         x[static_cast<size_t>(tri[2])]);
        }
        to_piece.resize(static_cast<size_t>(p.num_pieces()));
        corners.resize(static_cast<size_t>(p.num_pieces()));
        grid_size.resize(static_cast<size_t>(nt));
        grid_begin.resize(static_cast<size_t>(nt));
        for (int32_t t = 0; t < nt; ++t) {
            const int64_t nb = p.node_offsets[static_cast<size_t>(t)];
            const int64_t q0 = p.piece_offsets[static_cast<size_t>(t)], q1 = p.piece_offsets[static_cast<size_t>(t) + 1];
            const int64_t count = q1 - q0;
            // About one cell per piece area: few candidates per cell, small grids.
            const int32_t g = static_cast<int32_t>(
                std::clamp(std::ceil(std::sqrt(2.0 * static_cast<double>(count))), 1.0, 1024.0));
            grid_size[static_cast<size_t>(t)] = g;
            grid_begin[static_cast<size_t>(t)] = static_cast<int64_t>(cell_start.size());
            std::vector<std::vector<int32_t>> cells(static_cast<size_t>(g) * static_cast<size_t>(g));
            for (int64_t q = q0; q < q1; ++q) {
                const Tri& piece = p.pieces[static_cast<size_t>(q)];
                corners[static_cast<size_t>(q)] = corner_code(nb, piece, q);
                const Vec3& a = p.node_barycentric[static_cast<size_t>(nb + piece[0])];
                const Vec3& b = p.node_barycentric[static_cast<size_t>(nb + piece[1])];
                const Vec3& c = p.node_barycentric[static_cast<size_t>(nb + piece[2])];
                // Inverse of [a b c] (columns): rows are (b x c, c x a, a x b) / det.
                const Vec3 r0 = cross(b, c), r1 = cross(c, a), r2 = cross(a, b);
                const double det = dot(a, r0);
                Mat3& m = to_piece[static_cast<size_t>(q)];
                if (det == 0 || !std::isfinite(det)) {
                    // A degenerate piece covers no area; make every point look far outside it.
                    m.fill(-1.0);
                } else {
                    const double inv = 1.0 / det;
                    // For the identity piece det == 1 and the rows stay exact unit vectors.
                    for (int k = 0; k < 3; ++k) {
                        m[static_cast<size_t>(k)] = r0[k] * inv;
                        m[static_cast<size_t>(3 + k)] = r1[k] * inv;
                        m[static_cast<size_t>(6 + k)] = r2[k] * inv;
                    }
                }
                const Vec2 pa{a[1], a[2]}, pb{b[1], b[2]}, pc{c[1], c[2]};
                const double tol = 1e-9;
                const double umin = std::min({pa[0], pb[0], pc[0]}) - tol, umax = std::max({pa[0], pb[0], pc[0]}) + tol;
                const double vmin = std::min({pa[1], pb[1], pc[1]}) - tol, vmax = std::max({pa[1], pb[1], pc[1]}) + tol;
                const int32_t i0 = std::clamp(static_cast<int32_t>(std::floor(umin * g)), 0, g - 1);
                const int32_t i1 = std::clamp(static_cast<int32_t>(std::floor(umax * g)), 0, g - 1);
                const int32_t j0 = std::clamp(static_cast<int32_t>(std::floor(vmin * g)), 0, g - 1);
                const int32_t j1 = std::clamp(static_cast<int32_t>(std::floor(vmax * g)), 0, g - 1);
                for (int32_t i = i0; i <= i1; ++i)
                    for (int32_t j = j0; j <= j1; ++j) {
                        const double x0 = double(i) / g, x1 = double(i + 1) / g;
                        const double y0 = double(j) / g, y1 = double(j + 1) / g;
                        if (g == 1 || triangle_touches_box(pa, pb, pc, x0, y0, x1, y1, tol))
                            cells[static_cast<size_t>(i) * static_cast<size_t>(g) + static_cast<size_t>(j)].push_back(
                                static_cast<int32_t>(q));
                    }
            }
            for (const auto& cell : cells) {
                cell_start.push_back(static_cast<int64_t>(cell_pieces.size()));
                cell_pieces.insert(cell_pieces.end(), cell.begin(), cell.end());
            }
            cell_start.push_back(static_cast<int64_t>(cell_pieces.size()));
        }
    }

    // The piece containing `b`, and b's barycentrics in it.
    int64_t locate(int32_t t, const Vec3& b, Vec3& lambda) const {
        const int32_t g = grid_size[static_cast<size_t>(t)];
        // NaN-safe clamping: a comparison with NaN is false, which selects 0.
        const double fu = b[1] * g, fv = b[2] * g;
        const int32_t i = fu >= 0 ? std::min(static_cast<int32_t>(fu), g - 1) : 0;
        const int32_t j = fv >= 0 ? std::min(static_cast<int32_t>(fv), g - 1) : 0;
        const int64_t* cs = &cell_start[static_cast<size_t>(grid_begin[static_cast<size_t>(t)] +
                                                            static_cast<int64_t>(i) * g + j)];
        int64_t best = -1;
        double best_min = -std::numeric_limits<double>::infinity();
        for (int64_t k = cs[0]; k < cs[1]; ++k) {
            const int32_t q = cell_pieces[static_cast<size_t>(k)];
            const Vec3 l = mul(to_piece[static_cast<size_t>(q)], b);
            const double m = min3(l);
            if (m >= 0) {
                lambda = l;
                return q;
            }
            if (m > best_min) {
                best_min = m;
                best = q;
                lambda = l;
            }
        }
        // On a piece edge, rounding may put the point a hair outside every candidate;
        // anything further out (a query outside the triangle, or a cell whose list
        // missed it) gets the piece it is least outside of among all pieces.
        if (best >= 0 && best_min >= -1e-9) return best;
        const int64_t q0 = p.piece_offsets[static_cast<size_t>(t)], q1 = p.piece_offsets[static_cast<size_t>(t) + 1];
        for (int64_t q = q0; q < q1; ++q) {
            const Vec3 l = mul(to_piece[static_cast<size_t>(q)], b);
            const double m = min3(l);
            if (m > best_min) {
                best_min = m;
                best = q;
                lambda = l;
            }
        }
        return best;
    }

    // Where the corners of piece q sit in its original triangle, derived from what the
    // nodes are rather than from their positions (exact): an original vertex is a unit
    // vector, an edge crossing (u, w, s) is (1-s) at u plus s at w.
    CornerCode corner_code(int64_t nb, const Tri& piece, int64_t q) const {
        CornerCode code{};
        const Tri& tri = p.original.triangles[static_cast<size_t>(p.piece_original_triangle[static_cast<size_t>(q)])];
        const auto corner_of = [&](int32_t v) -> int {
            for (int c = 0; c < 3; ++c)
                if (tri[c] == v) return c;
            return -1;
        };
        for (int k = 0; k < 3; ++k) {
            const size_t n = static_cast<size_t>(nb + piece[k]);
            int a = -1, b = -1;
            double s = 0;
            if (p.node_kind[n] == NodeKind::EdgeCrossing) {
                a = corner_of(p.node_original_edge[n][0]);
                b = corner_of(p.node_original_edge[n][1]);
                s = p.node_edge_parameter[n];
            } else {
                a = b = corner_of(p.node_original_vertex[n]);
            }
            if (a < 0 || b < 0) {
                // Inconsistent input (the node is not on this triangle): use the nearest
                // corner of the triangle so that evaluation still returns something sane.
                a = b = nearest_corner(p.node_image[n], tri);
                s = 0;
            }
            code.a[k] = static_cast<uint8_t>(a);
            code.b[k] = static_cast<uint8_t>(b);
            code.s[k] = s;
        }
        return code;
    }

    int nearest_corner(const Vec3& y, const Tri& tri) const {
        int best = 0;
        for (int c = 1; c < 3; ++c)
            if (distance(y, p.original.vertices[static_cast<size_t>(tri[c])]) <
                distance(y, p.original.vertices[static_cast<size_t>(tri[best])]))
                best = c;
        return best;
    }

    PhiSample evaluate(int32_t t, const Vec3& b) const {
        Vec3 l;
        const int64_t q = locate(t, b, l);
        PhiSample out;
        if (q < 0) return out;  // coarse triangle without pieces: invalid input
        if (min3(l) < 0) {
            // Outside by rounding (or a query outside the triangle): snap to the piece.
            for (double& x : l) x = std::max(x, 0.0);
            const double sum = l[0] + l[1] + l[2];
            l = (1.0 / sum) * l;
        }
        const int64_t nb = p.node_offsets[static_cast<size_t>(t)];
        const Tri& piece = p.pieces[static_cast<size_t>(q)];
        const int64_t n0 = nb + piece[0], n1 = nb + piece[1], n2 = nb + piece[2];
        out.position = barycentric_point(p.node_image[static_cast<size_t>(n0)], p.node_image[static_cast<size_t>(n1)],
                                         p.node_image[static_cast<size_t>(n2)], l);
        const int32_t ot = p.piece_original_triangle[static_cast<size_t>(q)];
        out.original_triangle = ot;
        const CornerCode& code = corners[static_cast<size_t>(q)];
        Vec3 beta{0, 0, 0};
        for (int k = 0; k < 3; ++k) {
            // For an original vertex this adds l[k] * 1 and then + 0: exact.
            beta[code.a[k]] += l[k] * (1 - code.s[k]);
            beta[code.b[k]] += l[k] * code.s[k];
        }
        out.original_barycentric = beta;
        out.normal = normals[static_cast<size_t>(ot)];
        return out;
    }
};

PhiEvaluator::PhiEvaluator(const Parametrization& param) : impl_(new Impl(param)) {}
PhiEvaluator::~PhiEvaluator() { delete impl_; }

PhiSample PhiEvaluator::evaluate(int32_t coarse_triangle, const Vec3& barycentric) const {
    return impl_->evaluate(coarse_triangle, barycentric);
}

void PhiEvaluator::evaluate(const std::vector<int32_t>& triangles, const std::vector<Vec3>& barycentrics,
                            std::vector<PhiSample>& out) const {
    if (triangles.size() != barycentrics.size())
        throw std::invalid_argument("PhiEvaluator::evaluate: triangles and barycentrics differ in length");
    const size_t n = triangles.size();
    out.resize(n);
    const size_t nt = static_cast<size_t>(impl_->p.num_coarse_triangles());
    if (n < 4 * nt || n < 1024 || n > size_t(std::numeric_limits<uint32_t>::max())) {
        for (size_t i = 0; i < n; ++i) out[i] = impl_->evaluate(triangles[i], barycentrics[i]);
        return;
    }
    // Many queries: visit them grouped by coarse triangle (a counting sort), so that each
    // triangle's pieces and nodes are loaded into the cache once instead of once per
    // query; random query order is otherwise bound by memory latency.
    std::vector<uint32_t> start(nt + 1, 0);
    for (int32_t t : triangles) {
        if (t < 0 || static_cast<size_t>(t) >= nt)
            throw std::out_of_range("PhiEvaluator::evaluate: coarse triangle index out of range");
        ++start[static_cast<size_t>(t) + 1];
    }
    for (size_t t = 0; t < nt; ++t) start[t + 1] += start[t];
    std::vector<uint32_t> order(n);
    for (size_t i = 0; i < n; ++i) order[start[static_cast<size_t>(triangles[i])]++] = static_cast<uint32_t>(i);
    for (uint32_t i : order) out[i] = impl_->evaluate(triangles[i], barycentrics[i]);
}

}  // namespace bpm
