#pragma once
// Simplification by point removal with a bijective parametrization (Krause & Sander,
// "Automatic construction of boundary parametrizations for geometric multigrid
// solvers", §2.2–2.4; Floater 1997 for the shape-preserving map; Eck et al. 1995 for
// the polar map).
//
// The original surface S0 is simplified by removing vertices one at a time in order
// of a cost, keeping after every step a coarse surface S with the same topological
// type and non-manifold structure as S0 and a piecewise-linear bijection phi: S -> S0.

#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bpm/context.h"
#include "bpm/parametrization.h"
#include "bpm/simplification_steps.h"
#include "bpm/surface.h"

namespace bpm {

struct SimplifyOptions {
    // Stopping rules: the first one reached ends the run. 0 / infinity = not used.
    int64_t target_vertices = 0;      // stop at this many coarse vertices
    double target_ratio = 0.0;        // stop at this fraction of the input vertices
    double max_error = std::numeric_limits<double>::infinity();
    // ^ never exceed this geometric error, relative to the bounding-box diagonal:
    //   max over the surface of |phi(x) - x| (an upper bound of the one-sided
    //   Hausdorff distance from S to S0).

    // Cost = error/diagonal + aspect_weight * 1e-3 * (log2(worst new R/r / 2)
    //                                                - 0.5 log2(worst removed R/r / 2)
    //                                                - log2(max(worst removed, A) / max(worst new, A)))
    // with A = max_aspect_ratio: the last part credits removals that take out triangles
    // worse than max_aspect_ratio (slivers of the input), so that they go first.
    double aspect_weight = 1.0;
    // Distortion term of the cost (issue 19 item 2), from the largest angle between a new
    // coarse triangle's normal and an original triangle phi maps onto it: 0 up to 45
    // degrees, distortion_weight * 1e-3 * ((angle - 45) / 45)^2 above (1e-3: an error of
    // 0.1 % of the diagonal), and + 1 (more than any error relative to the diagonal) above
    // fold_limit_degrees (< 180), so that removals folding phi over that limit come after
    // every other removal. Off by default: measured at --ratio 0.1 (bench/RESULTS.md,
    // "Tets without slivers, phi's distortion"), weight 0.3 cuts the pieces turned
    // > 90 degrees by 11-25 % but raises the Hausdorff distance up to 1.22x (fandisk);
    // weight 1 cuts more and costs femur 1.32x; a fold limit of 90 leaves almost no folds
    // but costs femur 4.6x. 0 = off (the angle is then not computed unless
    // max_normal_deviation_degrees or fold_limit_degrees asks for it). The fold limit works
    // with any weight, 0 included.
    double distortion_weight = 0.0;
    double fold_limit_degrees = 180.0;
    // Fold term of the cost (issue 19, convergence through phi; libbpm/src/simplify/
    // distortion.h, fold_cost): a removal that turns an original piece by more than 90
    // degrees against its new coarse triangle (a fold of phi seen from the coarse surface)
    // costs fold_weight * 1e-3 * (angle - 90) / 90 more (1e-3: an error of 0.1 % of the
    // diagonal). Graded and small, unlike fold_limit_degrees: folds are put off while a
    // removal of about the same error folds less, not at any price. Refining through phi
    // converges slowly where phi folds (the folded part is squeezed and sampled too
    // coarsely). Off by default: measured (bench/RESULTS.md, "Folds of phi and
    // convergence"), weight 2 lifts the K = 0 -> 4 reduction of the maximum distance on the
    // rows where it sat on a fold (femur 1000 V 1.9x -> 3.0x, elephant 10 % and armadillo
    // 1000 V 4.3x -> 5.5x) and leaves the others as they were, but the changed removal order
    // moves femur 10 %'s K = 0 distance up 1.10x (1.13x the bench reference); weights 0.25 and
    // 1 did the same to mech-holes-shark 1000 V. 0 = off.
    double fold_weight = 0.0;
    // The queue orders candidates by a cheap lower bound of their cost; the candidate on
    // top is then planned in full. If its full cost is above the next candidate's bound
    // by more than this fraction (of that bound's magnitude), it goes back into the
    // queue; otherwise it is removed at once. 0 = strict cost order. With 0.1 one full
    // plan in five fewer is thrown away on femur (1-6 % less time on the bench meshes),
    // and the results are as good: the Hausdorff distances of the bench rows moved by up
    // to +-8 %, either way.
    double queue_tolerance = 0.1;
    // Removals tried per step, 1..64: the queue's top and, in queue order, the next
    // entries outside the stars of those taken before (a few passed over at most), planned
    // and validated together in the parallel rounds, committed in queue order, each after
    // the earlier ones only if its plan is still valid then and its new triangles do not
    // meet theirs. The output does not depend on the number of threads, but it does on
    // this. 2 (the default): the two share the rounds the second thread otherwise mostly
    // waits through, 6-11 % less time on the bench meshes; the second removal comes
    // before the re-ranked neighbours of the first, so the order changes a little: the
    // Hausdorff distances of the bench rows moved by -3 % to +6 % against 1. 1: one
    // removal per step (with queue_tolerance 0: strict cost order). More: larger rounds
    // for more threads, but more work: measured at 4, 8, 16 (bench/README.md, "Parallel
    // rounds"; again 2026-12-07, bench rows and 208k, 832k triangles): Hausdorff -8 % to +20 %
    // against 2 (removal order; each R has a row over +5 %: R=4 fandisk 1000 V +20 %, R=8
    // mech-holes-shark 1000 V +11 %, R=16 armadillo 1000 V +8 %), one-thread CPU up on most
    // rows (armadillo 10 %: +13/+18/+22 %), two-thread CPU down (old 200 us spin; R=16 -5..-17 %).
    int removals_per_step = 2;
    // Worst triangle shape (circumradius / inradius; 2 = equilateral) a removal may
    // create, unless the triangles it removes were already worse. Mesh generators need
    // bounded aspect ratios; infinity disables.
    double max_aspect_ratio = 30.0;
    // Final phase: edge flips of the coarse surface, with phi re-embedded exactly, for the
    // triangles that make slivers in a volume mesh (issue 19 item 5). A needle (R/r above
    // max_aspect_ratio) gets the flip of one of its edges that at least halves the worst
    // R/r of the two triangles (a cap; a needle with one short edge cannot be helped by
    // flips). With flip_min_dihedral_degrees > 0, on a closed single-patch surface, a
    // convex edge whose tetrahedron with its two triangles has a dihedral angle below it
    // and an empty circumsphere (TetGen keeps such tetrahedra: it may not split S) is
    // flipped too, if the new triangles are no worse than max(old worst R/r,
    // max_aspect_ratio). Never feature edges or patch borders; never a flip that makes
    // phi invalid, an intersection, a new crease (normals turning more than 60 degrees
    // unless they did before), or an error above the largest error of a removal, nor one
    // the guards of a removal would refuse (min_ridge_angle_degrees: ridges at its new
    // edge and at the four sides of its quad, wedges, clearance; sheet order, islands).
    // Measured (bench/RESULTS.md "Tets without slivers"): no needle of the bench surfaces
    // at 10 % or 1000 vertices can be flipped (femur's has a short edge); the sliver flips
    // (6 degrees) raise elephant 10 % from 4.92 to 6.29 degrees at level 0 but add
    // nothing once TetGen optimises towards 150 degrees (TetMeshOptions::
    // max_dihedral_degrees), so they are off by default. false: no flips at all.
    bool flip_edges = true;
    double flip_min_dihedral_degrees = 0.0;
    // Largest angle (degrees) a removal may leave between the normal of a new coarse
    // triangle and the normal of any original triangle that phi maps (partly) onto it.
    // Where the original surface turns away from the coarse triangle (above 90 degrees
    // it folds back over it), phi has to squeeze it, and refining through phi samples
    // that part too coarsely to converge to it. 180 disables.
    double max_normal_deviation_degrees = 180.0;
    // The ridge guard (issue 19, libbpm/src/simplify/ridge_guard.h): the smallest ridge
    // angle (degrees) a removal may leave at a coarse edge that is not a feature edge. The
    // ridge angle is 180 minus the angle between the two triangles' normals: the interior
    // dihedral angle of a convex edge, the exterior one of a concave edge (180 flat, 0
    // folded flat). A removal is refused when an edge it makes or changes gets a ridge
    // angle below min(this, the sharpest ridge angle of the original edges at the original
    // vertices it covers - 5): the coarse surface is then never much sharper than the
    // original where it lies. Edges already below the limit may stay as they are but not
    // get sharper; feature edges are exempt (they follow the original's feature lines, as
    // before). Without it femur at 10 % had coarse folds of 2.5-20 degrees where the
    // original's sharpest edge nearby was 35-78: a tetrahedron of 4.99 degrees bounded by
    // the coarse surface (bpm-mesh), refined vertices held back there (bpm-refine
    // --max-error). Measured on femur (bench/RESULTS.md, "Coarse ridges"): 30 met the
    // adaptive target at T = 0.001 and the tets' 5 degrees at level 0, for a Hausdorff
    // distance 1.02x; 20 left the adaptive rows unmet, 40 and 50 cost 1.13x. On fandisk,
    // armadillo and mech-holes-shark it changes nothing (elephant at 10 %: 1.06x).
    // Feature edges get a floor of their own (the wedge guard): the wedge between two
    // neighbouring sheets at a junction edge (three or more triangles) is kept at least
    // min(15, this) degrees wide, at another feature edge min(5, this), where it was so
    // wide, else it may not get thinner. Every tetrahedral mesh of the coarse surface has
    // a dihedral angle at most its thinnest wedge (noisy label images: junction wedges of
    // 1e-13 degrees, and bpm-mesh's angle with them). 0 = off (both guards, and the
    // clearance guard: no new triangle within 0.1 % of its size of another (1 % with two
    // or more patches), which made tetrahedra of 4e-6 degrees on noisy label images; and
    // on surfaces of two or more patches the corner-wedge guard: two triangles with one
    // common corner are not laid onto each other at less than min(4, this) degrees, which
    // made 0.34).
    double min_ridge_angle_degrees = 30.0;
    // Longest edge a removal may create, relative to the diagonal.
    double max_edge_length = std::numeric_limits<double>::infinity();
    // Edges whose dihedral angle (between normals) exceeds this are creases, kept as
    // feature lines; 180 disables. Boundaries, patch borders and edges with 3 or more
    // sheets are always feature lines.
    double feature_angle_degrees = 60.0;
    // Long shallow creases (issue 19): an edge whose normals differ by more than
    // crease_chain_angle_degrees (but not by more than feature_angle_degrees) is a crease
    // too where it lies on a chain of at least 8 such edges and at least crease_chain_length
    // (fraction of the bounding-box diagonal) long. A chain goes on through a vertex where
    // exactly two such edges meet and no sharper crease, turning at most 20 degrees, the
    // two edges' angles within 1.3x of each other (libbpm/src/core/crease_chains.h).
    // fandisk's curved 22-40 degree edges (chains of 10 to 29 edges, 13-37 % of the
    // diagonal) are then kept like sharp creases and the refined surface converges to them
    // through phi: the proven bound at 4 levels falls from 4.8e-4 to 1.0e-4 (10 %) and from
    // 2.9e-4 to 9.6e-5 (1000 vertices), the coarse error unchanged. The kinks of the
    // scanned femur, elephant and armadillo and mech-holes-shark's few shallow edges make no
    // such chain: their outputs are the same as without (bench/results/manual/crease-chains.md,
    // also why 20 and 0.1: at 15 degrees or 0.05 femur kept more vertices back from phi).
    // The smoother (SmoothOptions) and bpm-info (BpmInfoOptions) take the same two values.
    // 180 (or anything >= feature_angle_degrees) = off: only feature_angle_degrees decides.
    double crease_chain_angle_degrees = 20.0;
    double crease_chain_length = 0.10;
    // Keep the corners of creases: a vertex where three or more feature edges meet, one
    // of them at least a crease (a corner of a box, a crease meeting a boundary), or where
    // a single crease ends at a sharp cone (angle defect of the star at least that of a
    // cone whose opposite normals are feature_angle_degrees apart) is never removed, like
    // the ends and junctions of boundaries, patch borders and non-manifold lines (the
    // paper's rule for feature vertices, §2.4). The vertices along a crease are still
    // removed as far as the limits allow. false: corners are removed like any crease
    // vertex when the error allows (a crease may then be cut short).
    bool keep_corners = true;
    // A crease counts for keep_corners only where it runs as a line for at least this
    // fraction of the bounding-box diagonal from the vertex (noise on scanned surfaces
    // makes short creases: on femur.off 293 junctions of creases at most 1.8 % long;
    // fandisk's shortest real crease at a corner is 3.2 %). 0 = every crease counts.
    double corner_crease_length = 0.025;
    // Refuse removals whose new triangles would intersect the rest of the surface.
    bool prevent_intersections = true;
    // Refuse an input that already intersects itself (bpm::AlgorithmError naming the first
    // pair): its coarse surface could not be free of intersections either.
    bool reject_self_intersecting_input = true;
    // Testing aid: after every removal, rebuild and validate the parametrization of all
    // triangles around it from the committed state (slow). Throws bpm::AlgorithmError
    // naming the removal that broke it.
    bool self_check = false;
    // Log every removal (vertex, cost, error, aspect) through Context::debug.
    bool trace_removals = false;
    // Threads that share the work (planning rounds, the input check, the export); the
    // output is the same for every thread count. 0 = automatic: 1 for an input of fewer
    // than 10000 triangles (two saved it no wall time), else 2 if the hardware has a
    // second core and not every core is busy (1-minute load average below the number of
    // cores), else 1. Two threads take more CPU time than one (208k triangles, spinning
    // 30 us between the short rounds: 1.55x CPU for 0.85x wall on an idle machine, 1.25x
    // CPU and more wall at load 12) and save wall time only on a free core, so a busy
    // machine is better off with one.
    int threads = 0;
    // Record every committed removal (the vertex and the triangles that replaced its
    // star) in SimplifyResult::steps, so that bpm-check --replay can re-apply them.
    bool record_steps = false;
};

// Time spent in one phase of simplify(), measured by the library.
struct SimplifyPhaseTime {
    // One of, in this order: "set-up" (coarse mesh, features, embedding, grid), "input
    // intersection check" (one thread: on the set-up's grid; with more threads the check
    // runs beside the set-up and the two are one phase, "input intersection check with
    // set-up", first), "first ranking" (cheap
    // plans of every vertex), "removals" (the loop of steps, and why vertices were kept),
    // "edge flips" (SimplifyOptions::flip_edges), "export of phi" (freeing the planning
    // state, the export of the parametrization, the summary), "freeing the simplifier's
    // state". A phase that did not run is left out.
    std::string name;
    double wall_seconds = 0.0;  // steady clock
    double cpu_seconds = 0.0;   // CPU time of the whole process (all its threads) during the phase
};

// A coarse triangle worse than SimplifyOptions::max_aspect_ratio that the simplifier
// left (no removal makes one: it is a sliver of the input, or made of one, that could
// not be taken out), and why each of its corners stayed.
struct SliverReport {
    double aspect_ratio = 0.0;          // R/r (2 for equilateral; infinite if degenerate)
    std::array<int32_t, 3> vertices{};  // input vertex ids of its corners
    Vec3 centroid{};
    std::array<std::string, 3> kept;    // per corner: why it could not be removed at the end
};

struct SimplifyResult {
    int64_t input_vertices = 0, input_triangles = 0;
    int64_t output_vertices = 0, output_triangles = 0;
    int64_t removed = 0;
    int64_t shape_preserving_repairs = 0;  // removals whose transfer needed Floater's map
    int64_t paired_steps = 0;              // steps that removed two or more vertices (removals_per_step)
    int64_t refused_in_step = 0;  // later removals of a step refused: their new triangles met an earlier one's
    int64_t needle_flips = 0, sliver_flips = 0;  // edge flips of the final phase (flip_edges)
    double max_error = 0.0;           // final max |phi(x) - x| / diagonal
    double worst_aspect_ratio = 0.0;  // of the coarse surface
    // Coarse triangles worse than SimplifyOptions::max_aspect_ratio, and the worst of them
    // (at most kListedSlivers, worst first) with what kept them.
    int64_t slivers = 0;
    static constexpr size_t kListedSlivers = 5;
    std::vector<SliverReport> worst_slivers;
    double seconds = 0.0;  // wall time from the first ranking to the end of the export
    // Wall and CPU seconds of simplify()'s phases, in order; together they cover the call
    // (the option checks and the renumbering of the input into Morton order and back
    // aside: at most 0.5 % of the samples of a 208k-triangle run).
    std::vector<SimplifyPhaseTime> phases;
    int threads = 1;  // threads used (SimplifyOptions::threads, or what 0 chose)
    bool target_reached = false;
    std::string stop_reason;          // human readable
    // Vertices that are never removed: corners of creases (SimplifyOptions::keep_corners;
    // counted also when not kept) and the ends and junctions of boundaries, patch
    // borders and non-manifold lines. A vertex target below their sum cannot be reached.
    int64_t crease_junctions = 0;      // three or more feature edges, one at least a crease
    int64_t crease_cone_ends = 0;      // a crease ending at a sharp cone
    int64_t line_feature_vertices = 0; // one, or three or more, boundary / border / non-manifold edges
    bool corners_kept = true;          // SimplifyOptions::keep_corners
    int64_t kept_feature_vertices() const {
        return line_feature_vertices + (corners_kept ? crease_junctions + crease_cone_ends : 0);
    }
    // Why the vertices that remained could not be removed, counted by reason.
    std::map<std::string, int64_t> blocked;
    // The removals in order, when SimplifyOptions::record_steps is set (else empty).
    // Replayed on the connectivity of `out.original` they give exactly `out.coarse`.
    std::optional<SimplificationSteps> steps;
};

// \pre `original` passed validate_surface (finite, no degenerate or duplicate triangles).
// \throw bpm::OptionError for contradictory options, bpm::AlgorithmError for a
//        self-intersecting input (see SimplifyOptions) or one whose coordinates are outside
//        the range bpm computes in (coordinate_range_problem, bpm/surface.h),
//        bpm::Cancelled via the context.
// Fills `out` (original, coarse, phi) and returns what was achieved. The run itself
// works on its own numbering of the input (Morton order of the vertices, for memory
// locality: libbpm/src/simplify/vertex_order.h); `out.original` is the input exactly as
// given, and every id in `out`, the result and the messages is the caller's.
SimplifyResult simplify(const Surface& original, const SimplifyOptions& options, const Context& context,
                        Parametrization& out);
// The same, taking the input over: it becomes out.original without a copy, so that the
// caller's surface is not held a second time beside phi (the tools read a surface only to
// simplify it). The options are checked before `original` is taken.
SimplifyResult simplify(Surface&& original, const SimplifyOptions& options, const Context& context,
                        Parametrization& out);

}  // namespace bpm
