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
// Closest points: a uniform grid of cells about half as large as a typical original
// triangle, stored block-sparse (blocks of 4x4x4 cells; a dense table over the bounding
// box points to the blocks the surface meets, each with its cells' triangle lists). Cells
// list the triangles that may meet them (bounding box and plane tests, conservative). A
// query visits cells in growing cubic shells around its own cell, skips cells farther
// than the best distance found so far, and stops when a whole shell is farther. A point on
// or near S0 is answered from its own cell: the distance to each candidate's plane (a
// lower bound) is computed first and the candidate with the smallest is tested first,
// which for a point on S0 usually rules the others out. The closest point on a triangle is
// Ericson's region-based computation (Real-Time Collision Detection, 2005, §5.1.5), which
// returns barycentric coordinates with exact zeros on edges and exact unit vectors at
// corners. The winner is the smallest (squared distance, triangle index).
//
// Throughput: in random order both queries are bound by memory latency (perf on
// armadillo at 10%: the loads of grid cells, triangle planes and corners were the hot
// instructions, ~1 us per position query). So the triangles are renumbered internally in
// grid order (the data of neighbouring triangles is adjacent), and the batched calls
// visit their queries grouped like PhiEvaluator's: in chunks, counting-sorted by grid
// block (positions) or by internal triangle number / 64 (original points). Each query is
// still computed on its own, so neither the grouping nor the thread count changes a
// result.

#include "bpm/phi_inverse.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/number_text.h"
#include "phi/grouped_queries.h"
#include "phi/phi_corner_code.h"

namespace bpm {

namespace {

using detail::Mat3;

bool finite(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

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

namespace {

constexpr int kBlock = 4;  // cells per block side
constexpr int kBlockCells = kBlock * kBlock * kBlock;
constexpr int kTriangleGroup = 64;  // original points are grouped by internal triangle / 64
// How far (per axis, from S0's bounding box) a from_position query may be: 3 * 1e300
// squared distances stay finite; beyond, every distance would overflow to infinity.
constexpr double kMaxQueryOffset = 1e150;

}  // namespace

struct PhiInverse::Impl {
    const Parametrization& p;
    // Original triangles are renumbered internally in grid order (see the file comment).
    std::vector<int32_t> order;  // internal -> original triangle
    std::vector<int32_t> rank;   // original triangle -> internal
    // Pieces grouped by internal triangle (CSR), in increasing global piece index.
    std::vector<int64_t> piece_start;  // #S0.T + 1
    std::vector<InversePiece> pieces;  // #P

    // Closest-point grid.
    struct Plane {
        Vec3 normal;    // unit normal (zero for a degenerate triangle)
        double offset;  // dot(normal, corner 0)
    };
    std::vector<std::array<Vec3, 3>> corners;  // #S0.T corner positions, by internal number
    std::vector<Plane> planes;                 // #S0.T, a cheap lower bound of the distance
    Vec3 lo{0, 0, 0};
    Vec3 hi_box{0, 0, 0};  // with lo, the bounding box of S0
    double h = 1, inv_h = 1;
    int32_t dims[3] = {1, 1, 1};   // cells per axis
    int32_t bdims[3] = {1, 1, 1};  // blocks per axis
    std::vector<int32_t> block_id;       // dense over the blocks: -1 or the index of a stored block
    std::vector<uint32_t> block_cells;   // per stored block kBlockCells + 1 offsets into cell_tris
    std::vector<int32_t> cell_tris;      // internal triangle numbers, ascending per cell

    explicit Impl(const Parametrization& param) : p(param) {
        check_indexable();
        build_grid();
        build_pieces();
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

    // \pre build_grid() (the internal numbering).
    void build_pieces() {
        const size_t no = static_cast<size_t>(p.original.num_triangles());
        piece_start.assign(no + 1, 0);
        for (int32_t T : p.piece_original_triangle) ++piece_start[static_cast<size_t>(rank[static_cast<size_t>(T)]) + 1];
        for (size_t u = 0; u < no; ++u) piece_start[u + 1] += piece_start[u];
        std::vector<int64_t> fill(piece_start.begin(), piece_start.end() - 1);
        pieces.resize(p.pieces.size());
        for (int32_t t = 0; t < p.num_coarse_triangles(); ++t) {
            const int64_t nb = p.node_offsets[static_cast<size_t>(t)];
            for (int64_t q = p.piece_offsets[static_cast<size_t>(t)]; q < p.piece_offsets[static_cast<size_t>(t) + 1];
                 ++q) {
                const Tri& piece = p.pieces[static_cast<size_t>(q)];
                const int32_t u = rank[static_cast<size_t>(p.piece_original_triangle[static_cast<size_t>(q)])];
                InversePiece& r = pieces[static_cast<size_t>(fill[static_cast<size_t>(u)]++)];
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
        order.resize(no);
        rank.resize(no);
        corners.resize(no);
        planes.resize(no);
        block_id.assign(1, -1);
        block_cells.clear();
        cell_tris.clear();
        if (no == 0) return;
        Vec3 hi;
        for (int i = 0; i < 3; ++i) {
            lo[i] = std::numeric_limits<double>::infinity();
            hi[i] = -std::numeric_limits<double>::infinity();
        }
        double extent_sum = 0;
        std::vector<std::array<Vec3, 3>> x(no);
        for (size_t T = 0; T < no; ++T) {
            for (int k = 0; k < 3; ++k) {
                x[T][k] = p.original.vertices[static_cast<size_t>(p.original.triangles[T][k])];
                for (int i = 0; i < 3; ++i) {
                    lo[i] = std::min(lo[i], x[T][k][i]);
                    hi[i] = std::max(hi[i], x[T][k][i]);
                }
            }
            double e = 0;
            for (int i = 0; i < 3; ++i)
                e = std::max(e, std::max({x[T][0][i], x[T][1][i], x[T][2][i]}) -
                                    std::min({x[T][0][i], x[T][1][i], x[T][2][i]}));
            extent_sum += e;
        }
        for (int i = 0; i < 3; ++i)
            if (!std::isfinite(lo[i]) || !std::isfinite(hi[i]))
                throw std::invalid_argument("PhiInverse: the original surface has a non-finite coordinate");
        hi_box = hi;
        // Cells half as large as a typical triangle: a point of S0 then finds a few
        // triangles in its cell (measured on armadillo at 10%: cells as large as a
        // triangle held ten). The dense block table is kept below 4 entries per triangle
        // (a surface fills a thin layer of its bounding box), enlarging the cells if needed.
        const double diag = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 0.0});
        h = 0.5 * extent_sum / static_cast<double>(no);
        if (!(h > 0)) h = diag > 0 ? diag : 1.0;
        const double max_blocks = 4.0 * static_cast<double>(no) + 4096;
        for (;;) {
            double blocks = 1;
            for (int i = 0; i < 3; ++i) blocks *= std::max(1.0, std::ceil((hi[i] - lo[i]) / (h * kBlock)));
            if (blocks <= max_blocks) break;
            h *= std::cbrt(blocks / max_blocks) * 1.01;
        }
        inv_h = 1 / h;
        for (int i = 0; i < 3; ++i) {
            dims[i] = static_cast<int32_t>(std::max(1.0, std::ceil((hi[i] - lo[i]) * inv_h)));
            bdims[i] = (dims[i] + kBlock - 1) / kBlock;
        }
        // Internal numbering: triangles sorted by the cell of their centroid, block first.
        std::vector<std::pair<uint64_t, int32_t>> by_cell(no);
        for (size_t T = 0; T < no; ++T) {
            int32_t c[3];
            for (int i = 0; i < 3; ++i) c[i] = cell_coordinate((x[T][0][i] + x[T][1][i] + x[T][2][i]) / 3, i);
            by_cell[T] = {(static_cast<uint64_t>(block_of(c[0], c[1], c[2])) << 8) | local_of(c[0], c[1], c[2]),
                          static_cast<int32_t>(T)};
        }
        std::sort(by_cell.begin(), by_cell.end());
        for (size_t u = 0; u < no; ++u) {
            const int32_t T = by_cell[u].second;
            order[u] = T;
            rank[static_cast<size_t>(T)] = static_cast<int32_t>(u);
            corners[u] = x[static_cast<size_t>(T)];
            const Vec3 n = triangle_normal(corners[u][0], corners[u][1], corners[u][2]);
            planes[u] = Plane{n, dot(n, corners[u][0])};
        }
        // (block, cell in block, internal triangle), sorted.
        struct Entry {
            uint64_t cell;  // block << 8 | local
            int32_t u;
            bool operator<(const Entry& o) const { return cell != o.cell ? cell < o.cell : u < o.u; }
        };
        std::vector<Entry> entries;
        for (size_t u = 0; u < no; ++u)
            for_cells_of(corners[u], [&](int32_t i, int32_t j, int32_t k) {
                entries.push_back({(static_cast<uint64_t>(block_of(i, j, k)) << 8) | local_of(i, j, k),
                                   static_cast<int32_t>(u)});
            });
        std::sort(entries.begin(), entries.end());
        if (entries.size() >= (size_t(1) << 32))
            throw std::invalid_argument("PhiInverse: the original surface is too large for the closest-point grid");
        const size_t nblocks = static_cast<size_t>(bdims[0]) * static_cast<size_t>(bdims[1]) *
                               static_cast<size_t>(bdims[2]);
        block_id.assign(nblocks, -1);
        cell_tris.resize(entries.size());
        for (size_t e = 0; e < entries.size(); ++e) {
            cell_tris[e] = entries[e].u;
            const size_t block = static_cast<size_t>(entries[e].cell >> 8);
            const int local = static_cast<int>(entries[e].cell & 0xff);
            if (block_id[block] < 0) {
                // A new block: its offsets all start at e; closed when the next one opens.
                block_id[block] = static_cast<int32_t>(block_cells.size() / (kBlockCells + 1));
                block_cells.insert(block_cells.end(), kBlockCells + 1, static_cast<uint32_t>(e));
            }
            uint32_t* off = &block_cells[block_cells.size() - (kBlockCells + 1)];
            for (int l = local + 1; l <= kBlockCells; ++l) off[l] = static_cast<uint32_t>(e + 1);
        }
    }

    int32_t cell_coordinate(double x, int axis) const {
        const double f = (x - lo[axis]) * inv_h;
        // NaN-safe: a comparison with NaN is false, which selects 0.
        return f >= 0 ? static_cast<int32_t>(std::min(f, static_cast<double>(dims[axis] - 1))) : 0;
    }

    size_t block_of(int32_t i, int32_t j, int32_t k) const {
        return (static_cast<size_t>(i / kBlock) * static_cast<size_t>(bdims[1]) + static_cast<size_t>(j / kBlock)) *
                   static_cast<size_t>(bdims[2]) +
               static_cast<size_t>(k / kBlock);
    }
    static uint32_t local_of(int32_t i, int32_t j, int32_t k) {
        return static_cast<uint32_t>(((i % kBlock) * kBlock + (j % kBlock)) * kBlock + (k % kBlock));
    }

    // Calls f(i, j, k) for every cell the triangle may meet: the cells of its bounding box
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
        const double reach = 0.5 * h * (std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2])) + 1e-9 * h * nn;
        for (int32_t i = c0[0]; i <= c1[0]; ++i)
            for (int32_t j = c0[1]; j <= c1[1]; ++j)
                for (int32_t k = c0[2]; k <= c1[2]; ++k) {
                    if (nn > 0) {
                        const Vec3 center{lo[0] + (i + 0.5) * h, lo[1] + (j + 0.5) * h, lo[2] + (k + 0.5) * h};
                        if (std::abs(dot(n, center - x[0])) > reach) continue;
                    }
                    f(i, j, k);
                }
    }

    // The grid block of a query (for grouping).
    size_t block_of_position(const Vec3& q) const {
        return block_of(cell_coordinate(q[0], 0), cell_coordinate(q[1], 1), cell_coordinate(q[2], 2));
    }

    // The closest point of S0 to q: internal triangle number, barycentrics, squared distance.
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
            const int32_t id = block_id[block_of(i, j, k)];
            if (id < 0) return;
            const uint32_t* off = &block_cells[static_cast<size_t>(id) * (kBlockCells + 1) + local_of(i, j, k)];
            const int32_t* tris = cell_tris.data() + off[0];
            const uint32_t count = off[1] - off[0];
            // The distance to a triangle's plane is a lower bound of the distance to the
            // triangle and costs a dot product: bound every candidate, test the one with
            // the smallest bound first (for a point on S0, usually its own triangle, which
            // then rules the others out), then the rest whose bound is not above the best.
            constexpr uint32_t kMax = 32;
            double bound[kMax];
            uint32_t first = 0;
            const bool bounded = count <= kMax;
            if (bounded)
                for (uint32_t e = 0; e < count; ++e) {
                    const Plane& pl = planes[static_cast<size_t>(tris[e])];
                    const double d = dot(pl.normal, q) - pl.offset;
                    bound[e] = d * d;
                    if (bound[e] < bound[first]) first = e;
                }
            const auto test = [&](uint32_t e) {
                const int32_t u = tris[e];
                const auto& x = corners[static_cast<size_t>(u)];
                const double d = closest_on_triangle(q, x[0], x[1], x[2], b);
                // Ties go to the smaller original triangle number.
                if (d < best_d2 || (d == best_d2 && best >= 0 && order[static_cast<size_t>(u)] < order[static_cast<size_t>(best)])) {
                    best_d2 = d;
                    best = u;
                    bary = b;
                }
            };
            if (count > 0 && (!bounded || bound[first] <= best_d2)) test(first);
            for (uint32_t e = 0; e < count; ++e)
                if (e != first && (!bounded || bound[e] <= best_d2)) test(e);
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

    // The parameter point of the point (b0, b1, b2) of the triangle with internal number u.
    // \pre u in range and has pieces.
    SurfacePoint invert(int32_t u, double b0, double b1, double b2) const {
        const int64_t q0 = piece_start[static_cast<size_t>(u)], q1 = piece_start[static_cast<size_t>(u) + 1];
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

    bool has_pieces(int32_t u) const {
        return piece_start[static_cast<size_t>(u)] != piece_start[static_cast<size_t>(u) + 1];
    }

    void check_original(const OriginalPoint& x) const {
        if (x.triangle < 0 || x.triangle >= p.original.num_triangles())
            throw std::out_of_range("PhiInverse::from_original: original triangle " + std::to_string(x.triangle) +
                                    " outside [0, " + std::to_string(p.original.num_triangles()) + ")");
        if (!finite(x.barycentric))
            throw std::invalid_argument("PhiInverse::from_original: non-finite barycentric coordinate");
        if (!has_pieces(rank[static_cast<size_t>(x.triangle)])) no_pieces("from_original", x.triangle);
    }

    [[noreturn]] static void no_pieces(const char* call, int32_t T) {
        throw std::invalid_argument(std::string("PhiInverse::") + call +
                                    ": no piece of phi maps into original triangle " + std::to_string(T));
    }

    void check_position(const Vec3& y) const {
        if (!finite(y)) throw std::invalid_argument("PhiInverse::from_position: non-finite coordinate");
        if (p.original.triangles.empty())
            throw std::invalid_argument("PhiInverse::from_position: the original surface has no triangles");
        // Squared distances to S0 must not overflow (they would all be infinite, and no
        // triangle would be the closest): every coordinate difference to S0's bounding box
        // stays below kMaxQueryOffset, whose square, times 3, is far below DBL_MAX.
        for (int a = 0; a < 3; ++a)
            if (std::max(std::abs(y[a] - lo[a]), std::abs(y[a] - hi_box[a])) > kMaxQueryOffset)
                throw std::invalid_argument("PhiInverse::from_position: position (" + detail::round_trip_text(y[0]) + ", " +
                                            detail::round_trip_text(y[1]) + ", " + detail::round_trip_text(y[2]) +
                                            ") is too far from the original surface (more than 1e150 along an "
                                            "axis) for its distance to be computed in double precision");
    }

    SurfacePoint from_original(const OriginalPoint& x) const {
        return invert(rank[static_cast<size_t>(x.triangle)], x.barycentric[0], x.barycentric[1], x.barycentric[2]);
    }

    // Fills s; false if the closest triangle has no pieces (inconsistent input).
    bool sample(const Vec3& y, PhiInverseSample& s) const {
        double d2 = 0;
        Vec3& b = s.original.barycentric;
        const int32_t u = closest(y, b, d2);
        const auto& x = corners[static_cast<size_t>(u)];
        s.original.triangle = order[static_cast<size_t>(u)];
        s.foot = barycentric_point(x[0], x[1], x[2], b);
        s.distance = std::sqrt(d2);
        if (!has_pieces(u)) {
            s.point = SurfacePoint{};
            return false;
        }
        s.point = invert(u, b[0], b[1], b[2]);
        return true;
    }

    SurfacePoint point(const Vec3& y) const {
        Vec3 b;
        double d2 = 0;
        const int32_t u = closest(y, b, d2);
        if (!has_pieces(u)) return SurfacePoint{};
        return invert(u, b[0], b[1], b[2]);
    }
};

PhiInverse::PhiInverse(const Parametrization& param) : impl_(new Impl(param)) {}
PhiInverse::~PhiInverse() { delete impl_; }

SurfacePoint PhiInverse::from_original(const OriginalPoint& x) const {
    impl_->check_original(x);
    return impl_->from_original(x);
}

PhiInverseSample PhiInverse::from_position(const Vec3& position) const {
    impl_->check_position(position);
    PhiInverseSample s;
    if (!impl_->sample(position, s)) Impl::no_pieces("from_position", s.original.triangle);
    return s;
}

namespace {

// The batched calls (see the file comment): the argument checks of `call`, then
// eval(i) for every query in grouped order (key(i) < nkeys), with the query's input and
// output prefetched ahead. Returns whether some eval(i) returned false.
template <class Query, class Result, class Check, class Key, class Eval>
bool run_batch(const char* call, const std::vector<Query>& queries, std::vector<Result>& out, int threads,
               const Check& check, size_t nkeys, const Key& key, const Eval& eval) {
    if (threads < 0) throw std::invalid_argument(std::string("PhiInverse::") + call + ": threads must be >= 0");
    for (const Query& q : queries) check(q);
    out.resize(queries.size());
    std::atomic<bool> failed{false};
    detail::for_each_grouped(
        queries.size(), nkeys, 16, threads, key,
        [&](size_t, size_t i) {
            if (!eval(i)) failed.store(true, std::memory_order_relaxed);
        },
        [&](size_t i) {
            detail::prefetch_object<false>(&queries[i]);
            detail::prefetch_object<true>(&out[i]);
        });
    return failed;
}

}  // namespace

void PhiInverse::from_original(const std::vector<OriginalPoint>& points, std::vector<SurfacePoint>& out,
                               int threads) const {
    const Impl& impl = *impl_;
    run_batch(
        "from_original", points, out, threads, [&](const OriginalPoint& x) { impl.check_original(x); },
        static_cast<size_t>(impl.p.original.num_triangles() / kTriangleGroup + 1),
        [&](size_t i) { return static_cast<size_t>(impl.rank[static_cast<size_t>(points[i].triangle)] / kTriangleGroup); },
        [&](size_t i) {
            out[i] = impl.from_original(points[i]);
            return true;
        });
}

void PhiInverse::from_position(const std::vector<Vec3>& positions, std::vector<PhiInverseSample>& out,
                               int threads) const {
    const Impl& impl = *impl_;
    const bool failed = run_batch(
        "from_position", positions, out, threads, [&](const Vec3& y) { impl.check_position(y); },
        impl.block_id.size(), [&](size_t i) { return impl.block_of_position(positions[i]); },
        [&](size_t i) { return impl.sample(positions[i], out[i]); });
    if (failed)
        for (const PhiInverseSample& s : out)  // the first failure in query order
            if (!s.point.valid()) Impl::no_pieces("from_position", s.original.triangle);
}

void PhiInverse::from_position(const std::vector<Vec3>& positions, std::vector<SurfacePoint>& out,
                               int threads) const {
    const Impl& impl = *impl_;
    const bool failed = run_batch(
        "from_position", positions, out, threads, [&](const Vec3& y) { impl.check_position(y); },
        impl.block_id.size(), [&](size_t i) { return impl.block_of_position(positions[i]); },
        [&](size_t i) {
            out[i] = impl.point(positions[i]);
            return out[i].valid();
        });
    if (failed)
        for (size_t i = 0; i < out.size(); ++i)  // the first failure in query order
            if (!out[i].valid()) from_position(positions[i]);
}

}  // namespace bpm
