#pragma once
// Edge flips of the coarse surface with phi re-embedded (issue 19 item 5): the flip of
// edge a -- b between triangles (a,b,c) and (b,a,d) replaces them by (a,d,c) and
// (d,b,c). The two triangles are unfolded into the plane about a -- b (each keeps its
// own shape), where the quad a, d, b, c must be strictly convex; the original surface on
// the quad keeps its place in that plane: the original vertices inside the quad are
// located in the new triangles, and every run of an original edge through the quad is
// straightened between its fixed points (the quad's sides and the original vertices) and
// cut where it crosses the new edge c -- d (exact orientation predicates decide). The
// result is validated like a removal's (overlay.h: the faces of both new triangles,
// exactly); a flip that fails is undone.
//
// The simplifier's final phase (flip_edges) uses it for the triangles that make slivers
// in the volume mesh: needles (R/r above a limit) and thin tetrahedra between two
// neighbouring triangles at a convex edge.

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "bpm/geometry.h"
#include "simplify/coarse_mesh.h"
#include "simplify/embedding.h"
#include "simplify/intersection_test.h"
#include "simplify/island_guard.h"

namespace bpm::detail {

// What a flip changes: two triangles out, two in (same patch), and the embedding edits.
struct EdgeFlip {
    int32_t a = -1, b = -1, c = -1, d = -1;  // edge a -- b becomes c -- d
    std::array<int32_t, 2> removed{-1, -1};  // (a,b,c) and (b,a,d)
    std::array<Tri, 2> added{};              // (a,d,c) and (d,b,c)
    int32_t patch = 0;
    // Original vertices that move; Inside refers to added[i] as a = -1 - i.
    std::vector<std::pair<int32_t, SurfacePoint>> new_locations;
    std::vector<std::pair<int32_t, std::vector<Crossing>>> new_paths;
};

// Plans the flip of coarse edge {x, y}. Fails with `why` when the edge is a feature
// edge or has other than two consistently oriented triangles, when c -- d exists
// already, when the unfolded quad is not strictly convex, or when an original vertex or
// a cut would fall on the new edge or its ends.
bool plan_edge_flip(const CoarseMesh& mesh, const Embedding& embedding, int32_t x, int32_t y, EdgeFlip& flip,
                    std::string& why);

// Applies a plan; returns the ids of the two new triangles.
std::array<int32_t, 2> commit_edge_flip(CoarseMesh& mesh, Embedding& embedding, const EdgeFlip& flip);

// Checks the overlays of triangles `ids` exactly (compute_faces, triangulate_faces) and
// returns their largest deviation |phi(p) - p| in `max_deviation`; false with `why`.
bool validate_flipped(const CoarseMesh& mesh, const Embedding& embedding, const std::vector<int8_t>& orientation_sign,
                      const std::array<int32_t, 2>& ids, double& max_deviation, std::string& why);

struct FlipLimits {
    // Needles: a triangle with R/r above this gets a flip of one of its edges if that
    // halves the worst R/r of the two triangles at least.
    double needle_aspect = 30.0;
    // Thin tetrahedra: a convex edge a -- b of a closed single-patch surface whose
    // tetrahedron (a,b,c,d) lies inside and has a dihedral angle below this (degrees) is
    // flipped if the new triangles are no worse than max(old worst R/r, needle_aspect).
    // 0 = off.
    double sliver_dihedral_degrees = 0.0;
    double max_deviation = 0.0;    // absolute: no flip may raise |phi(p) - p| above it
    double max_normal_turn = 60.0; // degrees between the new triangles' normals (no new crease)
    bool prevent_intersections = true;
    // The wedge guard's floors at junction edges and other feature edges (degrees;
    // simplify/wedge_guard.h): the quad's sides may be such edges.
    double junction_wedge_floor = 15.0, crease_wedge_floor = 5.0;
    // The corner-wedge guard's floor (degrees; simplify/corner_wedge_guard.h, which is off
    // on one patch); 0 = off.
    double corner_wedge_floor = 0.0;
    // The clearance guard's floor (simplify/clearance_guard.h: kClearanceFloor, or
    // kMultiPatchClearanceFloor on two or more patches), asked only with
    // prevent_intersections (it reads the intersection test's grid); 0 = off.
    double clearance_floor = 0.0;
    // The ridge guard's floor (degrees; simplify/ridge_guard.h, with flip_edges'
    // `vertex_ridges`): the quad's new edge and its four sides, as a removal's diagonals
    // and the sides of its hole; 0 = off.
    double min_ridge_angle_degrees = 0.0;
};

struct FlipStats {
    int64_t needle_flips = 0, sliver_flips = 0;
    int64_t refused = 0;  // planned or validated and refused (counted per attempt)
};

// Flips while any candidate improves (passes in triangle id order: deterministic).
// `islands`, if given, refuses flips that sweep another component (simplify/island_guard.h).
// `vertex_ridges`, if given and not empty: the original's vertex_ridge_angles
// (simplify/ridge_guard.h), for the ridge guard (FlipLimits::min_ridge_angle_degrees).
// A flip passes the guards a removal passes at its commit (sheet order, islands, feature
// and corner wedges, clearance, ridges), with the same floors.
FlipStats flip_edges(CoarseMesh& mesh, Embedding& embedding, const std::vector<int8_t>& orientation_sign,
                     IntersectionTest& intersections, const FlipLimits& limits, const IslandGuard* islands = nullptr,
                     const std::vector<float>* vertex_ridges = nullptr);

}  // namespace bpm::detail
