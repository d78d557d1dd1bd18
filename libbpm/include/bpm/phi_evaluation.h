#pragma once
// Evaluating phi: for a point on the coarse surface given as (coarse triangle,
// barycentric coordinates), the point on the original surface, the original triangle
// it lies in with barycentric coordinates there (to interpolate data given on S0),
// and the normal of S0 there.

#include <cstdint>
#include <vector>

#include "bpm/parametrization.h"

namespace bpm {

struct PhiSample {
    Vec3 position;                   // phi(x), a point on S0
    int32_t original_triangle = -1;  // the triangle of S0 containing phi(x)
    Vec3 original_barycentric;       // barycentric coordinates of phi(x) in that triangle
    Vec3 normal;                     // unit normal of that original triangle
};

// Precomputes a point-location structure per coarse triangle; keeps a reference to
// `param`, which must outlive it.
class PhiEvaluator {
public:
    explicit PhiEvaluator(const Parametrization& param);
    ~PhiEvaluator();
    PhiEvaluator(const PhiEvaluator&) = delete;
    PhiEvaluator& operator=(const PhiEvaluator&) = delete;

    // \pre 0 <= coarse_triangle < #S.T, barycentric components >= 0 summing to 1
    //      (small rounding outside is tolerated: the nearest piece is used).
    PhiSample evaluate(int32_t coarse_triangle, const Vec3& barycentric) const;

    // Batched: `triangles` #Q, `barycentrics` #Q; fills `out` (#Q).
    void evaluate(const std::vector<int32_t>& triangles, const std::vector<Vec3>& barycentrics,
                  std::vector<PhiSample>& out) const;

private:
    struct Impl;
    Impl* impl_;
};

}  // namespace bpm
