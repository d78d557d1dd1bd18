#pragma once
// The boundary repair shared by repair_boundary (bpm/boundary_repair.h) and
// refine_tetmesh's step 4 (bpm/tet_refine.h); not public API.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "bpm/boundary_repair.h"
#include "bpm/context.h"

namespace bpm::detail {

// Where each boundary vertex v is on its way to phi: on the segment from base[v]
// (1-lambda = 0) to target[v] (1-lambda = 1), at fraction[v] = 1-lambda. All #V long;
// fraction is 1 for vertices that do not move (interior ones included). refine_tetmesh
// keeps them across levels, so that a vertex held back at one level is retried later on
// its original segment.
struct RepairSegments {
    std::vector<Vec3> base, target;
    std::vector<double> fraction;
};

// \throw OptionError for options repair_boundary refuses (smoothing included when
// options.smooth).
void check_repair_options(const BoundaryRepairOptions& options);

// Steps 1-4 of bpm/boundary_repair.h on raw arrays: moves the vertices `movers` (indices,
// each with fraction < 1, in the order they are visited) from where they are (x[v], on
// their segment at fraction[v]) towards their target, and smooths the vertices with
// movable[v] != 0 (never a mover). tets[t] is positively oriented, or negatively where
// negative[t] (negative may be empty: all positive). `reference` (#V) gives the volumes
// min_volume_fraction refers to. x and segments.fraction are updated; x[v] of a mover is
// always (1-w)*base + w*target of its fraction w (exactly base at 0, target at 1).
// Progress goes to context in [progress_base, progress_base + progress_span], labelled
// `stage`. Returns the seconds spent smoothing; `widened`, if given, gets the number of
// movers the widening pass (step 4) moved on.
double repair_boundary_vertices(std::vector<Vec3>& x, const std::vector<Tet>& tets, const std::vector<bool>& negative,
                                const std::vector<Vec3>& reference, const std::vector<int32_t>& movers,
                                const std::vector<char>& movable, RepairSegments& segments,
                                const BoundaryRepairOptions& options, const Context& context, double progress_base,
                                double progress_span, const std::string& stage, int64_t* widened = nullptr);

// Step 5 of bpm/boundary_repair.h (retreat): every vertex v with may_retreat[v] != 0 and
// plain[v] != x[v] that has a tetrahedron below options.min_dihedral_degrees around it,
// worst first, moves on the segment from x[v] towards plain[v] to where the worst
// tetrahedron around it is widest (a search of the segment), if that is wider than where
// it is and every tetrahedron around it is positively oriented there (exact); up to
// `rounds` rounds, stopping when none moves. The worst tetrahedron around a moved vertex
// only widens, so the mesh's smallest angle never gets smaller. tets positively oriented
// (as in repair_boundary). Sets dirty[u] for the corners of the tetrahedra around every
// moved vertex (for smooth_interior); returns how many distinct vertices moved.
int64_t retreat_boundary_vertices(std::vector<Vec3>& x, const std::vector<Tet>& tets, const std::vector<Vec3>& plain,
                                  const std::vector<char>& may_retreat, const BoundaryRepairOptions& options,
                                  std::vector<char>& dirty, int rounds = 3);

// Step 6 of bpm/boundary_repair.h (slide): every vertex v with may_slide[v] != 0 that has
// a tetrahedron below options.min_dihedral_degrees around it, worst first, moves along the
// surface: its parameter point points[v] changes within the coarse feature it lies on (the
// barycentric coordinates that are 0 stay exactly 0: a vertex inside a coarse triangle stays
// inside it, one on a coarse edge stays on that edge; a vertex with fewer than two nonzero
// coordinates, a coarse vertex, does not move), and the vertex goes to surface(new point),
// plus its offset from surface(old point) if it was not exactly there (a held-back vertex
// keeps its offset). A compass search in the parameter plane keeps a move where the worst
// tetrahedron around the vertex gets wider and every tetrahedron around it stays
// positively oriented (exact), within a quarter of the vertex's shortest edge of where it
// was; up to `rounds` rounds, stopping when none moves. The mesh's smallest angle never gets
// smaller. tets positively oriented. Sets dirty[u] for the corners of the tetrahedra around
// every moved vertex; returns how many distinct vertices moved.
int64_t slide_boundary_vertices(std::vector<Vec3>& x, const std::vector<Tet>& tets, std::vector<SurfacePoint>& points,
                                const std::function<Vec3(const SurfacePoint&)>& surface,
                                const std::vector<char>& may_slide, const BoundaryRepairOptions& options,
                                std::vector<char>& dirty, int rounds = 3);

// The smallest dihedral angle (degrees, 0 for no tetrahedra) and the number of tetrahedra
// with one below 1, 5 and 10 degrees; tets oriented as for repair_boundary_vertices.
struct TetQuality {
    double min_dihedral_degrees = 0;
    int64_t below_1_degree = 0, below_5_degrees = 0, below_10_degrees = 0;
};
TetQuality tet_quality(const std::vector<Vec3>& x, const std::vector<Tet>& tets, const std::vector<bool>& negative);

}  // namespace bpm::detail
