// Evaluating phi by point location among the pieces of a coarse triangle.
//
// The paper (Krause & Sander §2.2.3) locates points with the randomized walk of Brown
// and Faigle. Here every coarse triangle gets a small uniform grid over its parameter
// triangle in (b1, b2) coordinates instead; each cell lists the pieces that overlap it.
// A query looks at one cell and tests its few candidates, which is branch-light,
// needs no adjacency between pieces and is the same cost for every point.
//
// Each piece has the inverse of the matrix whose columns are its corners' barycentric
// coordinates in the coarse triangle (multiplying the query's coarse barycentrics by it
// gives the query's barycentrics in the piece directly), kept in a compact array of its
// own because it is all a candidate test reads, and one record with everything the
// chosen piece's result needs (no pointer chasing through the per-node arrays): the
// corner images, the matrix taking piece barycentrics to barycentrics in the original
// triangle, and that triangle's normal. For the identity parametrization both matrices
// are exactly the identity, so phi reproduces the input point bit for bit.
//
// Throughput (bench/refine.py, results in bench/results/refine.md; bpm-bench-refine
// throughput): for large random batches the batched calls group the queries by coarse
// triangle in chunks and can use several threads. What limited them (perf, armadillo
// at 10%, ~200 ns per query) was not the point location but memory traffic around it:
// lambda was copied through the stack so that every query waited for the store buffer
// to drain, i.e. for the previous queries' cache-missing output stores; now the
// location works on scalars, the output lines (and the query's input) are prefetched a
// few queries ahead, and the grouping sorts 4-byte query indices instead of 32-byte
// records. Measured on the shared 2-core machine (10 million random points, the 10% and
// 1000-vertex files), per CPU second: about 4-6 -> 8.5-12 million PhiSample and
// 5.5-9 -> 9-13 million positions-only evaluations; results unchanged bit for bit.

#include "bpm/phi_evaluation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "phi/grouped_queries.h"
#include "phi/phi_corner_code.h"

namespace bpm {

namespace {

using detail::Mat3;

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

// Everything a query needs about one piece, in one place (a query touches one record
// per candidate piece and nothing else but the grid).
struct PieceRecord {
    Vec3 image[3];            // node_image of the corners
    Mat3 to_original;         // piece barycentrics -> original barycentrics (column k: corner k)
    Vec3 normal;              // unit normal of the original triangle
    int32_t original_triangle;
};

struct Grid {
    int64_t begin;  // index of the triangle's first entry in cell_start
    int32_t g;      // cells per side (g*g cells, row-major in (b1, b2))
};

struct PhiEvaluator::Impl {
    const Parametrization& p;
    std::vector<Mat3> to_piece;        // #P: coarse barycentrics -> piece barycentrics
                                       // (all a candidate test reads, kept apart: compact)
    std::vector<PieceRecord> pieces;   // #P: what the chosen piece's result needs
    std::vector<Grid> grids;           // #S.T
    std::vector<int64_t> cell_start;   // per triangle g*g+1 offsets into cell_pieces
    std::vector<int32_t> cell_pieces;  // global piece indices

    explicit Impl(const Parametrization& param) : p(param) { build(); }

    void build() {
        const int32_t nt = p.num_coarse_triangles();
        const auto& x = p.original.vertices;
        std::vector<Vec3> normals(p.original.triangles.size());
        for (size_t i = 0; i < normals.size(); ++i) {
            const Tri& tri = p.original.triangles[i];
            normals[i] = triangle_normal(x[static_cast<size_t>(tri[0])], x[static_cast<size_t>(tri[1])],
                                         x[static_cast<size_t>(tri[2])]);
        }
        pieces.resize(static_cast<size_t>(p.num_pieces()));
        to_piece.resize(static_cast<size_t>(p.num_pieces()));
        grids.resize(static_cast<size_t>(nt));
        for (int32_t t = 0; t < nt; ++t) {
            const int64_t nb = p.node_offsets[static_cast<size_t>(t)];
            const int64_t q0 = p.piece_offsets[static_cast<size_t>(t)], q1 = p.piece_offsets[static_cast<size_t>(t) + 1];
            const int64_t count = q1 - q0;
            // About two cells per piece area: mostly one or two candidates per cell (each
            // candidate that is tested and rejected costs a branch misprediction), grids
            // still small (measured on armadillo at 10%: 2 -> 4 cells per piece is ~20% faster).
            const int32_t g = static_cast<int32_t>(
                std::clamp(std::ceil(std::sqrt(4.0 * static_cast<double>(count))), 1.0, 1024.0));
            grids[static_cast<size_t>(t)] = Grid{static_cast<int64_t>(cell_start.size()), g};
            std::vector<std::vector<int32_t>> cells(static_cast<size_t>(g) * static_cast<size_t>(g));
            for (int64_t q = q0; q < q1; ++q) {
                const Tri& piece = p.pieces[static_cast<size_t>(q)];
                PieceRecord& record = pieces[static_cast<size_t>(q)];
                // Column k holds corner k's coordinates in the original triangle: a unit
                // vector for an original vertex (so that beta is exact for phi = identity),
                // 1 - s and s at the ends of the edge for an edge crossing.
                record.to_original = detail::to_original_matrix(detail::corner_code(p, nb, piece, q));
                for (int k = 0; k < 3; ++k) record.image[k] = p.node_image[static_cast<size_t>(nb + piece[k])];
                record.original_triangle = p.piece_original_triangle[static_cast<size_t>(q)];
                record.normal = normals[static_cast<size_t>(record.original_triangle)];
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

    // The piece containing `b`, and b's barycentrics (l0, l1, l2) in it. The candidates
    // of the cell are tested in list order (increasing piece index): the first one that
    // contains b wins (this decides points on piece edges), else the one b is least
    // outside of. Scalars instead of Vec3 temporaries keep lambda in registers: copying
    // the arrays through the stack (8-byte stores read back as 16-byte loads) made every
    // query wait for the store buffer, i.e. for the previous queries' output stores.
    int64_t locate(int32_t t, double b0, double b1, double b2, double& l0, double& l1, double& l2) const {
        const Grid& grid = grids[static_cast<size_t>(t)];
        const int32_t g = grid.g;
        // NaN-safe clamping: a comparison with NaN is false, which selects 0.
        const double fu = b1 * g, fv = b2 * g;
        const int32_t i = fu >= 0 ? std::min(static_cast<int32_t>(fu), g - 1) : 0;
        const int32_t j = fv >= 0 ? std::min(static_cast<int32_t>(fv), g - 1) : 0;
        const int64_t* cs = &cell_start[static_cast<size_t>(grid.begin + static_cast<int64_t>(i) * g + j)];
        const int32_t* candidate = cell_pieces.data() + cs[0];
        const int32_t* const candidates_end = cell_pieces.data() + cs[1];
        int64_t best = -1;
        double best_min = -std::numeric_limits<double>::infinity();
        double c0 = 0, c1 = 0, c2 = 0;
        for (; candidate != candidates_end; ++candidate) {
            const int32_t q = *candidate;
            const Mat3& m = to_piece[static_cast<size_t>(q)];
            const double x0 = m[0] * b0 + m[1] * b1 + m[2] * b2;
            const double x1 = m[3] * b0 + m[4] * b1 + m[5] * b2;
            const double x2 = m[6] * b0 + m[7] * b1 + m[8] * b2;
            const double mn = std::min(x0, std::min(x1, x2));
            if (mn >= 0) {
                l0 = x0, l1 = x1, l2 = x2;
                return q;
            }
            if (mn > best_min) {
                best_min = mn;
                best = q;
                c0 = x0, c1 = x1, c2 = x2;
            }
        }
        // On a piece edge, rounding may put the point a hair outside every candidate;
        // anything further out (a query outside the triangle, or a cell whose list
        // missed it) gets the piece it is least outside of among all pieces.
        if (!(best >= 0 && best_min >= -1e-9)) {
            const int64_t q0 = p.piece_offsets[static_cast<size_t>(t)];
            const int64_t q1 = p.piece_offsets[static_cast<size_t>(t) + 1];
            for (int64_t q = q0; q < q1; ++q) {
                const Mat3& m = to_piece[static_cast<size_t>(q)];
                const double x0 = m[0] * b0 + m[1] * b1 + m[2] * b2;
                const double x1 = m[3] * b0 + m[4] * b1 + m[5] * b2;
                const double x2 = m[6] * b0 + m[7] * b1 + m[8] * b2;
                const double mn = std::min(x0, std::min(x1, x2));
                if (mn > best_min) {
                    best_min = mn;
                    best = q;
                    c0 = x0, c1 = x1, c2 = x2;
                }
            }
        }
        if (best >= 0) l0 = c0, l1 = c1, l2 = c2;
        return best;
    }

    // The piece containing b (-1 for a coarse triangle without pieces) and b's
    // barycentrics in it, clamped into the piece.
    int64_t piece_of(int32_t t, const Vec3& b, double& l0, double& l1, double& l2) const {
        const int64_t q = locate(t, b[0], b[1], b[2], l0, l1, l2);
        if (q >= 0 && std::min(l0, std::min(l1, l2)) < 0) {
            // Outside by rounding (or a query outside the triangle): snap to the piece.
            l0 = std::max(l0, 0.0), l1 = std::max(l1, 0.0), l2 = std::max(l2, 0.0);
            const double sum = l0 + l1 + l2;
            const double inv = 1.0 / sum;
            l0 = inv * l0, l1 = inv * l1, l2 = inv * l2;
        }
        return q;
    }

    // barycentric_point(image[0], image[1], image[2], l), written out.
    static Vec3 interpolate(const PieceRecord& r, double l0, double l1, double l2) {
        return {l0 * r.image[0][0] + l1 * r.image[1][0] + l2 * r.image[2][0],
                l0 * r.image[0][1] + l1 * r.image[1][1] + l2 * r.image[2][1],
                l0 * r.image[0][2] + l1 * r.image[1][2] + l2 * r.image[2][2]};
    }

    Vec3 position(int32_t t, const Vec3& b) const {
        double l0 = 0, l1 = 0, l2 = 0;
        const int64_t q = piece_of(t, b, l0, l1, l2);
        if (q < 0) return Vec3{0, 0, 0};
        return interpolate(pieces[static_cast<size_t>(q)], l0, l1, l2);
    }

    PhiSample evaluate(int32_t t, const Vec3& b) const {
        double l0 = 0, l1 = 0, l2 = 0;
        const int64_t q = piece_of(t, b, l0, l1, l2);
        PhiSample out;
        if (q < 0) return out;  // coarse triangle without pieces: invalid input
        const PieceRecord& record = pieces[static_cast<size_t>(q)];
        out.position = interpolate(record, l0, l1, l2);
        out.original_triangle = record.original_triangle;
        // For original vertices this is l[k] * 1 plus zeros: exact.
        const Mat3& m = record.to_original;
        out.original_barycentric = {m[0] * l0 + m[1] * l1 + m[2] * l2, m[3] * l0 + m[4] * l1 + m[5] * l2,
                                    m[6] * l0 + m[7] * l1 + m[8] * l2};
        out.normal = record.normal;
        return out;
    }
};

PhiEvaluator::PhiEvaluator(const Parametrization& param) : impl_(new Impl(param)) {}
PhiEvaluator::~PhiEvaluator() { delete impl_; }

PhiSample PhiEvaluator::evaluate(int32_t coarse_triangle, const Vec3& barycentric) const {
    return impl_->evaluate(coarse_triangle, barycentric);
}

PhiSample PhiEvaluator::evaluate(const SurfacePoint& point) const {
    return impl_->evaluate(point.triangle, point.barycentric);
}

namespace {

// Queries given as two parallel lists (the original API).
struct ParallelQueries {
    const std::vector<int32_t>& triangles;
    const std::vector<Vec3>& barycentrics;
    ParallelQueries(const std::vector<int32_t>& t, const std::vector<Vec3>& b) : triangles(t), barycentrics(b) {
        if (t.size() != b.size())
            throw std::invalid_argument("PhiEvaluator::evaluate: triangles and barycentrics differ in length");
    }
    size_t size() const { return triangles.size(); }
    int32_t triangle(size_t i) const { return triangles[i]; }
    const Vec3& barycentric(size_t i) const { return barycentrics[i]; }
};

// Queries given as SurfacePoints.
struct PointQueries {
    const std::vector<SurfacePoint>& points;
    size_t size() const { return points.size(); }
    int32_t triangle(size_t i) const { return points[i].triangle; }
    const Vec3& barycentric(size_t i) const { return points[i].barycentric; }
};

// Runs `eval(t, b, i)` for every query i (coarse triangle t, barycentrics b), see
// PhiEvaluator::evaluate, grouped by coarse triangle (phi/grouped_queries.h). A chunk
// holds 2^20 queries (at least 48 per coarse triangle): on armadillo at 10% (5196
// coarse triangles) 2^20 was faster than 2^18 (too little reuse) and than 2^22 (its
// scattered output no longer stays in the cache); rechecked after the changes in the
// file comment (2^16 to 2^22 on armadillo, 2^16 to 2^20 on femur at 10%, shared
// machine, noisy): 2^20 still as fast as any. `prefetch(i)` is called for the query a few
// places ahead in the visiting order, after its input has been prefetched, so that its
// output line is in the cache when its result is stored (otherwise the stores pile up in
// the store buffer and stall the loop).
//
// `Queries` is ParallelQueries or PointQueries above (the two ways the API takes queries).
template <class Queries, class Eval, class Prefetch>
void for_each_query_grouped(const Queries& queries, size_t nt, int threads, const Eval& eval,
                            const Prefetch& prefetch) {
    if (threads < 0) throw std::invalid_argument("PhiEvaluator::evaluate: threads must be >= 0");
    const size_t n = queries.size();
    for (size_t i = 0; i < n; ++i) {
        const int32_t t = queries.triangle(i);
        if (t < 0 || static_cast<size_t>(t) >= nt)
            throw std::out_of_range("PhiEvaluator::evaluate: coarse triangle index out of range");
    }
    detail::for_each_grouped(
        n, nt, 48, threads, [&](size_t i) { return static_cast<size_t>(queries.triangle(i)); },
        [&](size_t t, size_t i) { eval(static_cast<int32_t>(t), queries.barycentric(i), i); },
        [&](size_t i) {
            detail::prefetch_object<false>(&queries.barycentric(i));
            prefetch(i);
        });
}

}  // namespace

namespace {

// (Impl is deduced: PhiEvaluator::Impl is private.)
template <class Impl, class Queries>
void evaluate_samples(const Impl& impl, const Queries& queries, std::vector<PhiSample>& out,
                      int threads) {
    out.resize(queries.size());
    for_each_query_grouped(queries, static_cast<size_t>(impl.p.num_coarse_triangles()), threads,
                           [&](int32_t t, const Vec3& b, size_t i) { out[i] = impl.evaluate(t, b); },
                           // A PhiSample (80 bytes) may straddle two cache lines.
                           [&](size_t i) { detail::prefetch_object<true>(out.data() + i); });
}

template <class Impl, class Queries>
void evaluate_positions_of(const Impl& impl, const Queries& queries, std::vector<Vec3>& positions,
                           int threads) {
    positions.resize(queries.size());
    for_each_query_grouped(queries, static_cast<size_t>(impl.p.num_coarse_triangles()), threads,
                           [&](int32_t t, const Vec3& b, size_t i) { positions[i] = impl.position(t, b); },
                           [&](size_t i) { detail::prefetch_object<true>(positions.data() + i); });
}

}  // namespace

void PhiEvaluator::evaluate(const std::vector<int32_t>& triangles, const std::vector<Vec3>& barycentrics,
                            std::vector<PhiSample>& out, int threads) const {
    if (triangles.size() != barycentrics.size()) out.resize(std::min(triangles.size(), barycentrics.size()));
    evaluate_samples(*impl_, ParallelQueries(triangles, barycentrics), out, threads);
}

void PhiEvaluator::evaluate(const std::vector<SurfacePoint>& points, std::vector<PhiSample>& out, int threads) const {
    evaluate_samples(*impl_, PointQueries{points}, out, threads);
}

void PhiEvaluator::evaluate_positions(const std::vector<int32_t>& triangles, const std::vector<Vec3>& barycentrics,
                                      std::vector<Vec3>& positions, int threads) const {
    if (triangles.size() != barycentrics.size())
        positions.resize(std::min(triangles.size(), barycentrics.size()));
    evaluate_positions_of(*impl_, ParallelQueries(triangles, barycentrics), positions, threads);
}

void PhiEvaluator::evaluate_positions(const std::vector<SurfacePoint>& points, std::vector<Vec3>& positions,
                                      int threads) const {
    evaluate_positions_of(*impl_, PointQueries{points}, positions, threads);
}

}  // namespace bpm
