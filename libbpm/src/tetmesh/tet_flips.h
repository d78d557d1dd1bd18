#pragma once
// Topological flips that raise the smallest dihedral angle of a tetrahedral mesh without
// moving a vertex (not public API; generate_tetmesh and refine_tetmesh run it).
//
// Why: TetGen keeps S exactly (-Y) and its radius-edge refinement does not see slivers, so
// the worst tetrahedra it leaves are flat ones with all four corners on S, which smoothing
// the interior vertices cannot reach. Replacing two or three tetrahedra by three or two
// others on the same vertices often removes them.
//
// Flips, tried on every tetrahedron whose smallest dihedral angle is below target_degrees,
// worst first, in sweeps:
//   2-3: two tetrahedra (a,b,c,d), (a,b,c,e) sharing the face abc become (a,b,d,e),
//        (b,c,d,e), (c,a,d,e) around the new edge de;
//   3-2: the three tetrahedra around an edge ab whose ring is exactly c, d, e become
//        (c,d,e,a) and (c,d,e,b) (the inverse);
// (B. Joe, "Construction of three-dimensional improved-quality triangulations using local
// transformations", SIAM J. Sci. Comput. 16, 1995; Klingner & Shewchuk, "Aggressive
// tetrahedral mesh improvement", IMR 2007, for flips driven by the smallest dihedral angle).
// A flip is made only if
//   - the face or the three faces it removes are not faces on S (`protected_faces`: the
//     boundary and the interfaces between regions) and all tetrahedra involved have the
//     same region and, when `ancestor` is given, the same ancestor (so each level-0
//     tetrahedron's descendants keep covering exactly it);
//   - every new tetrahedron is positively oriented (exact orient3d, bpm/predicates.h) and
//     the new edge or face is not already in the mesh (the result is again a conforming
//     mesh of the same regions with the same faces on S);
//   - the smallest dihedral angle over the new tetrahedra is strictly larger than over the
//     old ones (floating point, pseudo-angles as in tetrahedron_quality.h). Of the flips a
//     tetrahedron allows, the one with the largest new smallest angle is made.
// So the sorted list of the tetrahedra's smallest angles grows lexicographically with every
// flip and the minimum of the mesh never decreases; the pass ends when a sweep flips
// nothing or after `sweeps` sweeps. Vertices never move; faces on S are kept (same vertices,
// same tetrahedra on their sides up to replacement by same-region ones). Deterministic:
// fixed visiting order (quality, then index), no hashing.

#include <cstdint>
#include <vector>

#include "bpm/geometry.h"
#include "bpm/tetmesh.h"

namespace bpm::detail {

struct TetFlipOptions {
    // Tetrahedra with a smaller dihedral angle are visited (the smoothing's target). Femur
    // at 1000 vertices, level 3: 15 leaves 544 tetrahedra below 10 degrees (4228 flips,
    // 3.2 s), 10 leaves 630 (768 flips, 1.8 s); the minimum is the same.
    double target_degrees = 15;
    int sweeps = 8;              // at most this many passes over them
    // Make no tetrahedron with a surface corner (a corner whose three edges are edges of
    // `protected_faces`; tetmesh/tet_split.h): at level 0 after split_surface_corners, so
    // that the flips do not bring back what the splits removed.
    bool keep_surface_corners_out = false;
};

struct TetFlipResult {
    int64_t flips_23 = 0;
    int64_t edge_removals = 0;                // 3-2, 4-4, 5-6, ... flips
    int64_t visited = 0;                      // tetrahedra below the target at the start
    double min_dihedral_before_degrees = 0;   // smallest angle of the mesh (signed, as tetrahedron_quality.h)
    double min_dihedral_after_degrees = 0;
    int sweeps = 0;                           // sweeps run
    double seconds = 0;
};

// Flips the tetrahedra `tets` over the vertices x (see the top of this file). tets[t] is
// positively oriented, or negatively where (*negative)[t] (negative may be null: all
// positive); the tetrahedra a flip makes are positively oriented (negative false). regions
// (#Tet) and ancestor (#Tet, or null) follow the tetrahedra; tetrahedra a flip removes are
// dropped, those it makes are appended or take a removed one's index. created (optional)
// gets #Tet flags: 1 for the tetrahedra made by flips. \pre the mesh is conforming (each
// face in at most two tetrahedra) and its tetrahedra are positively oriented as stated.
TetFlipResult flip_tetrahedra(const std::vector<Vec3>& x, std::vector<Tet>& tets, std::vector<bool>* negative,
                              std::vector<int32_t>& regions, std::vector<int32_t>* ancestor,
                              const std::vector<Tri>& protected_faces, const TetFlipOptions& options,
                              std::vector<char>* created = nullptr);

}  // namespace bpm::detail
