#pragma once
// Vertex insertion, the last resort of the sliver removal after the flips (not public API;
// generate_tetmesh runs it at level 0).
//
// Why: a flat tetrahedron with all four corners on S but no face on S can be locked: every
// 2-3 flip and edge removal makes it worse (fandisk at 1000 vertices: 2.94 degrees, both
// long diagonals with four tetrahedra around them), and smoothing cannot move its corners.
// A new vertex inside it can: Klingner and Shewchuk, "Aggressive tetrahedral mesh
// improvement", IMR 2007, section 3.3.
//
// For each tetrahedron t below target_degrees, worst first (quality, then index), in up to
// `rounds` passes (a star's new tetrahedra may be tried in the next): a cavity is t plus
// tetrahedra of t's region reached without crossing a face on S (`protected_faces`), and a
// new vertex p is connected to each face of the cavity's boundary (the star of p). The
// cavities tried: t with each non-empty subset of its face neighbours, and t with all
// tetrahedra around one or both of its two largest-angle edges when they are obtuse, with
// and without the face neighbours (a flat sliver's two long edges cross; unless their rings
// are in the cavity they stay reflex edges of it, one just above and one just below p).
// p starts at the centroid of t and moves by a compass search (the six axis directions,
// steps halving from a quarter of t's longest edge) that maximises the smallest dihedral
// angle of the star. The best star over the cavities replaces its cavity when
//   - the cavity's boundary is a closed 2-manifold through every corner of the cavity (each
//     boundary edge in exactly two boundary faces), no face inside it is on S;
//   - every new tetrahedron is positively oriented (exact orient3d, bpm/predicates.h);
//   - its smallest dihedral angle is strictly larger than the cavity's.
// With all cones from p positive the star covers the cavity exactly once, so the result is
// a conforming mesh of the same regions with the same faces on S (same vertices and
// tetrahedra on their sides up to replacement by same-region ones) and the same volume per
// region; p is strictly inside a region. Existing vertices never move. Deterministic.

#include <cstdint>
#include <vector>

#include "bpm/geometry.h"
#include "bpm/tetmesh.h"

namespace bpm::detail {

struct TetInsertOptions {
    double target_degrees = 15;  // tetrahedra with a smaller dihedral angle are tried (the flips' target)
    // Passes over the tetrahedra below the target (those the last pass made included); the
    // insertion stops after a pass that inserts nothing. One: with 3, femur 10 % and at 1000
    // vertices and fandisk at 1000 vertices got the same smallest angles with 1.6-1.7 times
    // the insertions.
    int rounds = 1;
};

struct TetInsertResult {
    int64_t inserted = 0;                     // new vertices (one per replaced cavity)
    int64_t tried = 0;                        // tetrahedra below the target at the start
    int rounds = 0;                           // passes run
    double min_dihedral_before_degrees = 0;   // smallest angle of the mesh (signed, as tetrahedron_quality.h)
    double min_dihedral_after_degrees = 0;
    double seconds = 0;
};

// Inserts vertices into `tets` over x (see the top of this file). Every tetrahedron is
// positively oriented; regions (#Tet) follow them. New vertices are appended to x, new
// tetrahedra to tets (replaced ones are dropped, keeping the order of the rest).
// \pre the mesh is conforming (each face in at most two tetrahedra).
TetInsertResult insert_vertices(std::vector<Vec3>& x, std::vector<Tet>& tets, std::vector<int32_t>& regions,
                                const std::vector<Tri>& protected_faces, const TetInsertOptions& options);

}  // namespace bpm::detail
