#pragma once
// Where the corners of a piece of phi sit in the piece's original triangle, derived from
// what the nodes are (spec/bpm-format.md §7 step 3), shared by the forward evaluator
// (bpm/phi_evaluation.h) and its inverse (bpm/phi_inverse.h) so that both use the very
// same exact coordinates. Internal to libbpm.

#include <array>
#include <cstdint>

#include "bpm/parametrization.h"

namespace bpm::detail {

using Mat3 = std::array<double, 9>;  // row-major

// Corner k of a piece has barycentric coordinates (1 - s[k]) at original corner a[k] plus
// s[k] at b[k] (s = 0, a = b for an original vertex).
struct CornerCode {
    double s[3];
    uint8_t a[3];
    uint8_t b[3];
};

// The corner code of piece q of a coarse triangle whose first node is `nb`: an original
// vertex is a unit vector, an edge crossing (u, w, s) is (1-s) at u plus s at w. A node
// that is not on the piece's original triangle (inconsistent input) gets the nearest
// corner of the triangle, so that evaluation still returns something sane.
CornerCode corner_code(const Parametrization& p, int64_t nb, const Tri& piece, int64_t q);

// The matrix taking piece barycentrics to barycentrics in the original triangle
// (column k: corner k's coordinates); exactly the identity for an identity piece.
Mat3 to_original_matrix(const CornerCode& code);

}  // namespace bpm::detail
