#pragma once
// Point removal with phi kept bijective (Krause & Sander §2.2.4, §2.4): flatten the
// star of a vertex with the polar map (a half-disk map per sector for vertices on
// feature lines), retriangulate the hole greedily with Delaunay-admissible ears of
// best 3D aspect ratio, and transfer the embedded original surface onto the new
// triangles: merge, straighten, re-cut, and reposition with Floater's
// shape-preserving map where straightening would flip pieces.
//
// The stages, each in its own file: star_fans (the star as fans, or why v is kept),
// polar_map, fan_retriangulation, star_graph (the original surface in the fan),
// phi_transfer (locate, re-cut, deviation), removal_validation (exact overlay checks),
// floater_repair. vertex_removal.cpp runs them per fan (FanPlanner) and assembles the plan.
//
// VertexRemover::plan() and plan_deferred() only compute; commit_removal() applies.
// Everything a removal changes is in the RemovalPlan, so costs can be evaluated without
// touching the state.

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "simplify/coarse_mesh.h"
#include "simplify/embedding.h"
#include "simplify/overlay.h"
#include "simplify/star_fans.h"  // VertexClass, the corner reasons

namespace bpm::detail {

// removal_cost()'s reason for new triangles above SimplifyOptions::max_aspect_ratio (and
// above the removed ones), which VertexRemover also gives a large star it refuses early.
inline constexpr const char* kShapeLimitReason = "triangle shape limit (max_aspect_ratio)";

struct RemovalPlan {
    int32_t vertex = -1;
    bool valid = false;
    std::string reason;  // why not valid

    std::vector<int32_t> removed_triangles;
    std::vector<Tri> new_triangles;
    std::vector<int32_t> new_patches;
    std::vector<std::array<int32_t, 2>> new_edges;  // edges that did not exist before
    bool feature_line = false;                      // a -- b replaces two feature edges
    int32_t feature_a = -1, feature_b = -1;
    uint8_t feature_kind = 0;                       // CoarseMesh::Feature of the new edge a -- b
    // Along a feature line of three or more sheets, per sheet: the apexes of its triangles
    // at a -- v and v -- b and of its new triangle at a -- b (line_sheets_of, keeps_line_sheet_order).
    std::vector<std::array<int32_t, 3>> line_sheets;

    // Embedding updates. Locations refer to new triangles by local index (>= 0) through
    // SurfacePoint::Inside with a = -1 - local index, to be mapped at commit.
    std::vector<std::pair<int32_t, SurfacePoint>> new_locations;
    std::vector<std::pair<int32_t, std::vector<Crossing>>> new_paths;
    std::vector<uint32_t> path_versions;  // Embedding::path_version of each edited edge when planned

    // Costs.
    double max_deviation = 0.0;     // max |phi(x) - x| over the new triangles (absolute units)
    double worst_old_aspect = 0.0;  // max R/r of the removed triangles
    double worst_new_aspect = 0.0;  // max R/r of the new triangles
    double longest_new_edge = 0.0;
    // Largest angle (degrees) between the normal of a new triangle and the normal of an
    // original triangle that phi maps (partly) onto it, both in the coarse orientation.
    // Above 90 the original surface folds back over the new triangle, and near 90 phi
    // must squeeze it; refinement through phi then samples it badly. Full plans: exact,
    // over the faces of the validated overlays. Cheap plans: a lower bound, over the
    // triangles around the original vertices that move strictly inside a new triangle.
    double max_normal_deviation = 0.0;
    // The ridge guard (simplify/ridge_guard.h), when the remover was given the original's
    // vertex ridge angles (else both 180): the smallest ridge angle (degrees) the removal
    // makes at a coarse edge that is not a feature edge (sharpest_changed_ridge), and the
    // smallest ridge angle of the original edges at the original vertices in the star.
    // Known for cheap, deferred (pending) and full plans alike, from the estimate on.
    double sharpest_new_ridge = 180.0;
    double sharpest_original_ridge = 180.0;
    bool used_floater = false;
    // The deviation of the first transfer that got a cost, before its validation and a
    // possible re-embedding with Floater's map (then max_deviation differs): full plans
    // are ranked by it first (Simplifier), so that deferring the validation
    // (plan_deferred) decides the same as validating at once.
    double estimated_deviation = 0.0;
    // The estimate is known: estimated_deviation, worst_new_aspect and longest_new_edge
    // were set before the validation, also if the validation then failed (!valid).
    bool estimated = false;
    // plan_deferred() stopped before the validation: the costs above are known except
    // max_normal_deviation, and removed_triangles and new_triangles; the rest is missing.
    // VertexRemover::finish_part / finish_parts_done complete the plan (or make it invalid).
    bool pending = false;

    // Back to a fresh plan, keeping the buffers (plans are made millions of times).
    void clear();
};

struct RemovalScratch;  // reusable buffers, defined in vertex_removal.cpp

class VertexRemover {
public:
    // `oriented_normals[T]`: unit normal of original triangle T in the coarse orientation
    // (times its orientation sign), for RemovalPlan::max_normal_deviation; empty: that
    // angle is not computed (left 0). `vertex_ridges`: the original's vertex_ridge_angles
    // (simplify/ridge_guard.h), for RemovalPlan::sharpest_new_ridge and
    // sharpest_original_ridge; empty: those are not measured (left 180). The remover keeps
    // references to both vectors.
    VertexRemover(const CoarseMesh& mesh, const Embedding& embedding, const std::vector<int8_t>& orientation_sign,
                  const std::vector<Vec3>& oriented_normals, const std::vector<float>& vertex_ridges);
    ~VertexRemover();

    // removal_cost's limit on the new triangles' R/r (SimplifyOptions::max_aspect_ratio;
    // the removed triangles' worst where that is higher). A fan of more than
    // kLargeFanCorners corners whose every retriangulation has a worse triangle
    // (triangulation_aspect_lower_bound) makes the plan invalid with kShapeLimitReason
    // before its O(n^2) retriangulation. removal_cost would refuse the full plan anyway
    // (for this reason, or for one it checks first, or the plan fails on the way), so
    // only the reason recorded for such a star may differ, and one thing more: a vertex on
    // a crease whose half-disk is refused here is tried as a disk (plan()), as after any
    // invalid plan, where a valid half-disk plan refused by its cost was not. Smaller fans
    // are always planned in full. Default +infinity: no early refusal.
    static constexpr int32_t kLargeFanCorners = 64;
    void set_aspect_limit(double max_aspect_ratio) { aspect_limit_ = max_aspect_ratio; }

    // Plans the removal of v. Checks everything local: classification, the topology
    // condition (no new edge or triangle may already exist), flattening, a valid
    // transfer of phi. Global checks (intersections with the rest of the surface)
    // are the caller's. Without `validate` the overlays of the new triangles are not
    // checked: cheaper, for ranking; a plan must be made with `validate` before commit.
    void plan(int32_t v, bool validate, RemovalPlan& plan);
    // A full plan that may stop before the validation (plan.pending), for a removal that
    // may be put back into the queue by its cost. A pending plan is completed, before any
    // other plan of this remover, by finish_part(k, parts) for k = 0 .. parts-1, run as
    // tasks of one round whose tasks start in order (part 0 prepares, the others wait for
    // that; each checks its share of the new triangles), then finish_parts_done(). The
    // result is the same for every number of parts (1 = on one thread).
    // finish_parts_done() returns true when the validation failed along a diagonal and
    // the plan was made again at once without it: its new triangles are then others than
    // the pending plan's, and a test of those against the rest of the surface is void.
    void plan_deferred(int32_t v, RemovalPlan& plan);
    static constexpr int kMaxFinishParts = 2;
    void finish_part(int part, int parts);
    bool finish_parts_done(RemovalPlan& plan, int parts);

private:
    void plan_once(int32_t v, bool force_disk, bool validate, bool defer, RemovalPlan& plan, bool& crease_line);
    void measure_new_ridges(RemovalPlan& plan);  // RemovalPlan::sharpest_new_ridge

    const CoarseMesh& mesh_;
    const Embedding& embedding_;
    const std::vector<float>& vertex_ridges_;
    RemovalScratch* scratch_;
    double aspect_limit_ = std::numeric_limits<double>::infinity();
};

void commit_removal(CoarseMesh& mesh, Embedding& embedding, const RemovalPlan& plan);

}  // namespace bpm::detail
