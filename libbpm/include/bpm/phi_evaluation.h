#pragma once
// Evaluating phi: for a point on the coarse surface given as (coarse triangle,
// barycentric coordinates), the point on the original surface, the original triangle
// it lies in with barycentric coordinates there (to interpolate data given on S0),
// and the normal of S0 there.

#include <cstdint>
#include <vector>

#include "bpm/parametrization.h"
#include "bpm/surface_point.h"

namespace bpm {

struct PhiSample {
    Vec3 position;                   // phi(x), a point on S0
    int32_t original_triangle = -1;  // the triangle of S0 containing phi(x)
    Vec3 original_barycentric;       // barycentric coordinates of phi(x) in that triangle
    Vec3 normal;                     // unit normal of that original triangle
};

// Precomputes a point-location structure per coarse triangle (a uniform grid over the
// parameter triangle listing the pieces that overlap each cell, about one cell per piece)
// and keeps a reference to `param`, which must outlive it and not change. Construction
// is O(#pieces); evaluate() is const and safe to call from several threads at once.
//
// Evaluation follows spec/bpm-format.md §7: the piece containing the point, linear
// interpolation of node_image; original_barycentric interpolates each piece corner's
// exact coordinates in the original triangle (derived from the node kind), so phi of the
// identity parametrization returns exactly barycentric_point(x0, x1, x2, b) and b.
// Throughput: single queries are fast when consecutive queries are in the same coarse
// triangle (the data of one triangle stays in the cache) and bound by memory latency in
// random order; the batched overloads group queries by coarse triangle themselves and
// can use several threads, so prefer them for large query sets (bench/refine.py measures
// both).
class PhiEvaluator {
public:
    explicit PhiEvaluator(const Parametrization& param);
    ~PhiEvaluator();
    PhiEvaluator(const PhiEvaluator&) = delete;
    PhiEvaluator& operator=(const PhiEvaluator&) = delete;

    // \pre 0 <= coarse_triangle < #S.T, barycentric components >= 0 summing to 1
    //      (small rounding outside is tolerated: the nearest piece is used).
    PhiSample evaluate(int32_t coarse_triangle, const Vec3& barycentric) const;
    // The same for point.triangle, point.barycentric (\pre likewise).
    PhiSample evaluate(const SurfacePoint& point) const;

    // Batched: `triangles` #Q, `barycentrics` #Q; fills `out` (#Q) in query order. Large
    // batches are visited grouped by coarse triangle and split over `threads` threads
    // (0 = std::thread::hardware_concurrency()); the result does not depend on `threads`.
    // \throw std::invalid_argument if the two lists differ in length or threads < 0,
    //        std::out_of_range for a coarse triangle index outside [0, #S.T).
    void evaluate(const std::vector<int32_t>& triangles, const std::vector<Vec3>& barycentrics,
                  std::vector<PhiSample>& out, int threads = 1) const;

    // The same, positions only (phi(x), what refinement needs): #Q rows of `positions`,
    // equal to evaluate(...).position. Writes 24 instead of 80 bytes per query.
    void evaluate_positions(const std::vector<int32_t>& triangles, const std::vector<Vec3>& barycentrics,
                            std::vector<Vec3>& positions, int threads = 1) const;

    // Both batched calls for queries given as SurfacePoints (#Q); the results are those of
    // the calls above for the same triangles and barycentrics, bit for bit.
    // \throw std::invalid_argument if threads < 0,
    //        std::out_of_range for a triangle index outside [0, #S.T) (also for an invalid
    //        SurfacePoint, triangle -1).
    void evaluate(const std::vector<SurfacePoint>& points, std::vector<PhiSample>& out, int threads = 1) const;
    void evaluate_positions(const std::vector<SurfacePoint>& points, std::vector<Vec3>& positions,
                            int threads = 1) const;

private:
    struct Impl;
    Impl* impl_;
};

}  // namespace bpm
