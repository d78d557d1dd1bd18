#pragma once
// Refinement of the coarse surface S through phi: every coarse triangle is subdivided in
// its parameter triangle, and every new vertex is placed at phi of its parameter
// position, i.e. on the original surface S0 (Krause & Sander §1: the coarse grid of a
// multigrid hierarchy is refined and the new vertices are moved onto the boundary with
// the boundary parametrization). How a solver places a vertex itself is described in
// spec/refinement.md.
//
// Uniform refinement splits each coarse triangle into 4^levels congruent triangles in
// parameter space (red refinement at edge midpoints; a midpoint of an edge shared by
// two triangles is one vertex). Adaptive refinement red-refines only triangles whose
// phi-image deviates from the flat triangle by more than a tolerance (computed exactly
// over the overlay of the triangle with the pieces of phi), keeps the mesh 1-irregular,
// and closes it with green bisections at the end, so the result is conforming (no
// hanging nodes).

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "bpm/context.h"
#include "bpm/parametrization.h"
#include "bpm/surface.h"

namespace bpm {

struct RefineOptions {
    // Uniform: each coarse triangle into 4^levels triangles. -1 = adaptive (tolerance).
    // Both (levels >= 0 and a tolerance other than 0) is an OptionError.
    int levels = -1;
    // Adaptive: split triangles whose phi-image deviates from the flat triangle by more
    // than this fraction of the bounding-box diagonal of S0 (> 0), measured exactly (max
    // over the overlay of the triangle with phi's pieces, held-back vertices where they
    // end up; on a planar region only what its bound depends on, the region's boundary and
    // offsets from the plane, not phi's drift within the plane): every triangle that is
    // not at max_level ends within it, a proven two-sided Hausdorff bound (RefineResult).
    double tolerance = 0.0;
    // Adaptive: never refine a coarse triangle more than this many times. Only triangles
    // above the tolerance are split, so the levels past 8 are reached only where they are
    // needed: where phi squeezes pieces of S0 into slivers that cross the refined
    // triangles (a fold), |flat - phi| falls only with the triangles' size (femur 10 % at
    // 0.0003: 1.37e-3 at level 8, 5.1e-4 at level 10; the sampled distance 3.9e-4 ->
    // 3.0e-4, 313772 -> 327382 triangles). It was 8.
    int max_level = 10;
    // Hold new vertices back from phi where the refined surface would intersect itself
    // (the lambda remedy of Krause & Sander §3.3, on the surface, made hierarchical): a
    // vertex of an intersecting pair of triangles (exact test, bpm::check_intersections)
    // moves to m + f (phi - m), m the current midpoint of its parent edge's ends (the
    // vertices it is the midpoint of in parameter space), with f halved per round and 0
    // after 10 halvings; a vertex that still intersects at m holds back its parents
    // instead (recursively up to the coarse vertices, which never move) and follows them.
    // So a held-back vertex is off phi by at most its ancestors' chord deviations (halved
    // per level), not by the distance to the coarse surface. With every fraction 0 every
    // vertex is on the coarse surface, which does not intersect itself, so this ends. Then
    // five bisection steps between each vertex's free and last intersecting fraction bring
    // the held-back vertices back towards phi as far as they stay free of intersections
    // (RefinedSurface::vertex_phi_fraction); adaptive refinement then tries each vertex
    // still held back farther than the tolerance alone at phi, and bisects it alone four
    // times where that intersects. Adaptive refinement measures the deviation
    // again with the vertices where they end up, refines the triangles still above the
    // tolerance and runs the remedy again (RefineResult::adaptive_passes). Off by default
    // in the library so that a measure of phi (bpm::refined_quality) sees the vertices at
    // phi; bpm-refine turns it on.
    bool prevent_intersections = false;
};

// A refined surface and where each of its vertices / triangles comes from.
struct RefinedSurface {
    Surface surface;  // vertices at phi of their parameter positions; patch of the coarse triangle
    // Per vertex (#V): one coarse triangle containing it and the barycentric coordinates there.
    std::vector<int32_t> vertex_coarse_triangle;
    std::vector<Vec3> vertex_barycentric;
    // Per vertex (#V): the original triangle containing its image and the barycentric
    // coordinates there (PhiSample), for interpolating data given at original vertices.
    std::vector<int32_t> vertex_original_triangle;
    std::vector<Vec3> vertex_original_barycentric;
    // Per triangle (#T): its coarse triangle, its corners' barycentric coordinates in that
    // coarse triangle (exact dyadic fractions), and its refinement level (green halves
    // have the level of the triangle they split).
    std::vector<int32_t> triangle_coarse;
    std::vector<std::array<Vec3, 3>> triangle_barycentric;
    std::vector<int32_t> triangle_level;
    // Per vertex (#V): where it is between the current midpoint of its parent edge's ends
    // (0; RefineOptions::prevent_intersections) and phi of its parameter position (1):
    // below 1 only where the remedy held it back, and exactly 1 (the vertex at phi) for
    // every other vertex. Coarse vertices 1. A vertex at 0 lies where its parents are
    // held back to, and on the coarse surface only if they all are.
    std::vector<double> vertex_phi_fraction;
    // Per triangle (#T): a proven bound, relative to the diagonal of S0, of the distance
    // from every point of the triangle as returned (held-back vertices where they are) to
    // S0 and from every point of its image phi(triangle) to the refined surface: max
    // |x - phi(x)| over the triangle, computed exactly over its overlay with phi's pieces
    // (then also a bound of the two-sided Hausdorff distance between the triangle and
    // phi(triangle)), or, where that is smaller, the bound of the planar region it lies in:
    // on coarse triangles that lie with their image in one plane, the region's boundary
    // and offsets from the plane bound the distance, and phi moving points within the
    // plane (tangential drift, no geometric error) does not count.
    std::vector<double> triangle_bound;
};

struct RefineResult {
    int64_t coarse_triangles = 0;
    int64_t vertices = 0, triangles = 0;
    int32_t max_level = 0;            // deepest level reached
    // Max over the refined triangles of max |flat - phi| / diagonal, computed exactly at the
    // corners of the overlay of each triangle with phi's pieces (phi and the flat triangle
    // are affine on each overlay cell), with every vertex at phi. (It was sampled at 7 points per
    // triangle, an estimate that the true distance exceeded.)
    double max_estimated_error = 0.0;
    // Proven upper bound of the two-sided Hausdorff distance between the refined surface
    // (as returned, held-back vertices included) and S0, relative to the diagonal of S0:
    // the largest RefinedSurface::triangle_bound (at most max_estimated_error +
    // max_held_back; it was that sum). phi pairs every point of the refined surface with a
    // point of S0 no farther than that, and maps onto all of S0; on planar regions the
    // region's bound holds for both directions (refine.cpp, "PLANAR REGIONS").
    double hausdorff_bound = 0.0;
    // Adaptive: triangles whose triangle_bound is above the tolerance, and those of them at
    // max_level (refining was stopped there; the others only if the passes ran out). The
    // tolerance is met, hausdorff_bound <= tolerance, exactly when the first is 0.
    int64_t triangles_above_tolerance = 0;
    int64_t triangles_at_max_level_above_tolerance = 0;
    // Adaptive with prevent_intersections: rounds of "refine, hold back, measure again";
    // a triangle above the tolerance after the remedy is refined further (up to 12 passes;
    // the result is the pass with the smallest bound, of equal bounds the one with fewer
    // triangles above the tolerance; the passes stop early at a pass that
    // lowers neither the bound nor the number of triangles above the tolerance, or when that
    // number passes 8 times the first pass's (at least 64): refining is then not helping).
    int32_t adaptive_passes = 0;
    // RefineOptions::prevent_intersections: vertices held back from phi, the largest
    // distance from phi of one (relative to the diagonal of S0), rounds of the remedy.
    int64_t held_back_vertices = 0;
    double max_held_back = 0.0;
    int32_t remedy_rounds = 0;
    double seconds = 0.0;
};

// \pre `param` passed check_format (e.g. read with read_bpm or made by simplify).
// \throw bpm::OptionError if neither levels >= 0 nor tolerance > 0 is given, or levels > 10.
// Coarse vertices keep their positions exactly (levels = 0 returns the coarse surface).
RefineResult refine(const Parametrization& param, const RefineOptions& options, const Context& context,
                    RefinedSurface& out);

// The refined surface as a new parametrized surface: S' = refined.surface is the coarse
// surface and phi' = phi o (S' -> S). The .bpm format needs every coarse vertex to be an
// original vertex and every piece to map into one original triangle, so the original
// surface of the result is S0 re-triangulated (same geometry, every triangle of S0
// subdivided flat) by the overlay of the pieces of phi and the refined triangles: its
// vertices are those of S0 (same indices first), then the former edge crossings of phi,
// the refined vertices and the points where refined edges cross piece edges. Each piece
// of phi' is one triangle of that surface, so phi' has only CoarseCorner and
// OriginalVertex nodes. Patches are kept.
// \throw bpm::AlgorithmError if the overlay could not be built consistently, in practice
//        when a node of phi lies within rounding distance of a refined edge without being
//        on it (the polygon between them is too thin for double precision).
Parametrization refined_parametrization(const Parametrization& param, const RefinedSurface& refined,
                                        const Context& context = {});

// Area-weighted vertex normals of a surface (unit length; zero for unreferenced vertices).
std::vector<Vec3> vertex_normals(const Surface& surface);

// Interpolates per-original-vertex data (#V0 rows of `components` values, row-major)
// onto the refined vertices through phi (original triangle + barycentric coordinates).
// \throw std::invalid_argument if data.size() != #V0 * components.
std::vector<double> transfer_vertex_data(const RefinedSurface& refined, const Surface& original,
                                         const std::vector<double>& data, int components);

// Writing the refined surface with point data: write_surface_vtu in bpm/write_vtu.h.

}  // namespace bpm
