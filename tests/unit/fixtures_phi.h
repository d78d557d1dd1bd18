#pragma once
// Parametrizations with a non-trivial phi built in code, for tests that need one
// before (or independently of) the simplifier. Catch2-free, so that test tools
// (bpm-make-example) can link it too.

#include <functional>

#include "bpm/bpm_file.h"
#include "bpm/parametrization.h"

namespace bpm::test {

// Coarse surface: the octahedron with corners at +-x, +-y, +-z (8 triangles, patch =
// face index). Original surface: every face subdivided `levels` times (4^levels
// sub-triangles per face) with the new vertices pushed off the face onto a bumpy
// sphere of radius about 1 (`bump` = relative height of the bumps), so phi maps each
// flat parameter triangle onto a curved patch. Pieces are exactly the sub-triangles;
// nodes are OriginalVertex / CoarseCorner only (no edge crossings).
// Node barycentrics are dyadic fractions, hence exact.
Parametrization make_subdivided_octahedron(int levels, double bump = 0.15);

// A height field z = height(x, y) over the unit square.
// Original surface: an n x n grid, each cell split along its anti-diagonal
// (x+1,y)-(x,y+1). Coarse surface: an m x m grid on the same square (n % m == 0, so
// coarse vertices are original vertices), each cell split along its main diagonal
// (x,y)-(x+1,y+1). phi is the vertical projection: a parameter point (x, y) of a coarse
// triangle maps to (x, y, h(x, y)) on the original piecewise-linear surface. The
// original anti-diagonals cross the coarse diagonals, so there are EdgeCrossing nodes,
// original vertices on coarse edges, and quadrilateral stumps split into two pieces.
// Patch of a triangle: 1 + (column of its coarse cell) % 3, the same for original and
// coarse triangles over the same cell.
using HeightFunction = std::function<double(double, double)>;
Parametrization make_height_field(int n, int m, const HeightFunction& height);
// Default bumpy height function used by tests.
double default_height(double x, double y);

// The example file of the spec (spec/examples/two_triangles.bpm): make_height_field(1,
// 1) with the two anti-diagonal corners lifted by 0.3, fixed provenance, units "mm".
BpmFile make_two_triangles_example();

}  // namespace bpm::test
