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

// The simplifier's fold term (SimplifyOptions::fold_weight, issue 19 "Convergence"): a
// removal that turns an original piece past 90 degrees against its new coarse triangle (a
// fold seen from S) costs
//   weight * 1e-3 * (deviation - 90) / 90       (0 up to 90 degrees; weight * 1e-3 at 180)
// more, in units of the diagonal like the error. Graded and small, unlike the fold limit's
// + 1: a fold is put off while a removal of about the same error that folds less is
// available, but a removal of clearly smaller error still goes first, so the scan's folds
// that cannot be avoided (femur: hundreds of CT-noise spikes) do not push the error up.
//
// Why: where phi folds the original over a coarse triangle, refining through phi samples
// the folded part too coarsely (a spike of the femur squeezed 30-70x), and there the
// refined surface stays far from S0 at K = 4; the maximum of the two-sided distance at
// K = 4 sat on such folds on 4 of the 10 bench rows (femur both, elephant 10 %, armadillo
// 1000 V). Measured (bench/results/manual/folds-and-convergence.md): weight 2 takes the
// K = 0 -> 4 reduction of the maximum from 1.9x to 3.0x on femur 1000 V and from 4.3x to
// 5.5x on elephant 10 % and armadillo 1000 V, at +10 % CPU, but the changed removal order
// moves the K = 0 distance of femur 10 % to 1.13x the bench reference (weights 0.25 and 1:
// mech-holes-shark 1000 V 1.12x), above the 1.1x: off by default. The alternatives were worse: a + 1 fold limit at 90 / 120 degrees cost femur
// 10 % 5.9x / 1.38x at K = 0; keeping the tips of sharp cones (angle defect >= 90..180
// degrees) as coarse vertices cost 1.10-1.30x and moved the K = 4 maximum to the next of
// the femur's hundreds of noise spikes. Even without any fold (fold limit 90 at 1000
// vertices) femur's K = 4 maximum stays at 1.57e-3 of the diagonal, on its noise creases.
double fold_cost(double max_normal_deviation_degrees, double weight);

}  // namespace bpm::detail
