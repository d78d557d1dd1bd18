#pragma once
// Inverse phi: for a point of the original surface S0, the point of the coarse surface S
// (the parameter point) that phi maps to it.
//
// A point of S0 is given either exactly, as an original triangle with barycentric
// coordinates in it (what PhiSample returns, or what a solver that carries data on S0
// has), or as a position in space on or near S0 (what deal.II's manifolds see): the
// closest point of S0 is found first, then inverted.
//
// Inversion is exact on the pieces of phi (bpm/parametrization.h): every piece maps
// affinely into one original triangle and the pieces mapping into one original triangle
// tile it (phi is bijective), so the point is located among the pieces of its original
// triangle and its barycentric coordinates in the piece's image are carried to the piece
// in the coarse triangle. Hence, up to rounding:
//   phi(from_original(T, beta)) == the point beta of T, and
//   from_original(phi(x)) == x for x inside a piece (for x on a piece edge, any coarse
//   triangle and piece containing x may be returned, which is the same point of S).

#include <cstdint>
#include <vector>

#include "bpm/parametrization.h"
#include "bpm/surface_point.h"

namespace bpm {

// A point of the original surface S0: an original triangle and barycentric coordinates
// (b0, b1, b2) in the corner order of /original/triangles, b0 + b1 + b2 = 1, all >= 0.
struct OriginalPoint {
    int32_t triangle = -1;  // 0 <= triangle < #S0.T
    Vec3 barycentric{0, 0, 0};
};

// The result of inverting phi at a position in space.
struct PhiInverseSample {
    SurfacePoint point;     // the parameter point: phi(point) == foot up to rounding
    OriginalPoint original; // where the foot point lies on S0
    Vec3 foot;              // the point of S0 closest to the query position
    double distance = 0;    // |position - foot|, in the model's units
};

// Precomputes, per original triangle, the pieces that map into it (CSR) with the
// matrices that take barycentric coordinates in the original triangle to coordinates in
// the piece and those to coordinates in the coarse triangle (all derived exactly from the
// node kinds, as PhiEvaluator does), and a uniform grid over the original triangles for
// closest-point queries. Keeps a reference to `param`, which must outlive it and not
// change. Construction is O(#pieces + #S0.T); every query is const and safe to call from
// several threads at once.
//
// Closest points: exact Euclidean closest point on the triangles of S0 (ties, e.g. a
// point on an edge shared by two triangles, go to the smaller triangle index). The grid
// answers points on or near S0 from one cell; a query far from S0 (many grid cells away)
// is correct but slower.
class PhiInverse {
public:
    // \throw std::invalid_argument if `param` is not consistent enough to index (piece or
    //        node ranges out of bounds, piece_original_triangle outside [0, #S0.T)).
    explicit PhiInverse(const Parametrization& param);
    ~PhiInverse();
    PhiInverse(const PhiInverse&) = delete;
    PhiInverse& operator=(const PhiInverse&) = delete;

    // The parameter point whose image under phi is `x`.
    // \pre barycentric components >= 0 summing to 1; points a rounding error outside the
    //      triangle are accepted (the nearest piece is used and the point snapped into it).
    // \throw std::out_of_range if x.triangle is outside [0, #S0.T).
    //        std::invalid_argument if no piece maps into x.triangle (an inconsistent
    //        parametrization) or a coordinate is not finite.
    SurfacePoint from_original(const OriginalPoint& x) const;

    // The closest point of S0 to `position`, and its parameter point.
    // \throw std::invalid_argument if a coordinate of `position` is not finite or S0 has
    //        no triangles.
    PhiInverseSample from_position(const Vec3& position) const;

    // Batched: fills `out` (#Q) in query order; queries are split over `threads` threads
    // (0 = std::thread::hardware_concurrency()), and the result does not depend on
    // `threads`. Each query gives what the single call gives, bit for bit.
    // \throw as the single calls (the first bad query in index order is reported), and
    //        std::invalid_argument if threads < 0.
    void from_original(const std::vector<OriginalPoint>& points, std::vector<SurfacePoint>& out,
                       int threads = 1) const;
    void from_position(const std::vector<Vec3>& positions, std::vector<PhiInverseSample>& out,
                       int threads = 1) const;
    // The same, parameter points only (== from_position(...).point); 32 instead of 104
    // bytes written per query.
    void from_position(const std::vector<Vec3>& positions, std::vector<SurfacePoint>& out, int threads = 1) const;

private:
    struct Impl;
    Impl* impl_;
};

}  // namespace bpm
