#pragma once
// The cyclic order of the sheets around an edge, decided with exact predicates: the
// triangles (a, b, c_i) that share the edge a -- b are half-planes bounded by the line
// through a and b, and their apexes c_i give the order in which one meets them turning
// around that line. Where three or more sheets meet (a junction edge of a
// multi-material surface) the order says which wedge lies between which sheets, and so
// which material fills it: a triangle turned past another around their common edge
// intersects nothing (two triangles that share an edge never do), yet the wedges now
// face other materials. Used by the junctions check (bpm-check) and by the simplifier,
// which refuses removals that change the order. Internal to libbpm.
//
// Angles are never computed: orient3d(a, b, p, q) is the sign of sin(theta_q - theta_p)
// for the angles theta of the half-planes of p and q around the directed line a -> b
// (positive = "q comes after p" in the turning direction of the order), which decides
// every comparison within a half-turn; a reference half-plane splits the turn in two.

#include <cstdint>
#include <vector>

#include "bpm/geometry.h"

namespace bpm::detail {

// Where the half-plane of q lies seen from that of r, turning around a -> b:
//   0  on r's half-plane (or q on the line: a degenerate triangle),
//   1  within the half-turn after r,  2  on the opposite half-plane,  3  within the half-turn before r.
int half_turn(const Vec3& a, const Vec3& b, const Vec3& r, const Vec3& q);

// Does q come strictly before p, turning from r? (Angles measured from r's half-plane
// in [0, 2 pi); equal angles compare false.)
bool turns_before(const Vec3& a, const Vec3& b, const Vec3& r, const Vec3& q, const Vec3& p);

// `order` receives the indices of `apexes` in the order one meets their half-planes
// turning around a -> b from apexes[0] (order[0] == 0). Returns false when two apexes
// lie on one half-plane (their triangles overlap) or one lies on the line; the order
// is still a total order then, ties by index.
bool sort_around_edge(const Vec3& a, const Vec3& b, const std::vector<Vec3>& apexes, std::vector<int32_t>& order);

// Is q's half-plane strictly inside the wedge turning from u's half-plane to w's (the
// open wedge; u == w's half-plane means the whole turn but that half-plane)?
bool strictly_between(const Vec3& a, const Vec3& b, const Vec3& u, const Vec3& w, const Vec3& q);

}  // namespace bpm::detail
