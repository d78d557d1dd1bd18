#pragma once
// General (non-manifold) connectivity and topological invariants of a Surface.
//
// Nothing here assumes a manifold: an edge keeps the list of all its incident
// triangles (CSR), components are found through shared edges, and the non-manifold
// structure (feature edges, feature vertices, feature lines with their number of
// sheets) is derived combinatorially, following Definition 2.4 and §2.4 of
// Krause & Sander, "Automatic construction of boundary parametrizations for geometric
// multigrid solvers" (the method of this library, see README.md).
//
// Used by the checker to compare a coarse surface with the original one: point
// removal keeps vertices, so feature vertices of the coarse surface are original
// vertices and can be compared by id; all other invariants are compared as numbers.
//
// \pre every triangle index is in range (validate_surface); a triangle with a repeated
//      corner has its repeated "edge" skipped. Vertices no triangle uses are ignored
//      (they are not part of the 2-complex).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "bpm/surface.h"

namespace bpm {

// Edges with all their incident triangles, and the triangles around each vertex.
struct SurfaceConnectivity {
    std::vector<std::array<int32_t, 2>> edges;    // #E (u, w) with u < w, sorted lexicographically
    std::vector<int64_t> edge_triangle_offsets;   // #E + 1, CSR into edge_triangles
    std::vector<int32_t> edge_triangles;          // incident triangles of each edge, ascending
    std::vector<std::array<int32_t, 3>> triangle_edges;  // #T: edge of local edge k (corner k -> k+1); -1 if degenerate
    std::vector<int64_t> vertex_triangle_offsets;  // #V + 1, CSR into vertex_triangles
    std::vector<int32_t> vertex_triangles;         // incident triangles of each vertex, ascending

    int32_t num_edges() const { return static_cast<int32_t>(edges.size()); }
    int32_t edge_degree(int32_t e) const {
        return static_cast<int32_t>(edge_triangle_offsets[e + 1] - edge_triangle_offsets[e]);
    }
    // Index of the edge {u, w} (either order); -1 if no triangle has it. O(log #E).
    int32_t find_edge(int32_t u, int32_t w) const;
};

SurfaceConnectivity build_connectivity(const Surface& surface);

// Why an edge is a feature edge. An edge is a feature edge when point removal must
// keep it as an edge of the coarse surface (it may only be shortened along its line):
//   Boundary     exactly 1 incident triangle
//   NonManifold  3 or more incident triangles (where 3+ sheets meet, §2.4)
//   Interface    exactly 2 incident triangles with different patch ids (a material
//                interface ends here even though the surface is manifold)
// Edges with 2 incident triangles of the same patch are regular.
enum class EdgeClass : uint8_t { Regular = 0, Boundary = 1, NonManifold = 2, Interface = 3 };

// A maximal chain of feature edges whose inner vertices are regular feature-line
// vertices (two feature edges, one half-disk fan per sheet between them), or a closed
// loop of such vertices.
struct FeatureLine {
    bool closed = false;
    int32_t first_vertex = -1;  // end vertices (feature vertices); for a closed loop, some vertex on it
    int32_t last_vertex = -1;
    int32_t sheets = 0;         // incident triangles of every edge of the line (1 = boundary)
    std::vector<int32_t> patches;  // sorted patch ids of the sheets (one entry per sheet)
    std::vector<int32_t> vertices; // in chain order, first .. last (closed: first not repeated)
    std::vector<int32_t> edges;    // #vertices - 1 (open) or #vertices (closed)
    int32_t component = -1;
};

// Invariants of one edge-connected component (triangles connected through shared edges).
struct ComponentSummary {
    int64_t vertices = 0, edges = 0, triangles = 0;
    int64_t euler_characteristic = 0;  // V - E + T of the component's own subcomplex
    bool orientable = true;      // consistent orientation exists across all 2-triangle edges
    bool manifold = true;        // no non-manifold edge or vertex (Definition 2.4)
    int64_t boundary_loops = 0;  // see SurfaceTopology::boundary_loops
    int64_t betti0 = 1, betti1 = 0, betti2 = 0;  // over Z2, of the component's subcomplex
    int64_t sheets = 0;          // pieces left when the component is cut along all feature edges
    int64_t feature_vertices = 0;
    int64_t feature_lines = 0;
    int64_t feature_loops = 0;   // closed feature lines (included in feature_lines)
    std::vector<int32_t> patches;  // sorted distinct patch ids
};

struct SurfaceTopology {
    SurfaceConnectivity connectivity;
    std::vector<EdgeClass> edge_class;          // #E
    std::vector<int32_t> triangle_component;    // #T edge-connected component of each triangle
    std::vector<ComponentSummary> components;   // ordered by smallest triangle index
    // Vertices shared by two or more components that share no edge there (e.g. the
    // apex of an hourglass): "vertex-only contacts", ascending.
    std::vector<int32_t> contact_vertices;
    // Whole 2-complex (vertex-connected), over Z2. Betti numbers of the union are not
    // the sums of the components' ones when components touch at vertices.
    int64_t vertices = 0, edges = 0, triangles = 0;  // referenced vertices only
    int64_t euler_characteristic = 0;
    int64_t betti0 = 0, betti1 = 0, betti2 = 0;
    // Boundary "loops": connected components of the graph of boundary edges after every
    // vertex is split into its wedges (groups of incident triangles connected through
    // edges at that vertex). Two disks touching at a boundary vertex have 2 loops, not a
    // figure eight; where a boundary meets a non-manifold line the curves there count as one.
    int64_t boundary_loops = 0;
    bool manifold = true;
    bool orientable = true;
    std::vector<int32_t> feature_vertices;  // ascending
    std::vector<FeatureLine> feature_lines; // open lines by (first, last), then loops
    // For every vertex the feature line it is an inner vertex of (or that closed loop), -1 otherwise.
    std::vector<int32_t> vertex_feature_line;
};

SurfaceTopology compute_topology(const Surface& surface);

// How elements of surface `b` correspond to elements of surface `a` when comparing
// (b = coarse, a = original). Either may be empty: then that part is compared by counts.
struct TopologyCorrespondence {
    std::vector<int32_t> vertex_map;     // #b.V: the a vertex each b vertex is (coarse_vertex_origin)
    std::vector<int32_t> component_map;  // #b components: the a component each one is
};

// Differences between two topological summaries, first difference first (at most
// `max_differences`; empty when equal). Compares the global and per-component Euler
// characteristic, orientability, manifoldness, boundary loops, Betti numbers, sheets,
// the feature vertex sets (exactly, by id through vertex_map) and the feature lines
// (by their end vertices, sheet counts and patches).
std::vector<std::string> compare_topology(const SurfaceTopology& a, const SurfaceTopology& b,
                                          const TopologyCorrespondence& correspondence,
                                          size_t max_differences = 10);

// One line such as "1 component, chi 2, b=(1,0,1), orientable, 0 boundary loops, 0 feature lines".
std::string describe_topology(const SurfaceTopology& topology);

}  // namespace bpm
