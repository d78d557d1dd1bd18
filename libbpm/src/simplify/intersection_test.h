#pragma once
// Whether a planned removal would make the coarse surface intersect itself: its new
// triangles against the rest of the surface (the triangles near them, found through a
// grid of triangle boxes) and against each other. Internal to libbpm.
//
// Two triangles of the coarse surface may share vertices (by id) and the edge between
// two shared vertices; anything else they have in common (crossing edges, a corner of
// one on the other, a coplanar overlap, a fold over a shared edge) "meets improperly",
// and is an intersection. Decided with exact predicates (triangles_intersect_improperly),
// so the answer does not depend on the order of the tests or on the grid's cell size.

#include <cstdint>
#include <utility>
#include <vector>

#include "bpm/geometry.h"
#include "simplify/coarse_mesh.h"
#include "core/triangle_grid.h"

namespace bpm::detail {

// Whether triangles a and b (corners: indices into x) meet other than in the vertices
// they share and the edge between two of those.
bool meet_improperly(const std::vector<Vec3>& x, const Tri& a, const Tri& b);

// Whether a triangle of `ours` meets a triangle of `others` improperly.
bool meet_improperly(const std::vector<Vec3>& x, const std::vector<Tri>& ours, const std::vector<Tri>& others);

// The alive triangles of a CoarseMesh in a grid, kept up to date by the caller through
// update() after each change of the mesh.
class IntersectionTest {
public:
    // Indexes the alive triangles of `mesh` (which must outlive this), with a cell size
    // of twice their mean edge length.
    explicit IntersectionTest(const CoarseMesh& mesh);

    // Whether `new_triangles` (the triangles a removal would add) meet improperly an
    // alive triangle of the mesh that is not in `removed_triangles` (those it would
    // take away), or each other. `scratch`: the caller's buffer (one per thread).
    // Reads the grid: not while update() runs.
    bool intersects_rest(const std::vector<Tri>& new_triangles, const std::vector<int32_t>& removed_triangles,
                         std::vector<TriangleGrid::Entry>& scratch) const;

    // Follows a change of the mesh: `removed` (id and corners of triangles no longer
    // alive) out of the grid, the triangles from id `first_new` on into it.
    void update(const std::vector<std::pair<int32_t, Tri>>& removed, int32_t first_new);

    // Rebuilds the grid (new cell size) once fewer than a quarter of the triangles of
    // the last build are alive: the cells would hold few triangles each, and the
    // queries would visit many cells.
    void rebuild_if_sparse();

    // The grid of the alive triangles' boxes (for surely_passes_intersection_check,
    // simplify/input_intersections.h, before the mesh changes).
    const TriangleGrid& grid() const { return grid_; }

    // Frees the grid once no more tests will be asked (before the export of phi, so that
    // the memory is reused by it). intersects_rest() must not be called afterwards.
    void release() { grid_ = TriangleGrid(1.0); }

private:
    void rebuild();
    const CoarseMesh& mesh_;
    TriangleGrid grid_;
    int32_t built_at_ = 0;  // alive triangles when the grid was last built
};

}  // namespace bpm::detail
