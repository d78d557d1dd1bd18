// Inverting phi: point location among the pieces of one original triangle, and closest
// points on S0 from a uniform grid.
//
// Every piece of phi maps affinely into one original triangle T, and its corners land on
// the boundary of T (a corner is an original vertex, i.e. a corner of T, or an edge
// crossing, a point on an edge of T). The pieces mapping into T tile it (phi is
// bijective), usually one to a few of them. So a point beta of T is located by testing
// T's pieces one after the other: lambda = M_q^-1 beta, where the columns of M_q are the
// piece corners' exact coordinates in T (from the node kinds, the matrix PhiEvaluator
// uses in the other direction); the point is in piece q if min(lambda) >= 0, and its
// coarse barycentrics are A_q lambda, A_q's columns being the corners' node_barycentric.
// The same rules as the forward evaluator decide points on piece edges (the first piece,
// in increasing piece index, that contains the point) and points a rounding error
// outside (the piece with the largest min(lambda), lambda clamped and renormalised). For
// the identity parametrization M_q = A_q = I and the inverse returns beta bit for bit.
//
// Closest points: a uniform grid over the bounding box of S0 whose cells list the
// triangles that may meet them (bounding box and plane tests, conservative). A query
// visits cells in growing cubic shells around its own cell, skips cells farther than the
// best distance found so far, and stops when a whole shell is farther. A point on or near
// S0 is answered from its own cell. The closest point on a triangle is Ericson's
// region-based computation (Real-Time Collision Detection, 2005, §5.1.5), which returns
// barycentric coordinates with exact zeros on edges and exact unit vectors at corners.
// The winner is the smallest (squared distance, triangle index): the search order cannot
// change it, so neither can the thread count.

#include "bpm/phi_inverse.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>

#include "phi_corner_code.h"

namespace bpm {

namespace {

using detail::Mat3;

bool finite(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

// Runs f(i) for i in [0, n) on `threads` threads, in blocks of consecutive queries taken
// in turn (each query is independent, so the split does not change any result).
template <class F>
void parallel_for(size_t n, int threads, const F& f) {
    if (threads == 0) threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    constexpr size_t block = size_t(1) << 13;
    const size_t blocks = (n + block - 1) / block;
    threads = static_cast<int>(std::min<size_t>(static_cast<size_t>(threads), std::max<size_t>(1, blocks)));
    std::atomic<size_t> next{0};
    const auto work = [&]() {
        for (size_t b = next.fetch_add(1); b < blocks; b = next.fetch_add(1)) {
            const size_t end = std::min(n, (b + 1) * block);
            for (size_t i = b * block; i < end; ++i) f(i);
        }
    };
    if (threads == 1) {
        work();
        return;
    }
    std::vector<std::thread> pool;
    for (int k = 1; k < threads; ++k) pool.emplace_back(work);
    work();
    for (std::thread& th : pool) th.join();
}

// Closest point to p on triangle (a, b, c) (Ericson §5.1.5): its barycentric coordinates
// (u, v, w) with exact zeros outside the feature it lies on, and the squared distance.
// A degenerate triangle gives an infinite distance (never chosen) unless its closest
// feature is a vertex or an edge, which are still well-defined.
double closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, Vec3& bary) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    const auto result = [&](double u, double v, double w) {
        bary = {u, v, w};
        const Vec3 x = barycentric_point(a, b, c, bary);
        const Vec3 d = p - x;
        return dot(d, d);
    };
    if (d1 <= 0 && d2 <= 0) return result(1, 0, 0);
    const Vec3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return result(0, 1, 0);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double v = d1 / (d1 - d3);
        return result(1 - v, v, 0);
    }
    const Vec3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return result(0, 0, 1);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double w = d2 / (d2 - d6);
        return result(1 - w, 0, w);
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return result(0, 1 - w, w);
    }
    const double sum = va + vb + vc;
    if (!(sum > 0) || !std::isfinite(sum)) return std::numeric_limits<double>::infinity();
    const double denom = 1 / sum;
    const double v = vb * denom, w = vc * denom;
    return result(1 - v - w, v, w);
}

}  // namespace

// One piece as seen from its original triangle.
struct InversePiece {
    Mat3 to_piece;   // original barycentrics -> piece barycentrics (inverse of the corner matrix)
    Mat3 to_coarse;  // piece barycentrics -> coarse barycentrics (column k: corner k's node_barycentric)
    int32_t coarse_triangle;
};

struct PhiInverse::Impl {
    const Parametrization& p;
    // Pieces grouped by original triangle (CSR), in increasing global piece index.
    std::vector<int64_t> piece_start;  // #S0.T + 1
    std::vector<InversePiece> pieces;  // #P

    // Closest-point grid.
    std::vector<std::array<Vec3, 3>> corners;  // #S0.T corner positions
    Vec3 lo{0, 0, 0};
    double h = 1, inv_h = 1;
    int32_t dims[3] = {1, 1, 1};
    std::vector<int64_t> cell_start;   // #cells + 1
    std::vector<int32_t> cell_tris;

    explicit Impl(const Parametrization& param) : p(param) {
        check_indexable();
        build_pieces();
        build_grid();
    }

    void check_indexable() const {
        const auto bad = [](const std::string& what) {
            throw std::invalid_argument("PhiInverse: inconsistent parametrization: " + what);
        };
        const size_t nt = static_cast<size_t>(p.num_coarse_triangles());
        if (p.node_offsets.size() != nt + 1 || p.piece_offsets.size() != nt + 1)
            bad("node_offsets / piece_offsets do not have #coarse triangles + 1 entries");
        if (p.piece_offsets.back() != p.num_pieces() || p.node_offsets.back() != p.num_nodes())
            bad("the last offset is not the number of pieces / nodes");
        if (p.piece_original_triangle.size() != p.pieces.size()) bad("piece_original_triangle has the wrong length");
        if (p.node_barycentric.size() != p.node_kind.size() || p.node_image.size() != p.node_kind.size() ||
            p.node_original_vertex.size() != p.node_kind.size() || p.node_original_edge.size() != p.node_kind.size() ||
            p.node_edge_parameter.size() != p.node_kind.size())
            bad("the node arrays differ in length");
        for (size_t t = 0; t < nt; ++t) {
            const int64_t n0 = p.node_offsets[t], n1 = p.node_offsets[t + 1];
            if (n0 > n1 || p.piece_offsets[t] > p.piece_offsets[t + 1]) bad("offsets decrease");
            for (int64_t q = p.piece_offsets[t]; q < p.piece_offsets[t + 1]; ++q)
                for (int32_t c : p.pieces[static_cast<size_t>(q)])
                    if (c < 0 || c >= n1 - n0) bad("piece " + std::to_string(q) + " has a corner outside its node range");
        }
        const int32_t no = p.original.num_triangles();
        for (size_t q = 0; q < p.pieces.size(); ++q)
            if (p.piece_original_triangle[q] < 0 || p.piece_original_triangle[q] >= no)
                bad("piece " + std::to_string(q) + " maps into original triangle " +
                    std::to_string(p.piece_original_triangle[q]) + " of " + std::to_string(no));
        for (const Tri& tri : p.original.triangles)
            for (int32_t v : tri)
                if (v < 0 || v >= p.original.num_vertices()) bad("an original triangle has a vertex index out of range");
    }

    void build_pieces() {
        const size_t no = static_cast<size_t>(p.original.num_triangles());
        piece_start.assign(no + 1, 0);
        for (int32_t T : p.piece_original_triangle) ++piece_start[static_cast<size_t>(T) + 1];
        for (size_t T = 0; T < no; ++T) piece_start[T + 1] += piece_start[T];
        std::vector<int64_t> fill(piece_start.begin(), piece_start.end() - 1);
        pieces.resize(p.pieces.size());
        for (int32_t t = 0; t < p.num_coarse_triangles(); ++t) {
            const int64_t nb = p.node_offsets[static_cast<size_t>(t)];
            for (int64_t q = p.piece_offsets[static_cast<size_t>(t)]; q < p.piece_offsets[static_cast<size_t>(t) + 1];
                 ++q) {
                const Tri& piece = p.pieces[static_cast<size_t>(q)];
                InversePiece& r =
                    pieces[static_cast<size_t>(fill[static_cast<size_t>(p.piece_original_triangle[static_cast<size_t>(q)])]++)];
                r.coarse_triangle = t;
                const Mat3 m = detail::to_original_matrix(detail::corner_code(p, nb, piece, q));
                // Inverse of m: rows are (c1 x c2, c2 x c0, c0 x c1) / det for columns c_k
                // (as PhiEvaluator inverts its matrix; exact for the identity).
                const Vec3 c0{m[0], m[3], m[6]}, c1{m[1], m[4], m[7]}, c2{m[2], m[5], m[8]};
                const Vec3 r0 = cross(c1, c2), r1 = cross(c2, c0), r2 = cross(c0, c1);
                const double det = dot(c0, r0);
                if (det == 0 || !std::isfinite(det)) {
                    // A piece with a degenerate image covers no area of T: every point
                    // looks far outside it.
                    r.to_piece.fill(-1.0);
                } else {
                    const double inv = 1.0 / det;
                    for (int k = 0; k < 3; ++k) {
                        r.to_piece[static_cast<size_t>(k)] = r0[k] * inv;
                        r.to_piece[static_cast<size_t>(3 + k)] = r1[k] * inv;
                        r.to_piece[static_cast<size_t>(6 + k)] = r2[k] * inv;
                    }
                }
                for (int k = 0; k < 3; ++k) {
                    const Vec3& b = p.node_barycentric[static_cast<size_t>(nb + piece[k])];
                    for (int i = 0; i < 3; ++i) r.to_coarse[static_cast<size_t>(3 * i + k)] = b[i];
                }
            }
        }
    }

    void build_grid() {
        const size_t no = static_cast<size_t>(p.original.num_triangles());
        corners.resize(no);
        if (no == 0) {
            cell_start.assign(2, 0);
            return;
        }
        Vec3 hi;
        for (int i = 0; i < 3; ++i) {
            lo[i] = std::numeric_limits<double>::infinity();
            hi[i] = -std::numeric_limits<double>::infinity();
        }
        double extent_sum = 0;
        for (size_t T = 0; T < no; ++T) {
            for (int k = 0; k < 3; ++k) {
                corners[T][k] = p.original.vertices[static_cast<size_t>(p.original.triangles[T][k])];
                for (int i = 0; i < 3; ++i) {
                    lo[i] = std::min(lo[i], corners[T][k][i]);
                    hi[i] = std::max(hi[i], corners[T][k][i]);
                }
            }
            double e = 0;
            for (int i = 0; i < 3; ++i)
                e = std::max(e, std::max({corners[T][0][i], corners[T][1][i], corners[T][2][i]}) -
                                    std::min({corners[T][0][i], corners[T][1][i], corners[T][2][i]}));
            extent_sum += e;
        }
        for (int i = 0; i < 3; ++i)
            if (!std::isfinite(lo[i]) || !std::isfinite(hi[i]))
                throw std::invalid_argument("PhiInverse: the original surface has a non-finite coordinate");
        // Cells about as large as a triangle: a point on S0 meets a few triangles in its
        // cell. The dense grid is capped at 8 cells per triangle (a surface fills a thin
        // layer of its bounding box), enlarging the cells if needed.
        const double diag = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 0.0});
        h = extent_sum / static_cast<double>(no);
        if (!(h > 0)) h = diag > 0 ? diag : 1.0;
        const double max_cells = 8.0 * static_cast<double>(no) + 64;
        for (;;) {
            double cells = 1;
            for (int i = 0; i < 3; ++i) cells *= std::max(1.0, std::ceil((hi[i] - lo[i]) / h));
            if (cells <= max_cells) break;
            h *= std::cbrt(cells / max_cells) * 1.01;
        }
        inv_h = 1 / h;
        for (int i = 0; i < 3; ++i)
            dims[i] = static_cast<int32_t>(std::max(1.0, std::ceil((hi[i] - lo[i]) / h)));
        const size_t ncells = static_cast<size_t>(dims[0]) * static_cast<size_t>(dims[1]) * static_cast<size_t>(dims[2]);
        // Two passes (count, fill) over the same conservative cell test.
        cell_start.assign(ncells + 1, 0);
        for (int pass = 0; pass < 2; ++pass) {
            std::vector<int64_t> fill;
            if (pass == 1) {
                for (size_t c = 0; c < ncells; ++c) cell_start[c + 1] += cell_start[c];
                cell_tris.resize(static_cast<size_t>(cell_start[ncells]));
                fill.assign(cell_start.begin(), cell_start.end() - 1);
            }
            for (size_t T = 0; T < no; ++T)
                for_cells_of(corners[T], [&](size_t c) {
                    if (pass == 0)
                        ++cell_start[c + 1];
                    else
                        cell_tris[static_cast<size_t>(fill[c]++)] = static_cast<int32_t>(T);
                });
        }
    }

    int32_t cell_coordinate(double x, int axis) const {
        const double f = (x - lo[axis]) * inv_h;
        // NaN-safe: a comparison with NaN is false, which selects 0.
        return f >= 0 ? std::min(static_cast<int32_t>(f), dims[axis] - 1) : 0;
    }

    size_t cell_index(int32_t i, int32_t j, int32_t k) const {
        return (static_cast<size_t>(i) * static_cast<size_t>(dims[1]) + static_cast<size_t>(j)) *
                   static_cast<size_t>(dims[2]) +
               static_cast<size_t>(k);
    }

    // Calls f(cell) for every cell the triangle may meet: the cells of its bounding box
    // (widened by a relative hair against rounding) whose box the triangle's plane
    // passes through or near.
    template <class F>
    void for_cells_of(const std::array<Vec3, 3>& x, const F& f) const {
        int32_t c0[3], c1[3];
        for (int i = 0; i < 3; ++i) {
            const double mn = std::min({x[0][i], x[1][i], x[2][i]}), mx = std::max({x[0][i], x[1][i], x[2][i]});
            const double slack = 1e-9 * h;
            c0[i] = cell_coordinate(mn - slack, i);
            c1[i] = cell_coordinate(mx + slack, i);
        }
        const Vec3 n = cross(x[1] - x[0], x[2] - x[0]);
        const double nn = norm(n);
        for (int32_t i = c0[0]; i <= c1[0]; ++i)
            for (int32_t j = c0[1]; j <= c1[1]; ++j)
                for (int32_t k = c0[2]; k <= c1[2]; ++k) {
                    if (nn > 0) {
                        const Vec3 center{lo[0] + (i + 0.5) * h, lo[1] + (j + 0.5) * h, lo[2] + (k + 0.5) * h};
                        const double reach = 0.5 * h * (std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2]));
                        if (std::abs(dot(n, center - x[0])) > reach + 1e-9 * h * nn) continue;
                    }
                    f(cell_index(i, j, k));
                }
    }

    // The closest point of S0 to q: triangle, barycentrics, squared distance.
    int32_t closest(const Vec3& q, Vec3& bary, double& best_d2) const {
        const int32_t c[3] = {cell_coordinate(q[0], 0), cell_coordinate(q[1], 1), cell_coordinate(q[2], 2)};
        best_d2 = std::numeric_limits<double>::infinity();
        int32_t best = -1;
        Vec3 b;
        const auto visit = [&](int32_t i, int32_t j, int32_t k) {
            // Squared distance from q to the cell's box: skip cells farther than the best.
            double d2 = 0;
            const int32_t ijk[3] = {i, j, k};
            for (int a = 0; a < 3; ++a) {
                const double x0 = lo[a] + ijk[a] * h, x1 = x0 + h;
                const double d = q[a] < x0 ? x0 - q[a] : (q[a] > x1 ? q[a] - x1 : 0.0);
                d2 += d * d;
            }
            if (d2 > best_d2) return;
            const size_t cell = cell_index(i, j, k);
            for (int64_t e = cell_start[cell]; e < cell_start[cell + 1]; ++e) {
                const int32_t T = cell_tris[static_cast<size_t>(e)];
                const auto& x = corners[static_cast<size_t>(T)];
                const double d = closest_on_triangle(q, x[0], x[1], x[2], b);
                if (d < best_d2 || (d == best_d2 && T < best)) {
                    best_d2 = d;
                    best = T;
                    bary = b;
                }
            }
        };
        visit(c[0], c[1], c[2]);
        for (int32_t r = 1;; ++r) {
            // Every cell of shell r lies outside the block of shells < r; stop when q is
            // farther than the best from everything outside that block (and when the
            // block is the whole grid).
            double bound = std::numeric_limits<double>::infinity();
            bool more = false;
            for (int a = 0; a < 3; ++a) {
                if (c[a] - r >= 0) {
                    more = true;
                    bound = std::min(bound, std::max(0.0, q[a] - (lo[a] + (c[a] - r + 1) * h)));
                }
                if (c[a] + r < dims[a]) {
                    more = true;
                    bound = std::min(bound, std::max(0.0, lo[a] + (c[a] + r) * h - q[a]));
                }
            }
            if (!more || bound * bound > best_d2) break;
            const int32_t i0 = std::max(c[0] - r, 0), i1 = std::min(c[0] + r, dims[0] - 1);
            const int32_t j0 = std::max(c[1] - r, 0), j1 = std::min(c[1] + r, dims[1] - 1);
            const int32_t k0 = c[2] - r, k1 = c[2] + r;
            for (int32_t i = i0; i <= i1; ++i)
                for (int32_t j = j0; j <= j1; ++j) {
                    if (std::abs(i - c[0]) == r || std::abs(j - c[1]) == r) {
                        for (int32_t k = std::max(k0, 0); k <= std::min(k1, dims[2] - 1); ++k) visit(i, j, k);
                    } else {
                        if (k0 >= 0) visit(i, j, k0);
                        if (k1 < dims[2]) visit(i, j, k1);
                    }
                }
        }
        return best;
    }

    // The parameter point of the point (b0, b1, b2) of original triangle T.
    // \pre T in range and has pieces.
    SurfacePoint invert(int32_t T, double b0, double b1, double b2) const {
        const int64_t q0 = piece_start[static_cast<size_t>(T)], q1 = piece_start[static_cast<size_t>(T) + 1];
        int64_t best = -1;
        double best_min = -std::numeric_limits<double>::infinity();
        double l0 = 0, l1 = 0, l2 = 0;
        for (int64_t q = q0; q < q1; ++q) {
            const Mat3& m = pieces[static_cast<size_t>(q)].to_piece;
            const double x0 = m[0] * b0 + m[1] * b1 + m[2] * b2;
            const double x1 = m[3] * b0 + m[4] * b1 + m[5] * b2;
            const double x2 = m[6] * b0 + m[7] * b1 + m[8] * b2;
            const double mn = std::min(x0, std::min(x1, x2));
            if (mn > best_min || best < 0) {
                best_min = mn;
                best = q;
                l0 = x0, l1 = x1, l2 = x2;
                if (mn >= 0) break;
            }
        }
        if (best_min < 0) {
            // Outside by rounding (or a query outside the triangle): snap into the piece.
            l0 = std::max(l0, 0.0), l1 = std::max(l1, 0.0), l2 = std::max(l2, 0.0);
            const double inv = 1.0 / (l0 + l1 + l2);
            l0 = inv * l0, l1 = inv * l1, l2 = inv * l2;
        }
        const InversePiece& r = pieces[static_cast<size_t>(best)];
        const Mat3& a = r.to_coarse;
        SurfacePoint out;
        out.triangle = r.coarse_triangle;
        out.barycentric = {a[0] * l0 + a[1] * l1 + a[2] * l2, a[3] * l0 + a[4] * l1 + a[5] * l2,
                           a[6] * l0 + a[7] * l1 + a[8] * l2};
        return out;
    }

    void check_original(const OriginalPoint& x) const {
        if (x.triangle < 0 || x.triangle >= p.original.num_triangles())
            throw std::out_of_range("PhiInverse::from_original: original triangle " + std::to_string(x.triangle) +
                                    " outside [0, " + std::to_string(p.original.num_triangles()) + ")");
        if (!finite(x.barycentric))
            throw std::invalid_argument("PhiInverse::from_original: non-finite barycentric coordinate");
        if (piece_start[static_cast<size_t>(x.triangle)] == piece_start[static_cast<size_t>(x.triangle) + 1])
            throw std::invalid_argument("PhiInverse::from_original: no piece of phi maps into original triangle " +
                                        std::to_string(x.triangle));
    }

    void check_position(const Vec3& y) const {
        if (!finite(y)) throw std::invalid_argument("PhiInverse::from_position: non-finite coordinate");
        if (p.original.triangles.empty())
            throw std::invalid_argument("PhiInverse::from_position: the original surface has no triangles");
    }

    PhiInverseSample sample(const Vec3& y) const {
        PhiInverseSample s;
        double d2 = 0;
        s.original.triangle = closest(y, s.original.barycentric, d2);
        const auto& x = corners[static_cast<size_t>(s.original.triangle)];
        s.foot = barycentric_point(x[0], x[1], x[2], s.original.barycentric);
        s.distance = std::sqrt(d2);
        if (piece_start[static_cast<size_t>(s.original.triangle)] ==
            piece_start[static_cast<size_t>(s.original.triangle) + 1])
            throw std::invalid_argument("PhiInverse::from_position: no piece of phi maps into original triangle " +
                                        std::to_string(s.original.triangle));
        const Vec3& b = s.original.barycentric;
        s.point = invert(s.original.triangle, b[0], b[1], b[2]);
        return s;
    }

    SurfacePoint point(const Vec3& y) const {
        Vec3 b;
        double d2 = 0;
        const int32_t T = closest(y, b, d2);
        if (piece_start[static_cast<size_t>(T)] == piece_start[static_cast<size_t>(T) + 1]) return SurfacePoint{};
        return invert(T, b[0], b[1], b[2]);
    }
};

PhiInverse::PhiInverse(const Parametrization& param) : impl_(new Impl(param)) {}
PhiInverse::~PhiInverse() { delete impl_; }

SurfacePoint PhiInverse::from_original(const OriginalPoint& x) const {
    impl_->check_original(x);
    return impl_->invert(x.triangle, x.barycentric[0], x.barycentric[1], x.barycentric[2]);
}

PhiInverseSample PhiInverse::from_position(const Vec3& position) const {
    impl_->check_position(position);
    return impl_->sample(position);
}

void PhiInverse::from_original(const std::vector<OriginalPoint>& points, std::vector<SurfacePoint>& out,
                               int threads) const {
    if (threads < 0) throw std::invalid_argument("PhiInverse::from_original: threads must be >= 0");
    for (const OriginalPoint& x : points) impl_->check_original(x);
    out.resize(points.size());
    parallel_for(points.size(), threads, [&](size_t i) {
        const OriginalPoint& x = points[i];
        out[i] = impl_->invert(x.triangle, x.barycentric[0], x.barycentric[1], x.barycentric[2]);
    });
}

void PhiInverse::from_position(const std::vector<Vec3>& positions, std::vector<PhiInverseSample>& out,
                               int threads) const {
    if (threads < 0) throw std::invalid_argument("PhiInverse::from_position: threads must be >= 0");
    for (const Vec3& y : positions) impl_->check_position(y);
    out.resize(positions.size());
    // A missing piece (inconsistent input) throws from a worker; catch it per thread.
    std::atomic<bool> failed{false};
    parallel_for(positions.size(), threads, [&](size_t i) {
        if (failed.load(std::memory_order_relaxed)) return;
        try {
            out[i] = impl_->sample(positions[i]);
        } catch (...) {
            failed = true;
        }
    });
    if (failed)
        for (const Vec3& y : positions) impl_->sample(y);  // rethrows the first failure in query order
}

void PhiInverse::from_position(const std::vector<Vec3>& positions, std::vector<SurfacePoint>& out,
                               int threads) const {
    if (threads < 0) throw std::invalid_argument("PhiInverse::from_position: threads must be >= 0");
    for (const Vec3& y : positions) impl_->check_position(y);
    out.resize(positions.size());
    std::atomic<bool> failed{false};
    parallel_for(positions.size(), threads, [&](size_t i) {
        out[i] = impl_->point(positions[i]);
        if (!out[i].valid()) failed.store(true, std::memory_order_relaxed);
    });
    if (failed)
        for (const Vec3& y : positions) impl_->sample(y);  // throws for the first failure in query order
}

}  // namespace bpm
