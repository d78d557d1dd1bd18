#pragma once
// Validation of surfaces and parametrized surfaces: what bpm-check runs, and the test
// oracle for the simplifier. Every verdict that concerns geometry uses the exact
// predicates of bpm/predicates.h; the only tolerances are relative ones stated below.
//
// A check never throws on bad data: it reports it. Each check returns a CheckResult
// with a count of all problems found and the first few of them (in a deterministic
// order), naming the offending element by kind and index. The JSON form is described
// in spec/check-report.md.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bpm/bpm_file.h"
#include "bpm/context.h"
#include "bpm/parametrization.h"
#include "bpm/surface.h"

namespace bpm {

// One offending element. `ids` names it for programs, e.g. {{"coarse_triangle", 17},
// {"piece", 4}}; `where` names it for people ("coarse triangle 17 piece 4").
struct CheckProblem {
    std::vector<std::pair<std::string, int64_t>> ids;
    std::string message;
    std::string where() const;
    std::string describe() const;  // "where: message"
    // The id of the given kind, or -1.
    int64_t id(const std::string& kind) const;
};

// The most extreme value a check measured (worst aspect ratio, largest image deviation...).
struct WorstValue {
    std::string name;      // e.g. "aspect_ratio"
    double value = 0.0;
    std::vector<std::pair<std::string, int64_t>> ids;  // where it occurs
};

struct CheckResult {
    std::string name;     // "format", "intersections", "original-intersections", "topology", "junctions", "bijectivity",
                          // "quality", "distance", "replay"
    bool passed = true;
    std::string summary;  // one line for people, e.g. "1234 triangles, 0 intersecting pairs"
    std::vector<std::pair<std::string, int64_t>> counts;  // named counts, e.g. {"triangles", 1234}
    int64_t problem_count = 0;            // all problems found
    std::vector<CheckProblem> problems;   // the first CheckOptions::max_problems of them
    std::optional<WorstValue> worst;
    // Further named measurements with where they occur (e.g. the one-sided distances of
    // the distance check); JSON "measures", only written when not empty.
    std::vector<WorstValue> measures;

    // Records a problem (kept only while fewer than `max_problems` are stored) and fails the check.
    void add_problem(CheckProblem problem, size_t max_problems);
    void add_count(const std::string& name, int64_t value) { counts.emplace_back(name, value); }
    int64_t count(const std::string& name) const;  // -1 if absent
};

struct CheckReport {
    std::string input;  // file name as given, "-" for standard input
    std::vector<CheckResult> checks;
    bool passed() const;
    const CheckResult* find(const std::string& name) const;
};

struct CheckOptions {
    size_t max_problems = 10;
    // Quality gates on the coarse surface; unset = not checked.
    std::optional<double> max_aspect_ratio;     // circumradius / inradius, 2 for equilateral
    std::optional<double> min_angle_degrees;
    // Distance gate (bpm-check --max-distance): fails when the two-sided Hausdorff distance between
    // phi's image and S0, or between the coarse surface S and S0, exceeds this fraction
    // of the bounding-box diagonal of S0. Unset = the distance check is not run.
    std::optional<double> max_error;
    // Spacing of the sample grid laid on every sampled triangle by the distance check,
    // relative to the diagonal (at least the corners, edge midpoints and centroid of
    // every triangle are sampled; at most 256 divisions per side, the spacing reached is
    // the measure "sample_spacing"). The sampled distances are at most one spacing below
    // the true ones.
    double error_sample_spacing = 1e-3;
    // Replay: recompute all topological invariants from scratch after every this many
    // steps (and always after the last one); 0 = automatic (4 evenly spaced recomputations).
    int64_t replay_check_interval = 0;
    // run_checks: threads that run checks side by side (the structural checks next to
    // bijectivity and the others); 0 = up to 2 as the hardware allows. The report is the
    // same for any number.
    int threads = 0;
};

// Structural consistency of an in-memory parametrization: sizes, index ranges, CSR
// offsets, finite values, node barycentrics (>= 0, sum 1 within 1e-12, exact zeros on
// coarse edges, unit vectors at corners), node identities (original vertices and
// original edges exist), images equal to what the node is within 1e-9 of the bounding
// box diagonal of S0, coarse vertices at their original positions (same tolerance).
// The other parametrization checks rely on this one and report "not checked" when it fails.
// For a file of format 1.x, the images it stored (BpmFile::stored_node_image) are the ones
// compared with what each node is; read_bpm recomputed param.node_image from the kinds.
CheckResult check_format(const Parametrization& param, const CheckOptions& options = {}, const Context& context = {});
CheckResult check_format(const BpmFile& file, const CheckOptions& options = {}, const Context& context = {});

// No two triangles intersect other than in a shared vertex or a shared edge (coplanar
// overlaps and folds included); degenerate triangles are reported too. `name` lets the
// caller label the result ("intersections" for S, "original-intersections" for S0).
CheckResult check_intersections(const Surface& surface, const CheckOptions& options = {}, const Context& context = {},
                                const std::string& name = "intersections");

// Coarse vs original: per component Euler characteristic, orientability, boundary
// loops, Betti numbers over Z2, sheets, feature vertices (by original id) and feature
// lines; every piece maps into an original triangle of the coarse triangle's patch.
CheckResult check_topology(const Parametrization& param, const CheckOptions& options = {}, const Context& context = {});
// A plain surface: computes and reports its invariants; fails only on surfaces whose
// topology cannot be computed (indices out of range).
CheckResult check_topology(const Surface& surface, const CheckOptions& options = {}, const Context& context = {});

// Around every junction edge (three or more triangles) the sheets, sorted by turning
// around the edge with exact predicates (orient3d), agree about the material between
// them: the two triangles that bound each wedge claim the same material on the wedge's
// side (front or back by each triangle's orientation, materials from patch_info,
// compared case-insensitively). Edges whose patches lack oriented materials are counted
// (junction_edges_without_materials) and skipped; edges with two triangles on one
// half-plane (an overlap the intersection check reports) are problems. A sheet turned
// past another around their common edge intersects nothing, so the intersection check
// passes, but the regions of the volume change. The file's form checks that S keeps the
// structure of S0: S0 is scanned too (counts prefixed "original_") but never fails, and
// patches whose materials contradict S0 itself (a reader's guess) are not checked on S
// (count "patches_contradicting_original"). The file's form also compares every component
// of S (triangles connected through shared vertices) with its component of S0 by the
// materials it lies in (exact ray-crossing parity over the other components' material
// boundaries): a sheet swept across an island intersects nothing either (counts
// "components", "original_components", "components_in_other_materials",
// "components_not_compared"; nothing to do when both have one component). The surface's
// form checks that surface.
CheckResult check_junctions(const BpmFile& file, const CheckOptions& options = {}, const Context& context = {});
CheckResult check_junctions(const Surface& surface, const std::vector<PatchInfo>& patch_info,
                            const CheckOptions& options = {}, const Context& context = {});

// phi is a bijection S -> S0: pieces tile every coarse triangle, agree along shared
// coarse edges, map into their original triangles with positive orientation and tile
// every original triangle; every original vertex is the image of exactly one point.
CheckResult check_bijectivity(const Parametrization& param, const CheckOptions& options = {}, const Context& context = {});

// How far phi is from an isometry, per piece (spec/check-report.md, "distortion"): the
// area squeeze (a piece's area in its coarse triangle over its original area, divided by
// the same ratio for the whole triangle; max(s, 1/s)) and the normal deviation (angle
// between the coarse triangle's normal and the normal of the original triangle the
// piece maps into), each p50 / p99 / max, and the pieces turned more than 60 and 90
// degrees (folds of phi seen from S). A report: fails only on unreadable data.
CheckResult check_distortion(const Parametrization& param, const CheckOptions& options = {},
                             const Context& context = {});

// Aspect ratio and smallest angle of every triangle against the limits in `options`.
CheckResult check_quality(const Surface& surface, const CheckOptions& options = {}, const Context& context = {});

// How far phi's image and the coarse surface are from S0, relative to the bounding-box
// diagonal of S0 (spec/check-report.md, "distance"):
//   image_hausdorff   two-sided Hausdorff distance between phi(S) and S0 (0 up to
//                     rounding for a correct phi; catches broken images);
//   coarse_hausdorff  two-sided Hausdorff distance between S and S0;
//   coarse_to_original_bound  max over phi nodes of |phi(x) - x|, an exact upper bound
//                     of the one-sided distance from S to S0 (phi is affine on every piece).
// The Hausdorff distances are estimated on a deterministic sample grid (spacing
// `error_sample_spacing`, at least corners, edge midpoints and centroids) with exact
// closest-point queries (CGAL AABB tree), pruned by exact per-triangle upper bounds;
// the estimate is at most the measure "sample_spacing" below the true value. Single
// threaded and deterministic (no randomness; ties go to the first element). Fails when either
// Hausdorff distance exceeds `options.max_error` (if set).
CheckResult check_distance(const Parametrization& param, const CheckOptions& options = {}, const Context& context = {});

// Replays the recorded point removals (file.simplification_steps, bpm-simplify
// --record-steps) on the connectivity of S0: every step must remove a vertex whose star
// is a disk or a set of half-disks along a feature line (paper §2.4), its link must be
// exactly the boundary of the recorded triangles (which must fill every disk /
// half-disk with a triangulated disk of the same patch), the local condition of
// Conjecture 2.1 must hold (no new edge, and no new triangle, exists already), and the
// topological invariants of check_topology must not change; the replayed surface must
// equal the coarse surface. Fails ("not checked") on files without a record.
CheckResult check_replay(const BpmFile& file, const CheckOptions& options = {}, const Context& context = {});

// The tetrahedral mesh of the file (/tetmesh, spec/tetmesh.md), beyond what the reader
// checks: every tetrahedron positively oriented (exact orient3d); conforming (a face is
// shared by at most two tetrahedra, which lie on its two sides); every boundary face of
// the mesh, and every face between two regions, is in /tetmesh/faces, and every listed
// face is a face of the mesh, once; every vertex is a corner of a tetrahedron; each face
// on S lies in its coarse triangle (its corners' parameter points) with the triangle's
// orientation, and the faces of a coarse triangle cover it (4^level of them); coarse
// vertices are at the coarse surface's positions (at level 0: the first #Vc vertices, in
// order, and face i is coarse triangle i). Reports the smallest dihedral angle as the
// worst value. Fails ("not checked") on a file without a tet mesh.
CheckResult check_tetmesh(const BpmFile& file, const CheckOptions& options = {}, const Context& context = {});

// What bpm-check runs.
struct CheckSelection {
    bool format = true;
    bool intersections = true;
    bool topology = true;
    bool junctions = true;                // check_junctions (S and S0)
    bool bijectivity = true;
    bool original_intersections = false;  // also check S0 (so a faulty input is reported as such)
    bool replay = false;                  // replay the recorded simplification steps (needs a record)
    bool distortion = false;              // report phi's distortion (check_distortion; bpm-check's default)
    bool tetmesh = true;                  // check the tet mesh (check_tetmesh), when the file has one
};
// Runs the selected checks and reports them in a fixed order: format, original
// intersections, intersections, topology, junctions, tetmesh (only for a file with a tet mesh),
// bijectivity, distortion, quality, distance, replay.
// With two threads (options.threads) the first four run on a second thread, without
// progress reports, next to the others.
CheckReport run_checks(const BpmFile& file, const CheckSelection& selection, const CheckOptions& options = {},
                       const Context& context = {});
// Also runs quality when a shape limit is set, distance when options.max_error is set.
// For a plain surface: intersections and/or topology (and quality if limits are set).
CheckReport run_surface_checks(const Surface& surface, const CheckSelection& selection,
                               const CheckOptions& options = {}, const Context& context = {});

// JSON text of the report (spec/check-report.md), ending in a newline.
std::string check_report_to_json(const CheckReport& report);
// One line per check: "PASS intersections  1234 triangles, 0 intersecting pairs".
std::string check_report_to_text(const CheckReport& report);

}  // namespace bpm
