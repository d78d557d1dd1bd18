#pragma once
// Tetrahedral volume meshes whose boundary is the coarse surface S (bpm-mesh).
//
// generate_tetmesh() writes S as a TetGen piecewise linear complex (one facet per coarse
// triangle, facet marker = patch id, one region point strictly inside every bounded
// region), runs the `tetgen` executable (Debian package `tetgen`) with -p -Y -q -A, and
// reads the mesh back. -Y keeps S exactly: every coarse triangle is a face of the tet
// mesh, and the first #S.V tet-mesh vertices are the coarse vertices, in order.
//
// Regions are the connected components of R^3 minus S; the unbounded one is not meshed.
// They are numbered 1, 2, ... in the order of the first coarse triangle side that bounds
// them: side 2t is the front of coarse triangle t (where its normal points), 2t+1 the back.
// For a single closed outward-oriented surface the one region is 1.
//
// References: H. Si, "TetGen, a Delaunay-based quality tetrahedral mesh generator",
// ACM TOMS 41(2), 2015 (the .poly/.node/.ele formats); spec/tetmesh.md for the /tetmesh
// group of a .bpm file.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bpm/context.h"
#include "bpm/geometry.h"
#include "bpm/parametrization.h"
#include "bpm/patch_info.h"
#include "bpm/surface.h"
#include "bpm/surface_point.h"
#include "bpm/tetmesh_smooth_options.h"

namespace bpm {

using Tet = std::array<int32_t, 4>;

// In-memory twin of the /tetmesh group (spec/tetmesh.md); names match the datasets.
// Every tetrahedron is positively oriented: det[x1-x0, x2-x0, x3-x0] > 0, i.e.
// orient3d(x0, x1, x2, x3) == +1 (CGAL::POSITIVE; e.g. (0,0,0), e1, e2, e3), as Gmsh, VTK
// and MEDIT expect.
struct TetMesh {
    std::vector<Vec3> vertices;             // #V positions
    std::vector<Tet> tetrahedra;            // #Tet four vertex indices, positive orientation
    std::vector<int32_t> regions;           // #Tet region id >= 1 of each tetrahedron
    // Boundary and interface faces: every face of the mesh that lies on S, once, oriented
    // like the coarse triangle it lies on (each coarse triangle exactly, at level 0; its
    // 4^level red-refinement children after tet_refine).
    std::vector<Tri> faces;                 // #F
    std::vector<int32_t> face_coarse_triangle;  // #F the coarse triangle the face lies on
    std::vector<int32_t> face_patches;          // #F = coarse patch of face_coarse_triangle
    // Where each vertex sits on S, so that a solver can apply phi (bpm/phi_evaluation.h):
    std::vector<int32_t> vertex_coarse_vertex;        // #V the coarse vertex it is, or -1
    // #V its parameter point: a coarse triangle containing it and its barycentric
    // coordinates there; invalid (triangle -1, barycentric {0,0,0}) for interior vertices.
    // Stored as the datasets vertex_parameter_triangle and vertex_parameter_barycentric.
    std::vector<SurfacePoint> vertex_parameter_points;
    // Refinement level (0 = TetGen's mesh) and, for refined meshes, the level-0
    // tetrahedron each tetrahedron descends from (empty at level 0).
    int32_t level = 0;
    std::vector<int32_t> tet_ancestor;      // #Tet or empty
    // Materials (spec/tetmesh.md §3.7; both empty when not assigned, as in files before
    // format 1.3): region r is material region_material[r-1], an id in 1..#M named
    // material_names[id-1]. Several regions may share a material. Set by assign_materials
    // (bpm/tetmesh_materials.h); checked by find_material_inconsistency.
    std::vector<int32_t> region_material;     // #R (= num_regions()) or empty
    std::vector<std::string> material_names;  // #M distinct non-empty names

    int32_t num_vertices() const { return static_cast<int32_t>(vertices.size()); }
    int32_t num_tetrahedra() const { return static_cast<int32_t>(tetrahedra.size()); }
    int32_t num_regions() const;  // largest region id (ids are 1..R)
};

// The largest minimum-dihedral-angle bound (degrees) generate_tetmesh accepts. TetGen 1.5's
// -q<ratio>/<angle> refinement ran forever from 21 degrees on (armadillo; 22 femur, 25
// fandisk, 30 elephant) and finished quickly up to 20 on all of them (see generate_tetmesh).
inline constexpr double kMaxTetgenMinDihedralDegrees = 18.0;

// generate_tetmesh warns when a coarse triangle's aspect ratio R/r exceeds this (the
// default --max-aspect of bpm-simplify): TetGen keeps S exactly, so the tetrahedra on such
// a needle get small dihedral angles whatever the quality bounds.
inline constexpr double kSliverAspectRatio = 30.0;

struct TetMeshOptions {
    double quality = 1.414;          // TetGen -q: maximum radius-edge ratio, > 1.0 (about 1.1 is the practical limit)
    // TetGen -q<quality>/<angle>: minimum dihedral angle to aim for, in degrees, at most
    // kMaxTetgenMinDihedralDegrees (TetGen 1.5 does not terminate above it on real surfaces).
    std::optional<double> min_dihedral_degrees;
    std::optional<double> max_volume;  // TetGen -a: maximum tetrahedron volume, in units^3
    // TetGen -o/<angle>: the largest dihedral angle (degrees) TetGen's mesh optimisation
    // (flips and smoothing of its own vertices, never of S) aims below; TetGen's default
    // is 165. With S kept exactly (-Y), the slivers left at level 0 are flat tetrahedra
    // with two dihedral angles near 155-165 degrees, all four vertices on S, which the
    // dihedral refinement cannot split; a 150 bound makes TetGen flip them away
    // (bench/RESULTS.md "Tets without slivers": level-0 minimum elephant 10 % 4.92 ->
    // 6.89 degrees before smoothing, armadillo 4.07 -> 8.35). 0 = TetGen's default.
    double max_dihedral_degrees = 150.0;
    std::string tetgen = "tetgen";   // executable: a name looked up on PATH, or a path
    // Stop TetGen and throw ExternalToolError when its runs together take longer than
    // this many seconds (0 = no limit).
    double time_limit_seconds = 0;
    // Keep TetGen's temporary directory (its path is logged) instead of deleting it.
    bool keep_temporary = false;
    // Smooth TetGen's Steiner points (bpm/tetmesh_smooth.h); vertices on S do not move.
    bool smooth = true;
    TetSmoothOptions smoothing;
    // Flip tetrahedra below 15 degrees (2-3 flips and edge removals inside a region, never
    // a face on S; no vertex moves) where that raises the smallest dihedral angle: the
    // slivers TetGen leaves have all four corners on S, out of the smoothing's reach. Runs
    // before the smoothing. Femur at 1000 vertices: 3.41 -> 6.53 degrees. A tetrahedron with
    // two faces on S that meet at a sharp edge of S is fixed by S and stays. Then a new
    // interior vertex goes into each tetrahedron still below 15 degrees where that raises
    // its neighbourhood's smallest angle (Klingner & Shewchuk 2007; spec/tetmesh.md §3.6),
    // and the flips run again: fandisk at 1000 vertices, an interior sliver with four
    // corners on S that no flip improves, 2.94 -> 12.0 degrees.
    bool flip = true;
    // Split the tetrahedra with a *surface corner*, a corner whose three edges are all edges
    // of S (two faces on neighbouring coarse triangles, or three edges at a coarse vertex):
    // the longest of their edges not on S at its midpoint (a new interior vertex, which the
    // smoothing then places), or at the centroid when all six edges are on S; then vertex
    // insertion and flips (which make none again) widen the split tetrahedra. Why: refinement makes tetrahedra with four corners on S only below
    // such tetrahedra (their corner children, at every level), and phi flattens those onto
    // the smooth original surface (spec/tetmesh.md §3.6; src/tetmesh/tet_split.h).
    bool split_surface_corners = true;
};

struct TetMeshResult {
    int64_t vertices = 0, tetrahedra = 0, faces = 0, regions = 0;
    int64_t steiner_points = 0;      // vertices added (all strictly inside regions): TetGen's and the insertions
    int64_t flips = 0;               // flips made (options.flip): 2-3 flips and edge removals
    int64_t insertions = 0;          // vertices inserted into slivers no flip improves (options.flip)
    int64_t surface_corner_splits = 0;  // vertices inserted by options.split_surface_corners
    double flip_seconds = 0.0;       // flips and insertions
    double tetgen_seconds = 0.0;     // wall time of the TetGen runs
    double seconds = 0.0;            // wall time of the whole call
    std::string tetgen_command;      // the final command line as run
};

// Problems that make TetGen refuse or mangle a surface, found before TetGen runs:
// invalid triangles (validate_surface), boundary edges (an open surface), improper
// self-intersections and touching sheets (check_intersections). Throws
// bpm::AlgorithmError naming the first problem and where it is, e.g.
// "surface has 12 boundary edges, first at vertices 3-17 (TetGen needs closed surfaces)".
void check_meshable(const Surface& surface, const Context& context = {});

// Meshes the volume bounded by param.coarse (see the top of this file).
// TetGen runs in a process group of its own and never outlives the call: it is stopped on
// every exit path (time limit, cancellation, exceptions), killed by the kernel if the
// calling thread dies (PR_SET_PDEATHSIG), and its temporary directory is removed.
// The progress callback is polled every 50 ms while TetGen runs (a way to cancel it), and
// an info line is logged every 30 s of a TetGen run.
// \throw OptionError for a quality bound <= 1 or a dihedral bound above
//        kMaxTetgenMinDihedralDegrees (settings for which TetGen does not terminate);
//        AlgorithmError if check_meshable fails or TetGen's mesh does not contain S
//        exactly; ExternalToolError if tetgen is missing (naming the Debian package),
//        fails (with TetGen's own error output) or exceeds time_limit_seconds;
//        Cancelled through the progress callback.
TetMeshResult generate_tetmesh(const Parametrization& param, const TetMeshOptions& options, const Context& context,
                               TetMesh& out);

// Structural consistency (sizes, index ranges, region ids >= 1, face patches equal to the
// coarse patches, finite values, barycentrics >= 0 summing to 1 within 1e-9); empty when
// fine, otherwise the first problem, starting with the /tetmesh dataset name. The .bpm
// reader and writer use it.
std::string find_tetmesh_inconsistency(const TetMesh& mesh, const Surface& coarse);

// --- measurements ---------------------------------------------------------------

struct TetMeshStats {
    int64_t inverted = 0;            // tetrahedra that are not positively oriented (exact orient3d)
    // smallest and largest dihedral angle over all tetrahedra, unsigned (an inverted
    // tetrahedron counts with the angles of its mirror image, a flat one with 0)
    double min_dihedral_degrees = 0;
    double max_dihedral_degrees = 0;
    // tetrahedra whose smallest dihedral angle is below 1, 5 and 10 degrees
    int64_t below_1_degree = 0, below_5_degrees = 0, below_10_degrees = 0;
    std::vector<double> region_volumes;  // [r-1] = volume of region r (sum of signed tet volumes)
};
TetMeshStats tetmesh_stats(const TetMesh& mesh);

// For every region r (index r-1), the volume enclosed by the image phi(S) = S0 of its
// boundary: the sum over the coarse triangle sides bounding r of the signed cone volumes of
// phi's pieces. Compares the meshed volume with the volume of the original surface.
std::vector<double> region_volumes_on_original(const Parametrization& param, const TetMesh& mesh);

// Writing a mesh to .msh, .vtu or .mesh: bpm/write_tetmesh.h.

}  // namespace bpm
