#pragma once
// How far a node image may be from the point its node names before it counts as another
// point: one value for bpm-check's format check (check_format.cpp, which also holds coarse
// vertices to it) and for write_bpm (io/bpm_write.cpp), which refuses exactly the images
// that check would fail, since a format 2.0 file drops them and readers recompute them.
// Internal to libbpm.

namespace bpm::detail {

// Times the bounding-box diagonal of the original surface S0. The value is the spec's
// (check-report.md "format", bpm-format.md §6.2.1): changing it changes which files
// bpm-check accepts. Why 1e-9: the image rule (bpm-format.md §6.2) fixes the point to the
// bit, so libbpm's own images are 0 off; a writer that evaluates (1 - s) x_u + s x_w in
// another order or with a fused multiply-add is a few ulps off, about 1e-16 of a
// coordinate's magnitude, which stays below 1e-9 of the diagonal for models up to ~10^6
// diagonals from the origin. A wrong image (another vertex, edge or parameter) is off by
// a fraction of an original edge, orders of magnitude more.
inline constexpr double kImageToleranceRelativeToDiagonal = 1e-9;

}  // namespace bpm::detail
