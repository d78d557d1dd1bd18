#pragma once
// DUNE boundary segments whose geometry is phi (bpm/phi_evaluation.h): a UGGrid built
// with them puts every boundary vertex it creates while refining on the original surface.
//
// Dune::BoundarySegment<3>::operator()(local) is called by the grid with local coordinates
// (x, y) in the reference triangle (0,0)-(1,0)-(0,1) whose corners are the segment's
// corners in the order they were given to GridFactory::insertBoundarySegment (for UGGrid:
// its factory converts UG's own parameter triangle to this one). A PhiBoundarySegment
// knows the parameter points of those corners, all expressed in one coarse triangle t,
// and returns phi(t, (1-x-y) B0 + x B1 + y B2): phi of the point of the coarse surface
// that lies at (x, y) between the corners. Because phi is continuous across coarse edges,
// two segments sharing an edge give the same point for it whichever one the grid asks.
//
// Needs DUNE 2.9 (dune-grid); for UGGrid compile as bpm/dune/uggrid_from_bpm.h says.
// Header-only: libbpm itself does not depend on DUNE.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>

#include <dune/common/fvector.hh>
#include <dune/grid/common/boundarysegment.hh>

#include "bpm/errors.h"
#include "bpm/phi_evaluation.h"
#include "bpm/surface.h"
#include "bpm/surface_point.h"

namespace bpm::dune {

// Barycentric coordinates of the point `p` of the coarse surface in the frame of coarse
// triangle `t`, or nullopt if p does not lie in the closure of t. A point of triangle
// p.triangle lies in t exactly when all corners of p.triangle with a nonzero coordinate
// are corners of t (p is on their shared edge or vertex); coordinates are moved, not
// recomputed, so exact zeros and sums stay exact.
// \pre 0 <= p.triangle, t < #coarse.T
inline std::optional<Vec3> barycentric_in_triangle(const Surface& coarse, const SurfacePoint& p, int32_t t) {
    if (p.triangle == t) return p.barycentric;
    const Tri& from = coarse.triangles.at(static_cast<size_t>(p.triangle));
    const Tri& to = coarse.triangles.at(static_cast<size_t>(t));
    Vec3 b{0, 0, 0};
    for (int k = 0; k < 3; ++k) {
        if (p.barycentric[k] == 0.0) continue;
        int m = 0;
        while (m < 3 && to[m] != from[k]) ++m;
        if (m == 3) return std::nullopt;
        b[m] += p.barycentric[k];
    }
    return b;
}

// A boundary segment whose corners have the parameter points (t, corner_barycentric[i]).
// `phi` is shared by all segments of a grid and must outlive the grid (UGGrid keeps the
// segments as long as the grid lives).
class PhiBoundarySegment final : public Dune::BoundarySegment<3> {
public:
    // \pre corner_barycentric[i] are barycentric coordinates in coarse triangle `triangle`
    // \throw std::invalid_argument if phi is null
    PhiBoundarySegment(std::shared_ptr<const PhiEvaluator> phi, int32_t triangle,
                       const std::array<Vec3, 3>& corner_barycentric)
        : phi_(std::move(phi)), triangle_(triangle), corners_(corner_barycentric) {
        if (!phi_) throw std::invalid_argument("PhiBoundarySegment: phi is null");
    }

    // The parameter point at local coordinates (x, y) of the segment.
    SurfacePoint parameter_point(const Dune::FieldVector<double, 2>& local) const {
        const double w0 = 1.0 - local[0] - local[1], w1 = local[0], w2 = local[1];
        SurfacePoint p;
        p.triangle = triangle_;
        for (int k = 0; k < 3; ++k) p.barycentric[k] = w0 * corners_[0][k] + w1 * corners_[1][k] + w2 * corners_[2][k];
        return p;
    }

    Dune::FieldVector<double, 3> operator()(const Dune::FieldVector<double, 2>& local) const override {
        const SurfacePoint p = parameter_point(local);
        const Vec3 x = phi_->evaluate(p.triangle, p.barycentric).position;
        return {x[0], x[1], x[2]};
    }

    int32_t coarse_triangle() const { return triangle_; }
    const std::array<Vec3, 3>& corner_barycentric() const { return corners_; }

private:
    std::shared_ptr<const PhiEvaluator> phi_;
    int32_t triangle_;
    std::array<Vec3, 3> corners_;
};

// A plane boundary segment through three points (the segment's corners, in insertion
// order): refinement puts new boundary vertices at plain midpoints, as if there were no
// phi. Used for comparison runs ("flat"); it keeps the same segment numbering as the phi
// segments, so the parameter points of boundary vertices can be tracked in both cases.
class FlatBoundarySegment final : public Dune::BoundarySegment<3> {
public:
    explicit FlatBoundarySegment(const std::array<Vec3, 3>& corners) : corners_(corners) {}

    Dune::FieldVector<double, 3> operator()(const Dune::FieldVector<double, 2>& local) const override {
        const Vec3 b{1.0 - local[0] - local[1], local[0], local[1]};
        const Vec3 x = barycentric_point(corners_[0], corners_[1], corners_[2], b);
        return {x[0], x[1], x[2]};
    }

private:
    std::array<Vec3, 3> corners_;
};

}  // namespace bpm::dune
