#pragma once
// A triangulated surface: one material or several, manifold or not.
//
// Connectivity is only the triangle list; adjacency (edges with all their incident
// triangles, components, boundary loops, feature lines) is derived on demand by
// bpm/surface_topology.h. Nothing here assumes a manifold.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bpm/geometry.h"

namespace bpm {

// A named per-vertex data array of a surface: a scalar field (1 component), a vector
// (normals: 3), colours, ... as read from PLY vertex properties or VTK POINT_DATA.
// Carried through bpm files (/original/point_data) onto refined surfaces (bpm-refine --data).
struct VertexArray {
    std::string name;            // unique within the surface; no '/', not "." or empty
    int components = 1;          // values per vertex, >= 1
    std::vector<double> values;  // #V * components, row-major (vertex v at [v * components, (v+1) * components))
};

struct Surface {
    std::vector<Vec3> vertices;     // #V positions, double precision
    std::vector<Tri> triangles;     // #T triangles, indices into `vertices`
    std::vector<int32_t> patches;   // #T patch (material interface / group) id per triangle; same size as triangles
    std::vector<VertexArray> vertex_data;  // optional per-vertex arrays; the repairs below keep them in step

    int32_t num_vertices() const { return static_cast<int32_t>(vertices.size()); }
    int32_t num_triangles() const { return static_cast<int32_t>(triangles.size()); }
};

// Axis-aligned bounding box diagonal length; 0 for an empty surface. All relative
// tolerances in bpm (errors, edge lengths) are fractions of this length so that
// results do not depend on the model's units.
double bounding_box_diagonal(const Surface& surface);
double bounding_box_diagonal(const std::vector<Vec3>& points);

// Problems that make a surface unusable as bpm input. validate_surface() lists
// them all (up to a limit) instead of stopping at the first.
struct SurfaceProblem {
    enum class Kind {
        NonFiniteCoordinate,  // element = vertex index
        IndexOutOfRange,      // element = triangle index
        RepeatedCorner,       // element = triangle index (two corners are the same vertex)
        ZeroArea,             // element = triangle index (collinear corners, exact test)
        DuplicateTriangle,    // element = triangle index (same three vertices as `other`)
        UnreferencedVertex,   // element = vertex index
        DuplicateVertex,      // element = vertex index (same position as `other`)
        PatchCountMismatch,   // patches.size() != triangles.size() (element = patches.size(), other = triangles.size())
    };
    // `other`: IndexOutOfRange -> the offending index; RepeatedCorner -> the repeated
    // vertex; DuplicateTriangle / DuplicateVertex -> the smallest index of the same set /
    // position (problems are reported for the later elements only).
    Kind kind;
    int64_t element = -1;
    int64_t other = -1;
    // "triangle 17: zero area (its three corners are collinear)"; see also describe_problem.
    std::string describe() const;
};

// describe() with details looked up in the surface the problem was found in: the vertex
// indices of a triangle, which corners repeat, which coordinate is NaN, positions.
std::string describe_problem(const SurfaceProblem& problem, const Surface& surface);

struct ValidateOptions {
    bool allow_unreferenced_vertices = false;
    bool allow_duplicate_vertices = false;
    size_t max_problems = 20;  // stop after this many; 0 = no limit
};

// Checks in this order, each in index order: patch count, non-finite coordinates, per
// triangle (index range, repeated corner, zero area by the exact collinear3d), duplicate
// triangles (same vertex set in any order), unreferenced vertices, duplicate vertices
// (identical coordinates; -0 equals +0). Deterministic.
std::vector<SurfaceProblem> validate_surface(const Surface& surface, const ValidateOptions& options = {});

// The range of coordinates bpm computes in: no |coordinate| above kMaxCoordinate, and a
// bounding box whose largest side is at least kMinExtent. bpm's shape and error measures
// square lengths and multiply squares (aspect_ratio: a length^4 over a length^4), which
// overflow double precision near 1e77 and lose every digit to underflow near 1e-77;
// bpm-simplify removed nothing on a sphere of radius 1e78 and blamed "input slivers",
// and TetGen aborted below a diagonal of about 1e-52. 1e40 keeps a margin of 1e37 to
// both, far beyond any physical model in any length unit. (Scaling internally would have
// to reach every tool, the Python module, the adapters and TetGen's input; a model
// outside the range is rescaled once by its user instead.)
inline constexpr double kMaxCoordinate = 1e40;
inline constexpr double kMinExtent = 1e-40;

// Why the surface's coordinates are outside that range, with the values found and what
// to do (rescale, i.e. express the model in another length unit); empty when they are
// inside it, or when a coordinate is NaN/Inf or there are no vertices (validate_surface
// reports those). simplify, refine, smooth and generate_tetmesh refuse such surfaces
// (AlgorithmError with this text), check_format reports them (a .bpm written elsewhere).
std::string coordinate_range_problem(const Surface& surface);

// Repairs that only happen on request (tools: --merge-duplicate-vertices,
// --drop-unreferenced-vertices). Each returns how many elements it changed.
// Both keep the surviving vertices in their original order (a merged group is kept at
// its smallest index, with that vertex's data) and renumber the triangles; triangle order and patches are not
// touched, so merging may leave repeated corners or duplicate triangles for
// validate_surface() to report. Vertices with NaN/Inf coordinates are never merged.
// Problems of the vertex data (wrong size, components < 1, empty, repeated or
// unstorable name), one line each, e.g. "vertex data 'u': 12 values for 5 vertices x 3
// components"; empty if none.
std::vector<std::string> vertex_data_problems(const Surface& surface);

// Several surfaces as one, e.g. one file per material (bpm-simplify A.stl B.stl ...):
// vertices and triangles appended in order; patch ids renumbered 0, 1, 2, ... by
// (part, patch) in order of first use, so that patches of different parts never merge;
// vertex data arrays that every part has with the same name and components are kept,
// the others dropped. `patch_origin`, if given, receives for every new patch id its
// (part index, patch id in that part); `dropped_arrays` the names of dropped arrays.
Surface combine_surfaces(const std::vector<Surface>& parts,
                         std::vector<std::pair<int, int32_t>>* patch_origin = nullptr,
                         std::vector<std::string>* dropped_arrays = nullptr);

int64_t merge_duplicate_vertices(Surface& surface);   // exact position equality

// Repair (merge vertices within a distance) for seams left open by rounding: a CAD
// export or a conversion that writes both sides of a seam with positions a few ulps or
// 1e-9 of the model apart. In index order, every vertex either joins the first
// (smallest index) vertex kept so far that is within `distance` of it, taking its
// position, or is kept itself; so vertices move by at most `distance`, and the result
// depends only on the input. Exact duplicates merge at any distance >= 0; vertices with
// a NaN or infinite coordinate never merge. If the merge would give a triangle two equal
// corners (the distance is not small against the triangles), nothing is changed and
// collapsed_triangle names the first such triangle, with the two corners.
struct CloseVertexMerge {
    int64_t merged = 0;             // vertices removed
    double largest_move = 0.0;      // the largest distance a merged vertex moved
    int32_t collapsed_triangle = -1;
    std::array<int32_t, 2> collapsed_corners{-1, -1};  // its two vertices that would be merged
};
CloseVertexMerge merge_close_vertices(Surface& surface, double distance);

// An open seam: boundary edges (edges of one triangle) whose two ends are each within
// `max_gap` of the ends of another boundary edge, so that merging vertices within a
// little more than `gap` would join them (merge_close_vertices). Empty if no boundary
// edge pairs up that way.
struct OpenSeam {
    int64_t boundary_edges = 0;  // of the whole surface
    int64_t paired_edges = 0;    // those that pair up with another
    double gap = 0.0;            // the largest distance between paired ends
    std::array<int32_t, 2> first_edge{-1, -1};  // the paired edge with the smallest vertices
};
std::optional<OpenSeam> find_open_seam(const Surface& surface, double max_gap);
// Boundary edges closer than this fraction of the bounding-box diagonal to another one
// are taken for an open seam: far below any modelled gap, far above rounding (binary
// STL's float32 coordinates round at 6e-8 of their magnitude).
constexpr double kOpenSeamMaxGap = 1e-6;
// The merge tolerance, as a fraction of `diagonal`, that closes `seam` (found on
// `surface`): the smallest power of 10 at least twice its gap, if merging within it
// closes some of the seam's edges and collapses no triangle (tried on a copy); else 0.
double seam_merge_tolerance(const Surface& surface, const OpenSeam& seam, double diagonal);
int64_t drop_unreferenced_vertices(Surface& surface);

// Repair (--merge-duplicate-triangles) for one closed surface per material read together:
// an interface between two materials is then in both files, as the same triangles in
// opposite orientation (once the touching files share vertices, see
// merge_duplicate_vertices). Every set of triangles with the same three vertices (any
// order and orientation) becomes its first triangle (smallest index, its orientation);
// the others are removed, the order of the rest is kept. A set whose triangles had
// different patches gets a new patch, one per distinct set of patches, numbered from the
// largest patch + 1 in order of first use: the interface is then a patch of its own, a
// sheet between the materials. `interfaces`, if given, receives every new patch with the
// patches it joins (sorted). Triangles with repeated corners or vertex indices out of
// range are left for validate_surface() to report. Returns the number of triangles removed.
struct FusedPatch {
    int32_t patch = -1;
    std::vector<int32_t> joins;  // the patches whose triangles became this patch's
    int64_t triangles = 0;       // how many fused triangles it has
    // The patch whose triangles were kept (the first of each set, with its orientation)
    // when that is the same patch for every set; -1 when it differs between sets.
    int32_t kept_from = -1;
};
int64_t fuse_duplicate_triangles(Surface& surface, std::vector<FusedPatch>* interfaces = nullptr);

}  // namespace bpm
