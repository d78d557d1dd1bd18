#pragma once
// Retriangulation of the hole a removed vertex leaves in one fan (Krause & Sander
// §2.2.4): greedy ear cutting on the fan's polygon in the plane (polar_map.h), which
// prefers Delaunay-admissible ears and among them the best 3D aspect ratio, and never
// creates an edge or a triangle that already exists (the topology condition,
// Conjecture 2.1). The plane only decides admissibility; quality is judged in 3D.

#include <array>
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "simplify/coarse_mesh.h"
#include "simplify/polar_map.h"
#include "simplify/star_fans.h"

namespace bpm::detail {

// New triangles over polygon corner indices (corner i is fan.link[i]).
struct FanTriangulation {
    std::vector<std::array<int32_t, 3>> triangles;  // counter-clockwise in the plane (and in the fan's orientation)
    std::vector<double> aspects;                     // aspect_ratio() of each, corners in that order
    std::vector<std::array<int32_t, 2>> diagonals;   // the new interior edges, in the order they were cut
};

// Buffers of retriangulate_fan(), one entry per polygon corner (see RemovalScratch in
// vertex_removal.cpp).
struct EarScratch {
    std::vector<int32_t> polygon;   // corners still in the polygon
    std::vector<double> aspect;     // of the ear at each corner, NaN: unknown
    std::vector<int8_t> blocked;    // -1 unknown, 0 free, 1 its diagonal exists or is forbidden
    std::vector<int8_t> delaunay;   // -1 unknown, 0 no, 1 yes
    std::vector<int32_t> witness;   // a corner clearly inside the circle of a non-admissible ear
    std::vector<int8_t> polar;      // -1 unknown, 0 no, 1 an ear of the polar map's polygon (map.cocircular)
    std::vector<int32_t> polar_witness;  // a corner in the polar map's triangle of a non-polar ear, or -1
    // Of the fallback when no ear may be cut (n x n, row-major): the smallest worst aspect
    // ratio of a triangulation of corners i..k closed by i -- k, and its apex.
    std::vector<double> worst;
    std::vector<int32_t> apex;
    std::vector<std::array<int32_t, 2>> stack;
    // Of the indexed ear cutting (large polygons on a circle, see retriangulate_fan).
    struct EarKey {
        int8_t rank;    // 0: an ear of the polar map's polygon, 1: not
        double aspect;  // 3D R/r, finite
        int32_t corner;
        bool operator<(const EarKey& o) const {
            return rank != o.rank ? rank < o.rank : aspect != o.aspect ? aspect < o.aspect : corner < o.corner;
        }
    };
    std::set<EarKey> ears;             // the non-degenerate ears, except those found blocked
    std::vector<int8_t> queued;        // the corner's ear is in `ears`
    std::vector<int32_t> next, prev;   // the polygon as a cyclic list
    std::vector<double> angle;         // atan2 of each corner in the polar map's polygon
    std::vector<int32_t> by_angle;     // the corners sorted by angle
    std::vector<double> sorted_angle;  // their angles
    std::vector<int32_t> angle_rank;   // the position of each corner in by_angle
    std::vector<int32_t> skip;         // by position in by_angle: towards the next corner still in the polygon
    std::vector<std::vector<int32_t>> witnessed;  // ears whose polar witness the corner is (or was)
    std::vector<int32_t> ties;         // the best ears within rounding
    // Tests only: false gives every polygon the plain scan (the choices are the same).
    bool indexed = true;
    // Corners the last call visited in its scans and tests (the ear choices, the polar-ear,
    // Delaunay and witness loops; not the fallback): what its cost grows with, for tests.
    int64_t work = 0;
};

// Triangulates the polygon of `fan` laid out by `map` (a strictly convex polygon) into
// n - 2 ears. The ear at corner b, (a, b, d), may be cut when its diagonal a -- d is not
// an edge of `mesh` and not in `forbidden` (pairs of corner indices, either order).
// Among those: first ears of the polar map's own polygon (when map.cocircular), then
// Delaunay-admissible ones (no other corner clearly inside their circumcircle), then the
// smallest 3D aspect ratio, near-ties to the first. When the ears left all have a
// diagonal that exists or is forbidden (the greedy choice can lead there: after a retry
// forbade both diagonals of the quadrilateral it left), and the map is not cocircular, the
// triangulation of the whole polygon without such diagonals and degenerate triangles with
// the smallest worst aspect ratio is taken instead (dynamic programming, O(n^3)). Fails
// with `why` when there is none, or the last triangle is degenerate or already exists;
// `out` is then unspecified.
// A polygon of more than kIndexedEarCorners corners that the polar map put on a circle
// (map.cocircular, so every ear is Delaunay-admissible: a CAD face fanned from its centre,
// with collinear rim corners) is cut with its ears in an ordered set, and the polar-ear
// test looks only at the corners within the ear's angle seen from v: O(n log n) on
// collinear rims where the plain scan is O(n^2) per call (O(n^2) still when the ears'
// angles widen), with the same triangulation (the scan's choice among
// ears of near-equal aspect ratio is replayed on those ears alone).
inline constexpr int32_t kIndexedEarCorners = 64;
bool retriangulate_fan(const CoarseMesh& mesh, const Fan& fan, const PolarMap& map,
                       const std::vector<std::array<int32_t, 2>>& forbidden, FanTriangulation& out,
                       EarScratch& scratch, std::string& why);

// A lower bound of the worst 3D aspect ratio (R/r) of every triangulation of the polygon
// of `fan` (corners fan.link[0..n-1], n >= 4) that retriangulate_fan() or any other could
// make, in O(n) (a retriangulation is O(n^2)). The larger of two bounds:
// - every triangulation of a polygon has two ears (triangles of three consecutive
//   corners) at different corners: its worst triangle is at least the second best ear;
// - every side of the polygon is in one new triangle, whose third corner is another
//   corner: the shortest side's best such triangle.
// The centre of a CAD disc fanned into n slivers is what this is for: every new triangle
// on the rim's shortest side is about twice as thin as the fan's own sliver there.
// Degenerate triangles count as +infinity (no triangulation may use them).
double triangulation_aspect_lower_bound(const std::vector<Vec3>& x, const Fan& fan);

}  // namespace bpm::detail
