#pragma once
// How far phi is from an isometry on one piece (issue 19 item 2): what bpm-check's
// distortion check reports and what the simplifier's distortion term would weigh.
//
// A piece q of coarse triangle t is a triangle of t's parameter triangle that phi maps
// affinely onto a triangle of the original triangle piece_original_triangle[q].
//   area squeeze   (area of q in t) / (area of phi(q)), divided by the same ratio for the
//                  whole triangle, area(t) / sum over t's pieces of area(phi(q)): 1 where
//                  phi stretches q as much as it stretches t on average; 1000 for a piece
//                  that t holds a thousand times smaller than its share (a fold squeezes
//                  the pieces it folds over), 0.001 for the opposite. Reported as
//                  max(s, 1/s) >= 1, the factor of distortion either way.
//   normal deviation  the angle between t's normal and the normal of the original
//                  triangle phi(q) lies in (both oriented): 0 for a flat copy, > 90 degrees
//                  where phi turns the piece over relative to the coarse triangle (a fold
//                  seen from the coarse surface).
// Pieces whose parameter or image area is 0 (a piece cut to a sliver by rounding-free
// overlay arithmetic can be) have no squeeze; they are counted apart.
#include <array>
#include <cstdint>
#include <vector>

#include "bpm/geometry.h"
#include "bpm/parametrization.h"

namespace bpm::detail {

struct PieceDistortion {
    double squeeze = 1;           // max(s, 1/s) >= 1; +inf when `degenerate`
    double normal_deviation = 0;  // degrees, in [0, 180]
    bool degenerate = false;      // parameter or image area 0 (squeeze undefined)
};

// Distortion of every piece of coarse triangle t (in piece order). `original_normals`:
// unit normals of the original triangles (oriented like them), or empty to compute them.
void triangle_distortion(const Parametrization& param, int32_t t, const std::vector<Vec3>& original_normals,
                         std::vector<PieceDistortion>& out);

// Unit normals of the triangles of `surface` (0 for degenerate ones).
std::vector<Vec3> unit_normals(const Surface& surface);

// The simplifier's distortion term (SimplifyOptions::distortion_weight, fold_limit_degrees),
// from the largest normal deviation a removal leaves between a new coarse triangle and an
// original triangle phi maps onto it (RemovalPlan::max_normal_deviation):
//   0                                          up to 45 degrees (a piece of a curved
//                                              surface under a coarse triangle),
//   weight * 1e-3 * ((deviation - 45) / 45)^2  above (the same scale as the aspect term:
//                                              1e-3 is an error of 0.1 % of the diagonal),
//   + 1 above fold_limit (if < 180)            (a fold seen from S: the removal goes behind
//                                              every removal that folds nothing, since
//                                              costs are errors relative to the diagonal;
//                                              it is made only when the target cannot be
//                                              reached otherwise).
// weight 0 turns the quadratic part off; fold_limit 180 the fold part. Either works alone.
double distortion_cost(double max_normal_deviation_degrees, double weight, double fold_limit_degrees);

}  // namespace bpm::detail
