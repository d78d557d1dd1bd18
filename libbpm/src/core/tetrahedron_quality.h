#pragma once
// Dihedral angles of a tetrahedron: the one implementation behind every dihedral angle bpm
// measures or decides on (tetmesh_stats, tetrahedral smoothing, the boundary repair's
// guard, tet_refine's report, the simplifier's sliver flips).
//
// Corners (a, b, c, d) = 0, 1, 2, 3. The six edges, in this order: 01 02 03 12 13 23. The
// dihedral angle at edge (i, j) is the angle inside the tetrahedron between the two faces
// through that edge.
//
// Sign: the angles are signed by the orientation of (a, b, c, d) as computed in floating
// point (6 volume = (b - a) . ((c - a) x (d - a))): all six in (0, pi) for a positively
// oriented tetrahedron (orient3d(a, b, c, d) > 0), all six in (-pi, 0) for an inverted one,
// with the same magnitudes as the positive tetrahedron (b, a, c, d). So "the smallest
// angle" is one quality measure that also ranks inverted tetrahedra below every valid one
// (smoothing uses it to untangle). For the unsigned angles take the magnitudes.
//
// Degeneracy: a flat tetrahedron (floating-point volume exactly 0) has every angle 0 or pi
// (never -0), and its smallest is 0: the outer edges of a flat quadrilateral or triangle
// are 0, its diagonals or the edges to a point inside it are pi; the edges of a face of
// zero area (coincident or collinear corners) are 0. Near flat tetrahedra the sign comes
// from floating point: decisions about inversion use exact orient3d (bpm/predicates.h);
// these angles measure and rank.
//
// Everything here is double precision floating point, no allocation, no exceptions.

#include "bpm/geometry.h"

namespace bpm::detail {

// The six signed dihedral angles (radians) of (a, b, c, d) at the edges 01 02 03 12 13 23.
void dihedral_angles(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double out[6]);
// The smallest of the six signed angles (radians), and the same in degrees.
double min_dihedral(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
double min_dihedral_degrees(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// The same angles as pseudo-angles, cheaper (no atan2) and strictly increasing in the
// angle, for optimisation loops that compare angles: sin(angle) for |angle| <= pi/2,
// continued by 2 - sin (up to pi) and -2 - sin (down to -pi), so in (-2, 2), and equal to
// the angle to first order near 0. A flat tetrahedron's pseudo-angles are 0 or 2 (pi),
// exactly where its angles are 0 or pi.
void dihedral_pseudo_angles(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double out[6]);
double min_dihedral_pseudo(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
// Conversions between a signed angle in [-pi, pi] (radians) and its pseudo-angle.
double pseudo_from_radians(double angle);
double radians_from_pseudo(double pseudo);

}  // namespace bpm::detail
