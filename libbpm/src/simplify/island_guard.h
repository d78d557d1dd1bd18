#pragma once
// The island guard: a removal (or an edge flip) must not sweep a sheet across a whole
// component of the surface that it does not touch (an island: a blob of one label
// inside another in a label image, a cavity in a solid). The old triangles and the new
// ones together bound the volume the change sweeps; an island inside it touches no new
// triangle, so the intersection test passes, but the island then lies in another
// material (bpm-mesh found regions whose sides disagree; bpm-check's junctions check
// compares the material every component lies in).
//
// Exact (core/ray_crossing.h): a vertex of the island inside the closed surface of the
// old and the new triangles, by the parity of a ray's crossings. Components are those of
// the triangles through shared vertices (core/vertex_components.h); removals and flips
// never change them (the new triangles join the same link vertices).
//
// Along a feature line a -- v -- b each sheet j (half-disk) is replaced on its own: old
// fan F_j, new triangles G_j, and F_j + G_j has the boundary of the triangle T = (a, v, b).
// A material whose region meets the line has, around it, an even number of sheets on its
// boundary (those where it begins or ends, around the line); its boundary changes by the
// sum of their F_j + G_j, in which the T's cancel: a point leaves or enters that material
// exactly when the parities of those sheets' F_j + G_j (one ray for all) XOR to 1. Every
// even set of sheets bounds some union of the wedges between them, so a point keeps its
// material for every labelling exactly when all sheets' parities are equal: that is the
// test (for a crease, the two sheets' parities differ; nested volumes of two sheets do not
// cancel, and T, no part of the surface, which another component may cross, flips every
// sheet's parity at once and does not matter). Each difference is the parity of the
// closed surface F_i + G_i + F_j + G_j, which another component does not cross (the
// surface does not intersect itself, and the intersection test passed for the new
// triangles), so one of its vertices decides for all of it. A line with one sheet (the
// boundary of an open surface) is closed by T and refused when odd, as without a line
// (there a component crossing T can make the vertex tested refuse wrongly: an
// over-refusal only).
// Preconditions of the exactness: the intersection test passed for the new triangles
// (with intersections allowed another component may cross them, and one vertex no longer
// tells where the whole component lies: the guard still decides the same way every time,
// but may refuse or pass wrongly). The sheet order guard runs first: the sheets keep their
// order around the line, so the wedges before and after correspond.
// Internal to libbpm.

#include <cstdint>
#include <vector>

#include "bpm/geometry.h"
#include "core/triangle_grid.h"
#include "simplify/coarse_mesh.h"

namespace bpm::detail {

// The reason recorded for a refused removal (counted in the simplifier's "vertices kept").
inline constexpr const char* kIslandReason = "would sweep a sheet across another component of the surface (island)";

class IslandGuard {
public:
    // The components of the alive triangles of `mesh` (which must stay the same mesh).
    explicit IslandGuard(const CoarseMesh& mesh);

    // Two or more components: otherwise there is nothing to guard and sweeps_island()
    // answers false at once.
    bool active() const { return !component_.empty(); }
    int32_t components() const { return components_; }

    // Whether a vertex of a component other than v's lies inside the volume swept by
    // replacing `removed` (alive triangles of the mesh, all in v's component) with
    // `added`. Along a feature line, `a` and `b` are its vertices next to v (else -1).
    // The candidates come from `grid` (the alive triangles, as far as indexed) and the
    // triangles from id `first_unindexed` on (made since the grid was last updated).
    // `scratch` is the caller's buffer.
    struct Scratch {
        std::vector<TriangleGrid::Entry> entries;
        std::vector<int32_t> components, points, group;
        std::vector<Tri> tris;
    };
    bool sweeps_island(const CoarseMesh& mesh, const TriangleGrid& grid, int32_t first_unindexed, int32_t v,
                       int32_t a, int32_t b, const std::vector<int32_t>& removed, const std::vector<Tri>& added,
                       Scratch& scratch) const;

private:
    std::vector<int32_t> component_;  // per vertex; empty when the mesh has one component
    int32_t components_ = 0;
};

}  // namespace bpm::detail
