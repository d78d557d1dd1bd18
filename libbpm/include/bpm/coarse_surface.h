#pragma once
// Points of the coarse surface S across triangle boundaries: the same point in another
// coarse triangle, and the midpoint of two points in (possibly) different triangles.
//
// A solver that refines its grid puts a new boundary vertex at phi of the midpoint of a
// boundary edge, taken in the parameter domain S. The ends of that edge are SurfacePoints,
// often in two adjacent coarse triangles; their midpoint is found by unfolding the
// triangles between them into one plane (the straight segment in the unfolding is the
// shortest path on S between them when it stays inside the unfolded triangles).
//
// Which triangles contain a point is decided by exact zeros of its barycentric
// coordinates (bpm/surface_point.h): b[k] == 0 for exactly one k puts the point on the
// edge opposite corner k, two zeros on a corner. A coordinate that is only tiny (1e-17)
// leaves the point inside its triangle.

#include <cstdint>
#include <optional>

#include "bpm/surface.h"
#include "bpm/surface_point.h"
#include "bpm/surface_topology.h"

namespace bpm {

// The coarse surface with the adjacency the operations below need (built once, O(#T log
// #T)). Keeps a reference to `coarse`, which must outlive it and not change. All queries
// are const and safe to call from several threads at once.
class CoarseSurface {
public:
    // \pre validate_surface(coarse) finds nothing (indices in range, no repeated corners).
    explicit CoarseSurface(const Surface& coarse);

    const Surface& surface() const { return coarse_; }

    // The coordinates of `p` in coarse triangle `triangle` if that triangle contains p
    // (p.triangle itself; for p on an edge every triangle with that edge, for p on a
    // corner every triangle with that vertex); the coordinates are p's, permuted (exact).
    // std::nullopt if `triangle` does not contain p.
    // \throw std::out_of_range if p.triangle or `triangle` is outside [0, #S.T).
    std::optional<SurfacePoint> express_in(const SurfacePoint& p, int32_t triangle) const;

    // The midpoint of a and b in the parameter domain:
    // - a triangle contains both (the same triangle, or one of them on an edge or corner of
    //   the other's triangle): the average of their coordinates in that triangle (exact
    //   for points on one coarse edge, e.g. a feature line: the midpoint stays on it);
    // - their triangles share an edge: the two triangles are unfolded into one plane across
    //   it, the midpoint of the straight segment is expressed in the triangle that contains
    //   it;
    // - their triangles share only a vertex: the triangles around that vertex are unfolded
    //   one after the other from a's triangle to b's, the shorter way round (by the sum of
    //   their angles at the vertex), and the midpoint is expressed in the unfolded triangle
    //   containing it.
    // When the unfolded segment leaves the unfolded triangles (around a reflex corner),
    // its midpoint is snapped into the nearest of them.
    // \throw std::out_of_range if a triangle index is outside [0, #S.T).
    //        AlgorithmError if the two triangles share no vertex, or share only a vertex
    //        whose triangles do not form a single fan (an edge at it with 3 or more
    //        triangles, or several fans meeting there), naming the vertex and what is wrong.
    SurfacePoint midpoint(const SurfacePoint& a, const SurfacePoint& b) const;

private:
    const Surface& coarse_;
    SurfaceConnectivity connectivity_;
};

}  // namespace bpm
