#pragma once
// The ridge guard of the simplifier (SimplifyOptions::min_ridge_angle_degrees, issue 19):
// a removal must not make a coarse ridge sharper than the original is where it lies.
// Internal to libbpm.
//
// Why: removals that minimise |phi(x) - x| alone may fold the coarse surface along an
// edge that is not a crease of the original (femur at 10 %: 13 coarse ridge angles of
// 2.5 to 20 degrees, where no original edge is sharper than 24.6 and the sharpest original
// edge around each was 35 to 78). Such a ridge makes a thin tetrahedron out of the coarse
// surface itself (bpm-mesh: the two triangles are faces of the volume mesh: 4.99 degrees),
// the refined surface through phi would intersect itself near it (bpm-refine --max-error
// held vertices back there), and phi squeezes the original into the thin wedge. Measured
// with the floors 0 to 50: bench/RESULTS.md, "Coarse ridges".
//
// The angle: ridge_angle_degrees (core/crease.h), 180 minus the angle between the two
// normals: the interior dihedral angle of a convex edge, the exterior one of a concave
// edge; folds either way count.
//
// The rule, per removal: let `sharpest_new` be the smallest ridge angle over the coarse
// edges whose triangles the removal changes and that are not feature edges (its new
// diagonals, whose both triangles are new; the sides of its hole, whose one triangle is
// new, counted only where the new triangle makes the ridge sharper than the removed one
// did), and `sharpest_original` the smallest ridge angle of the original edges at the
// original vertices in the removed star (its corners, the vertices inside its triangles
// and on its spokes, for a vertex on a feature line the vertices on the feature line).
// The removal is refused when
//     sharpest_new < min(min_ridge_angle_degrees, sharpest_original - kRidgeMargin):
// never sharper than the floor where the original is smoother, and never much sharper
// than the original where the original itself is sharper than the floor. Feature edges
// (creases, boundaries, patch borders, non-manifold edges) are exempt: they follow the
// original's feature lines as before, and so is the new feature edge of a removal on a
// feature line (so coarse crease edges of a scan's noise creases may still be sharp:
// femur's are 11 degrees; guarding creases too cost femur 1.13x in distance). An edge
// already sharper than the limit (the input's own sharp edges when feature lines are
// off) may stay as it is, only not get sharper.
//
// The final edge flips (simplify/edge_flip.h) follow the same rule: the flip's new edge
// is a diagonal, the four sides of its quad are sides of the hole (each keeps its
// triangle outside the quad and gets a new one inside: a flip can fold a side onto its
// neighbour while its new edge stays flat), and the original vertices are the quad's
// corners and those inside it (in its two triangles and on the old edge).
//
// Floating point: the angles are measured, not topological decisions; the comparison is
// deterministic (the same operations in the same order on every thread).

#include <algorithm>
#include <cstdint>
#include <vector>

#include "bpm/geometry.h"
#include "bpm/surface.h"
#include "simplify/coarse_mesh.h"
#include "simplify/embedding.h"

namespace bpm::detail {

// Degrees below the original's sharpest ridge angle in the region that a new ridge may
// still have (when that is below the floor): ridges of the coarse surface are straighter
// than the original's noisy ones, a little sharper is fine.
constexpr double kRidgeMargin = 5.0;

// The rule, for a removal (removal_cost) and an edge flip (edge_flip.cpp): refused when
// the sharpest ridge the change makes (sharpest_changed_ridge) is below `floor_degrees`
// (min_ridge_angle_degrees) and below the original's sharpest ridge where the change lies
// (vertex_ridge_angles over the original vertices it covers) minus kRidgeMargin.
inline bool ridge_too_sharp(double sharpest_new, double sharpest_original, double floor_degrees) {
    return sharpest_new < std::min(floor_degrees, sharpest_original - kRidgeMargin);
}

// Per original vertex: the smallest ridge angle (degrees) of the original edges at it
// that have exactly two triangles; 180 if it has none. #V0 entries. `embedding`: of
// `original` (its edges and their triangles).
std::vector<float> vertex_ridge_angles(const Surface& original, const Embedding& embedding);

// The buffers of sharpest_changed_ridge (plans are made millions of times).
struct HoleSide {
    int32_t added;    // the added triangle on it
    int32_t k;        // its edge added[k], added[(k + 1) % 3]
    int32_t outside;  // the alive triangle on it outside the removed ones
    int32_t inside;   // the removed triangle on it
};
struct RidgeScratch {
    std::vector<Vec3> normals;    // of the added triangles
    std::vector<HoleSide> sides;  // the sides of the hole that are judged
};

// The smallest ridge angle (degrees) the change of `removed` (alive triangles of `mesh`)
// into `added` makes, over the edges of `added` that are not feature edges of `mesh`
// and not (feature_a, feature_b) (the new feature edge, or -1, -1): the edges shared by
// two added triangles, and the edges an added triangle shares with exactly one triangle
// of `mesh` outside `removed` where the ridge gets sharper than it was with the one
// triangle of `removed` there. Edges with another number of triangles are left out.
// 180 if none.
// `hole_sides` (optional, 3 entries per added triangle: edge k of added[i] at 3 i + k):
// the removed triangle on that edge where the caller knows it to be a side of the hole
// (the planner does: side j of a fan is the edge of its triangle j), -2 - j where it knows
// the edge to be a diagonal whose only other added triangle is added[j], else -1; the
// edges marked -1 and all edges without it are found by searching `added` and the two
// corners' triangle lists. The result is the same either way: a side has no other added
// triangle on it (a diagonal is never an existing edge: the topology condition), and its
// triangles outside `removed` are found from the lists alone.
double sharpest_changed_ridge(const CoarseMesh& mesh, const std::vector<int32_t>& removed,
                              const std::vector<Tri>& added, int32_t feature_a, int32_t feature_b,
                              RidgeScratch& scratch, const std::vector<int32_t>& hole_sides = {});

}  // namespace bpm::detail
