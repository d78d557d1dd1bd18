#include "simplify/vertex_removal.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <thread>
#include <unordered_map>

#include "bpm/predicates.h"
#include "simplify/fan_retriangulation.h"
#include "simplify/floater_repair.h"
#include "simplify/phi_transfer.h"
#include "simplify/polar_map.h"
#include "simplify/removal_validation.h"
#include "simplify/ridge_guard.h"
#include "simplify/sheet_guard.h"
#include "simplify/star_fans.h"
#include "simplify/star_graph.h"

namespace bpm::detail {

namespace {

// One fan through the stages of a removal, in order: polar_map (polar_map.h),
// retriangulate_fan (fan_retriangulation.h), gather_star_nodes and
// gather_straight_segments (star_graph.h), locate_free_nodes, cut_segments and
// transfer_deviation (phi_transfer.h), assign_pieces and check_new_triangles
// (removal_validation.h), and floater_repair (floater_repair.h) when the straightened
// transfer fails. FanPlanner keeps what the stages hand on
// (the polygon, the new triangles, the star graph, the cuts) and their buffers.
class FanPlanner {
public:
    // Planners are reused across removals so that their buffers keep their capacity.
    FanPlanner(const CoarseMesh& mesh, const Embedding& emb, const std::vector<int8_t>& sign,
               const std::vector<Vec3>& normals)
        : mesh_(mesh), emb_(emb), sign_(sign), normals_(normals) {}
    void reset(int32_t v, const Fan& fan, double radius_scale,
               const std::unordered_map<int32_t, double>* new_edge_params, bool validate) {
        v_ = v;
        fan_ = &fan;
        scale_ = radius_scale;
        new_edge_params_ = new_edge_params;
        validate_ = validate;
        graph_.clear(emb_.location.size());
        max_deviation = 0.0;
        estimated_deviation = 0.0;
        min_normal_cosine = 1.0;
        used_floater = false;
        for (PathEdit& e : pieces.path_edits) pieces.recycle(e.middle);
        pieces.path_edits.clear();
        locations.clear();
        along_diagonal_ = {-1, -1};
    }
    // Diagonals (link indices) the next triangulations must not use, until cleared: a
    // retriangulation after a transfer failed because an original edge runs exactly
    // along a diagonal (on a regular grid both diagonals of a square star pass through
    // original vertices, one of them along original edges; aspect ratios tie).
    // The original's vertex ridge angles (simplify/ridge_guard.h), or empty: only asked
    // for ahead of sharpest_original_ridge() (a cache hint).
    void set_vertex_ridges(const std::vector<float>& ridges) { ridges_ = &ridges; }
    void clear_forbidden() { forbidden_.clear(); }
    void forbid(const std::array<int32_t, 2>& d) { forbidden_.push_back(d); }
    // The diagonal of the last failed transfer that had an original edge along it, or {-1, -1}.
    std::array<int32_t, 2> along_diagonal() const { return along_diagonal_; }

    // Full plans run in two steps: estimate() stops once the straightened transfer has
    // its cost (the part that ranks the removal), finish() validates the overlays of the
    // new triangles (about two thirds of the work), with Floater's map if they are not
    // valid. Most full plans are of removals that turn out dearer than the next queue
    // entry and wait; their validation is not needed until they come back.
    enum class Stage { Failed, Estimated, Done };
    Stage estimate(std::string& why);
    bool finish(std::string& why);  // after Stage::Estimated
    // finish() in steps, so that the checks of the new triangles (most of its work) can
    // be shared by threads: prepare_checks(), then check_triangles() for ranges of the new
    // triangles, on any threads with a TriangleCheck each, then end_finish() with
    // whether all passed (and the reason of the failure in the first triangle that failed).
    bool prepare_checks(std::string& why);
    bool check_triangles(int32_t begin, int32_t end, TriangleCheck& check, double& min_cosine, std::string& why) const;
    bool end_finish(bool checks_passed, const std::string& reason, double min_cosine, std::string& why);
    int32_t num_new_triangles() const { return static_cast<int32_t>(tri.triangles.size()); }
    // The smallest of `vertex_ridges` (simplify/ridge_guard.h) over the original vertices
    // of the fan that cheap and full plans both gather: the corners, the free vertices,
    // and those on the new edge of an open fan (not the fixed ones on the link edges, which
    // only full plans gather). After estimate() got past gathering the nodes.
    double sharpest_original_ridge(const std::vector<float>& vertex_ridges) const {
        double sharpest = 180.0;
        for (const StarNode& s : graph_.nodes)
            if (s.vertex >= 0 && (s.free || s.poly_corner >= 0 || (!fan_->closed && s.poly_edge == n_ - 1)))
                sharpest = std::min(sharpest, double(vertex_ridges[size_t(s.vertex)]));
        return sharpest;
    }
    bool run(std::string& why) {
        const Stage stage = estimate(why);
        return stage == Stage::Done || (stage == Stage::Estimated && finish(why));
    }

    // Outputs.
    FanTriangulation tri;  // the new triangles
    TransferPieces pieces;  // where the re-cut edges lie, and the path edits
    std::vector<std::pair<int32_t, SurfacePoint>> locations;  // free vertices; Inside uses -1-local
    double max_deviation = 0.0;
    // max_deviation of the first transfer that got its cost (before validation and a
    // possible re-embedding with Floater's map): what a full plan is ranked by first.
    double estimated_deviation = 0.0;
    // Smallest cosine between a new triangle's normal and an original normal on it
    // (RemovalPlan::max_normal_deviation).
    double min_normal_cosine = 1.0;
    bool used_floater = false;

private:
    const CoarseMesh& mesh_;
    const Embedding& emb_;
    const std::vector<int8_t>& sign_;
    const std::vector<Vec3>& normals_;  // oriented unit normals of the original triangles
    const std::vector<float>* ridges_ = nullptr;
    int32_t v_ = -1;
    const Fan* fan_ = nullptr;
    double scale_ = 1.0;
    // Open fans: canonical parameter (from the smaller end) of every vertex on the new edge.
    const std::unordered_map<int32_t, double>* new_edge_params_;
    bool validate_ = false;  // full validation of the new triangles' overlays (else: costs only)

    int32_t n_ = 0;   // polygon corners
    PolarMap map_;    // the polygon in the plane
    EarScratch ears_;  // of retriangulate_fan
    std::vector<std::array<int32_t, 2>> forbidden_;
    std::array<int32_t, 2> along_diagonal_{-1, -1};
    StarGraph graph_;  // the original surface in the fan
    StarGraphScratch graph_scratch_;  // of gather_star_nodes, gather_straight_segments
    // Buffers of transfer().
    RecutEdges cuts_;  // the straightened segments cut along the diagonals
    std::vector<std::array<double, 4>> triangle_boxes_;  // of locate_free_nodes: x/y min, x/y max
    TriangleCheck own_check_;  // of finish() and transfer_validate()
    std::vector<Vec3> new_normals_;                 // unit normal of every new triangle

    void compute_new_normals() {
        if (normals_.empty()) return;
        const auto& x = mesh_.positions();
        new_normals_.resize(tri.triangles.size());
        for (size_t t = 0; t < tri.triangles.size(); ++t) {
            const auto& c = tri.triangles[t];
            new_normals_[t] = triangle_normal(x[fan_->link[c[0]]], x[fan_->link[c[1]]], x[fan_->link[c[2]]]);
        }
    }

    // transfer = transfer_cost (re-cut, deviation) + transfer_validate (overlays).
    bool transfer(std::string& why) { return transfer_cost(why) && (!validate_ || transfer_validate(why)); }
    bool transfer_cost(std::string& why);
    bool transfer_validate(std::string& why);
    void set_locations();
    std::string first_reason_;  // why the first transfer failed (before Floater's map)
};

bool FanPlanner::transfer_cost(std::string& why) {
    if (!locate_free_nodes(emb_, *fan_, map_.q, tri, validate_, graph_, triangle_boxes_, why)) return false;
    if (!cut_segments(emb_, *fan_, map_.q, tri, graph_, cuts_, why)) return false;
    max_deviation = transfer_deviation(mesh_.positions(), emb_, *fan_, tri, graph_, cuts_);
    return true;
}

bool FanPlanner::transfer_validate(std::string& why) {
    if (!prepare_checks(why)) return false;
    double min_cosine = 1.0;
    if (!check_triangles(0, int32_t(tri.triangles.size()), own_check_, min_cosine, why)) return false;
    min_normal_cosine = min_cosine;
    set_locations();
    return true;
}

bool FanPlanner::prepare_checks(std::string& why) {
    min_normal_cosine = 1.0;  // a second transfer (after Floater's map) starts afresh
    return assign_pieces(*fan_, tri, graph_, cuts_, pieces, along_diagonal_, why);
}

bool FanPlanner::check_triangles(int32_t begin, int32_t end, TriangleCheck& check, double& min_cosine,
                                 std::string& why) const {
    const FanTransfer transfer{emb_, sign_, normals_, *fan_, tri, new_normals_, graph_, cuts_, pieces};
    return check_new_triangles(transfer, begin, end, check, min_cosine, why);
}

void FanPlanner::set_locations() {
    // 4. New locations of the free vertices.
    locations.clear();
    for (const StarNode& s : graph_.nodes) {
        if (!s.free) continue;
        if (s.new_triangle >= 0)
            locations.push_back({s.vertex, SurfacePoint::inside(-1 - s.new_triangle, s.bary)});
        else
            locations.push_back({s.vertex, SurfacePoint{SurfacePoint::OnEdge, s.edge_lo, s.edge_hi, s.edge_s, {}}});
    }
}

FanPlanner::Stage FanPlanner::estimate(std::string& why) {
    n_ = fan_->corners();
    if (!polar_map(mesh_.positions(), v_, *fan_, scale_, map_, why)) return Stage::Failed;
    if (!retriangulate_fan(mesh_, *fan_, map_, forbidden_, tri, ears_, why)) return Stage::Failed;
    compute_new_normals();
    if (!gather_star_nodes(mesh_, emb_, v_, *fan_, map_.q, validate_, new_edge_params_, graph_, graph_scratch_, why))
        return Stage::Failed;
    // sharpest_original_ridge() reads the nodes' ridge angles, scattered: ask for them now.
    if (ridges_ && !ridges_->empty())
        for (const StarNode& s : graph_.nodes) __builtin_prefetch(ridges_->data() + std::max(s.vertex, 0));
    if (!validate_) {
        // For ranking only: the deviation at the original vertices that move, placed by
        // the flattening. The full plan adds the new edge crossings and validates.
        if (!locate_free_nodes(emb_, *fan_, map_.q, tri, validate_, graph_, triangle_boxes_, why)) return Stage::Failed;
        const auto& x = mesh_.positions();
        max_deviation = 0.0;
        for (const StarNode& s : graph_.nodes) {
            if (s.free && s.new_triangle >= 0) {
                const auto& c = tri.triangles[s.new_triangle];
                const Vec3 flat = barycentric_point(x[fan_->link[c[0]]], x[fan_->link[c[1]]], x[fan_->link[c[2]]], s.bary);
                max_deviation = std::max(max_deviation, distance(x[s.vertex], flat));
                // A vertex strictly inside a new triangle has a piece of every triangle
                // around it there (the triangles of its edges): a lower bound of the
                // full plan's value.
                if (normals_.empty()) continue;
                const Vec3& normal = new_normals_[s.new_triangle];
                for (int32_t k = emb_.vertex_edge_offsets[s.vertex]; k < emb_.vertex_edge_offsets[s.vertex + 1]; ++k) {
                    const int32_t e = emb_.vertex_edges[k];
                    for (int32_t j = emb_.edge_triangle_offsets[e]; j < emb_.edge_triangle_offsets[e + 1]; ++j)
                        min_normal_cosine = std::min(min_normal_cosine, dot(normal, normals_[emb_.edge_triangles[j]]));
                }
            } else if ((s.free && s.diagonal >= 0) || (!fan_->closed && s.poly_edge == n_ - 1)) {
                const Vec3 flat = (1.0 - s.edge_s) * x[s.edge_lo] + s.edge_s * x[s.edge_hi];
                max_deviation = std::max(max_deviation, distance(x[s.vertex], flat));
            }
        }
        estimated_deviation = max_deviation;
        return Stage::Done;
    }
    if (!gather_straight_segments(emb_, v_, *fan_, graph_, graph_scratch_, why)) return Stage::Failed;
    first_reason_.clear();
    if (transfer_cost(first_reason_)) {
        estimated_deviation = max_deviation;
        return Stage::Estimated;
    }
    // Straightening flipped or squeezed something: reposition with Floater's map.
    if (!floater_repair(emb_, graph_, why)) return Stage::Failed;
    used_floater = true;
    if (!transfer_cost(why)) {
        why = "transfer failed (" + first_reason_ + "; after shape-preserving map: " + why + ")";
        return Stage::Failed;
    }
    estimated_deviation = max_deviation;
    return finish(why) ? Stage::Done : Stage::Failed;
}

bool FanPlanner::finish(std::string& why) {
    std::string reason;
    const bool prepared = prepare_checks(reason);
    double min_cosine = 1.0;
    const bool ok = prepared && check_triangles(0, int32_t(tri.triangles.size()), own_check_, min_cosine, reason);
    return end_finish(ok, reason, min_cosine, why);
}

bool FanPlanner::end_finish(bool checks_passed, const std::string& reason, double min_cosine, std::string& why) {
    if (checks_passed) {
        min_normal_cosine = min_cosine;
        set_locations();
        return true;
    }
    if (used_floater) {
        // The transfer after Floater's map had its cost: only its validation was left.
        why = "transfer failed (" + first_reason_ + "; after shape-preserving map: " + reason + ")";
        return false;
    }
    first_reason_ = reason;
    // The overlays are not valid: reposition with Floater's map.
    if (!floater_repair(emb_, graph_, why)) return false;
    used_floater = true;
    if (transfer(why)) return true;
    why = "transfer failed (" + first_reason_ + "; after shape-preserving map: " + why + ")";
    return false;
}

}  // namespace

// Every buffer of a VertexRemover, reused across its plans (plans are made millions of
// times). Buffers are kept one way: in this struct, handed to the stage functions
// explicitly as their own small scratch structs (StarScratch, EarScratch,
// StarGraphScratch; FanPlanner, which lives here, holds those of its stages). A
// VertexRemover is used by one thread at a time (the driver gives every planning thread
// its own), so the buffers are per thread without thread_local; unlike function-local
// static thread_local buffers they are visible in the signatures, so every stage can be
// called and tested on its own, and they are freed with their remover instead of living
// as long as the thread. (finish_part() runs parts of one plan on several threads at
// once: each part has its own TriangleCheck in `parts`.)
// append_hole_sides's buffers.
struct HoleSideScratch {
    static constexpr int32_t kTableCorners = 64;  // the table: at most 64 x 64 entries (16 kB)
    std::vector<int32_t> owner;                   // the table, all -1 between calls
    // Larger fans: each diagonal as one of its triangles runs it (corner `from` to corner
    // `to`), ordered by (from, to, triangle).
    struct DirectedDiagonal {
        int32_t from, to, triangle;
        bool operator<(const DirectedDiagonal& o) const {
            return from != o.from ? from < o.from : (to != o.to ? to < o.to : triangle < o.triangle);
        }
    };
    std::vector<DirectedDiagonal> diagonals;
};
using DirectedDiagonal = HoleSideScratch::DirectedDiagonal;

struct RemovalScratch {
    RemovalPlan disk;  // the second plan of plan(), kept for its buffers
    // A diagonal the next plan_once() must not use (a deferred validation failed on it).
    std::array<int32_t, 2> retry_forbid{-1, -1};
    std::vector<Fan> fans;
    StarScratch star;
    std::vector<SurfacePoint> points;
    std::vector<double> sigmas;
    FanPlanner planner;
    std::vector<PathEdit> edits;               // of all fans of a plan
    // finish_part(): 0 while part 0 prepares the checks, then 1 (prepared) or 2 (failed).
    std::atomic<int> prepared{0};
    std::string prepare_reason;
    struct Part {
        bool passed = false;
        double min_cosine = 1.0;
        std::string reason;
        TriangleCheck check;
    };
    Part parts[VertexRemover::kMaxFinishParts];
    std::unordered_map<int32_t, double> new_edge_params;  // see plan_once
    RidgeScratch ridges;  // of measure_new_ridges
    // Per edge of the plan's new triangles (3 i + k), what the fan knows of it:
    // sharpest_changed_ridge's `hole_sides`, appended with the new triangles
    // (append_hole_sides).
    std::vector<int32_t> hole_sides;
    HoleSideScratch hole_side_scratch;  // of append_hole_sides
    RemovalScratch(const CoarseMesh& mesh, const Embedding& embedding, const std::vector<int8_t>& sign,
                   const std::vector<Vec3>& normals)
        : planner(mesh, embedding, sign, normals) {}
};

namespace {
// The hole sides and diagonals of `fan`'s new triangles `tri` (RemovalScratch::hole_sides),
// in their order: the edge from local corner j to j + 1 is side j of the polygon, whose
// removed triangle is fan.triangles[j] (an open fan's side n - 1 is its new edge: -1); a
// diagonal is -2 - the index (in the plan's new triangles) of the fan's other triangle on
// it. The fan's first triangle is new triangle `base`. `scratch`: buffers.
void append_hole_sides(const Fan& fan, const FanTriangulation& tri, int32_t base, HoleSideScratch& scratch,
                       std::vector<int32_t>& out) {
    const int32_t n = fan.corners();
    const auto& ts = tri.triangles;
    const auto is_side = [n](int32_t a, int32_t b) { return b == (a + 1 == n ? 0 : a + 1); };
    // Per diagonal, the first triangle that runs it from corner a to corner b, so that the
    // one that runs it the other way is found directly (a search of all the triangles per
    // diagonal was quadratic, and mispredicted). Up to kTableCorners corners (nearly
    // every star) in a table of a * n + b, all -1 between calls; larger fans (the centre
    // of a CAD disc has thousands of corners: the table would grow with the square) in a
    // sorted list of the diagonals.
    const bool table = n <= HoleSideScratch::kTableCorners;
    auto& owner = scratch.owner;
    auto& diagonals = scratch.diagonals;
    const auto at = [n](int32_t a, int32_t b) { return size_t(a) * size_t(n) + size_t(b); };
    if (table && owner.size() < size_t(n) * size_t(n)) owner.resize(size_t(n) * size_t(n), -1);
    diagonals.clear();
    for (size_t i = 0; i < ts.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            const int32_t a = ts[i][k], b = ts[i][k == 2 ? 0 : k + 1];
            if (is_side(a, b)) continue;
            if (!table) diagonals.push_back({a, b, int32_t(i)});
            else if (owner[at(a, b)] < 0) owner[at(a, b)] = int32_t(i);
        }
    if (!table) std::sort(diagonals.begin(), diagonals.end());
    // The first triangle that runs a diagonal from a to b, or -1.
    const auto first_running = [&](int32_t a, int32_t b) -> int32_t {
        if (table) return owner[at(a, b)];
        const auto it = std::lower_bound(diagonals.begin(), diagonals.end(), DirectedDiagonal{a, b, -1});
        return it != diagonals.end() && it->from == a && it->to == b ? it->triangle : -1;
    };
    const size_t first = out.size();
    out.resize(first + 3 * ts.size());
    for (size_t i = 0; i < ts.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            const int32_t a = ts[i][k], b = ts[i][k == 2 ? 0 : k + 1];
            int32_t& known = out[first + 3 * i + size_t(k)];
            if (is_side(a, b)) {
                known = fan.closed || a != n - 1 ? fan.triangles[size_t(a)] : -1;
                continue;
            }
            const int32_t twin = first_running(b, a);  // the triangle that runs the diagonal the other way
            known = twin < 0 ? -1 : -2 - (base + twin);
        }
    if (table)
        for (const auto& t : ts) {
            owner[at(t[0], t[1])] = -1;
            owner[at(t[1], t[2])] = -1;
            owner[at(t[2], t[0])] = -1;
        }
}
// The parts of a plan taken from a planned fan, and the rewritten paths at the end.
void add_fan(const CoarseMesh& mesh, RemovalScratch& scratch, const Fan& fan, FanPlanner& planner, RemovalPlan& plan);
void finish_paths(const CoarseMesh& mesh, const Embedding& embedding, RemovalScratch& scratch, RemovalPlan& plan);
}  // namespace

VertexRemover::VertexRemover(const CoarseMesh& mesh, const Embedding& embedding,
                             const std::vector<int8_t>& orientation_sign, const std::vector<Vec3>& oriented_normals,
                             const std::vector<float>& vertex_ridges)
    : mesh_(mesh),
      embedding_(embedding),
      vertex_ridges_(vertex_ridges),
      scratch_(new RemovalScratch(mesh, embedding, orientation_sign, oriented_normals)) {
    scratch_->planner.set_vertex_ridges(vertex_ridges_);
}

VertexRemover::~VertexRemover() { delete scratch_; }


void VertexRemover::plan(int32_t v, bool validate, RemovalPlan& plan) {
    bool crease_line = false;
    plan_once(v, false, validate, false, plan, crease_line);
    // A crease that cannot be followed here may still end here.
    if (!plan.valid && crease_line) {
        RemovalPlan& disk = scratch_->disk;
        plan_once(v, true, validate, false, disk, crease_line);
        if (disk.valid) std::swap(plan, disk);
    }
}

void VertexRemover::plan_deferred(int32_t v, RemovalPlan& plan) {
    bool crease_line = false;
    plan_once(v, false, true, true, plan, crease_line);
    if (plan.pending) return;  // a single fan, not on a crease: nothing to retry
    if (!plan.valid && crease_line) {
        RemovalPlan& disk = scratch_->disk;
        plan_once(v, true, true, false, disk, crease_line);
        if (disk.valid) std::swap(plan, disk);
    }
}

void VertexRemover::finish_part(int part, int parts) {
    FanPlanner& planner = scratch_->planner;
    int state;
    if (part == 0) {
        try {
            state = planner.prepare_checks(scratch_->prepare_reason) ? 1 : 2;
        } catch (...) {
            scratch_->prepared.store(2, std::memory_order_release);  // the other parts must not wait forever
            throw;
        }
        scratch_->prepared.store(state, std::memory_order_release);
    } else {
        // Part 0 was taken first (tasks start in order) and runs on another thread.
        while ((state = scratch_->prepared.load(std::memory_order_acquire)) == 0) {
#if defined(__x86_64__) || defined(__i386__)
            __builtin_ia32_pause();
#else
            std::this_thread::yield();
#endif
        }
    }
    RemovalScratch::Part& p = scratch_->parts[part];
    p.passed = false;
    p.min_cosine = 1.0;
    if (state != 1) return;
    const int32_t n = planner.num_new_triangles();
    p.passed = planner.check_triangles(n * part / parts, n * (part + 1) / parts, p.check, p.min_cosine, p.reason);
}

bool VertexRemover::finish_parts_done(RemovalPlan& plan, int parts) {
    if (!plan.pending) return false;
    plan.pending = false;
    FanPlanner& planner = scratch_->planner;
    const bool prepared = scratch_->prepared.load(std::memory_order_acquire) == 1;
    scratch_->prepared.store(0, std::memory_order_relaxed);
    bool passed = prepared;
    double min_cosine = 1.0;
    const std::string* reason = &scratch_->prepare_reason;
    for (int k = 0; k < parts && passed; ++k) {
        const RemovalScratch::Part& p = scratch_->parts[k];
        min_cosine = std::min(min_cosine, p.min_cosine);
        if (!p.passed) {
            passed = false;  // the first failing triangle is in the first failing part
            reason = &p.reason;
        }
    }
    std::string why;
    if (!planner.end_finish(passed, *reason, min_cosine, why)) {
        plan.reason = why;
        if (planner.along_diagonal()[0] >= 0) {
            // An original edge along a diagonal: plan again at once without that diagonal.
            scratch_->retry_forbid = planner.along_diagonal();
            bool crease_line = false;
            plan_once(plan.vertex, false, true, false, plan, crease_line);
            return true;
        }
        return false;
    }
    plan.max_deviation = 0.0;  // Floater's map may have changed it: add_fan sets it again
    plan.new_triangles.clear();
    scratch_->hole_sides.clear();
    add_fan(mesh_, *scratch_, scratch_->fans[0], planner, plan);
    finish_paths(mesh_, embedding_, *scratch_, plan);
    return false;
}

void RemovalPlan::clear() {
    vertex = -1;
    valid = false;
    reason.clear();
    removed_triangles.clear();
    new_triangles.clear();
    new_patches.clear();
    line_sheets.clear();
    new_edges.clear();
    feature_line = false;
    feature_a = feature_b = -1;
    feature_kind = 0;
    new_locations.clear();
    new_paths.clear();
    path_versions.clear();
    max_deviation = worst_old_aspect = worst_new_aspect = longest_new_edge = 0.0;
    max_normal_deviation = 0.0;
    sharpest_new_ridge = sharpest_original_ridge = 180.0;
    estimated_deviation = 0.0;
    estimated = pending = false;
    used_floater = false;
}

void VertexRemover::plan_once(int32_t v, bool force_disk, bool validate, bool defer, RemovalPlan& plan,
                              bool& crease_line) {
    // The plan's rewritten paths go back to the spare lists before it is cleared.
    TransferPieces& spare = scratch_->planner.pieces;
    for (auto& p : plan.new_paths) spare.recycle(p.second);
    plan.clear();
    plan.vertex = v;
    scratch_->hole_sides.clear();
    auto& fans = scratch_->fans;
    const VertexClass cls = classify_star(mesh_, v, force_disk, fans, crease_line, plan.reason, scratch_->star);
    if (cls == VertexClass::Feature) return;
    const auto& x = mesh_.positions();
    // What the fans' planning reads scattered in memory, one load after another: the
    // removed triangles' aspect ratios, the heads of their inside lists, the contents of
    // the spokes (and of the link edges, for a full plan). Asked for together, these
    // misses overlap, and they arrive while the fans are flattened and triangulated.
    for (const Fan& fan : fans) {
        for (int32_t t : fan.triangles) {
            mesh_.prefetch_aspect(t);
            embedding_.inside.prefetch(t);
        }
        const int32_t n = fan.corners();
        for (int32_t i = 0; i < n; ++i) {
            embedding_.edge_content.prefetch(edge_key(v, fan.link[i]));
            if (validate) embedding_.edge_content.prefetch(edge_key(fan.link[i], fan.link[mod(i + 1, n)]));
        }
    }
    // Then for the ridge guard, which walks the triangles around the link last
    // (measure_new_ridges): the link vertices' lists.
    if (!vertex_ridges_.empty())
        for (const Fan& fan : fans)
            for (int32_t l : fan.link) mesh_.prefetch_vertex(l);

    double radius = 0.0;
    int count = 0;
    for (const Fan& fan : fans)
        for (int32_t l : fan.link) {
            radius += distance(x[l], x[v]);
            ++count;
        }
    radius /= std::max(count, 1);
    if (!(radius > 0)) {
        plan.reason = "zero-length edges around the vertex";
        return;
    }

    if (cls == VertexClass::FeatureLine) {
        const int32_t a = fans[0].link.front(), b = fans[0].link.back();
        if (mesh_.has_edge(a, b)) {
            plan.reason = "feature line would get an edge that already exists (topology condition)";
            return;
        }
        for (const Fan& fan : fans)
            if (fan.triangles.size() < 2) {
                plan.reason = "a half-disk with a single triangle";
                return;
            }
        plan.feature_line = true;
        plan.feature_a = a;
        plan.feature_b = b;
        plan.feature_kind = static_cast<uint8_t>(mesh_.feature(v, a));
        plan.new_edges.push_back({std::min(a, b), std::max(a, b)});
    }

    // A large fan (the centre of a CAD disc: thousands of corners) whose every
    // retriangulation has a triangle worse than removal_cost's shape limit is refused now,
    // in O(n): its retriangulation is O(n^2), and it is re-ranked each time one of its
    // corners goes. The margin covers the rounding of an R/r with its corners in another order.
    const auto large = [](const Fan& f) { return f.corners() > kLargeFanCorners; };
    if (aspect_limit_ < std::numeric_limits<double>::infinity() && std::any_of(fans.begin(), fans.end(), large)) {
        double limit = aspect_limit_;  // or the removed triangles' worst, as in removal_cost
        for (const Fan& fan : fans)
            for (int32_t t : fan.triangles) limit = std::max(limit, mesh_.aspect(t));
        for (const Fan& fan : fans)
            if (large(fan) && triangulation_aspect_lower_bound(x, fan) > limit * (1.0 + 1e-6)) {
                plan.reason = kShapeLimitReason;
                return;
            }
    }

    // Path edits of all fans, grouped by edge in finish_paths() (a feature-line vertex
    // has two fans that an original edge may both pass).
    for (PathEdit& e : scratch_->edits) spare.recycle(e.middle);
    scratch_->edits.clear();
    // v and the vertices on its two feature edges end up on the new feature edge a--b,
    // in the order a, ..., v, ..., b, at parameters proportional to 3D distance.
    auto& new_edge_params = scratch_->new_edge_params;
    new_edge_params.clear();
    if (plan.feature_line) {
        const int32_t a = plan.feature_a, b = plan.feature_b;
        const int32_t lo = std::min(a, b), hi = std::max(a, b);
        const double la = distance(x[v], x[a]), lb = distance(x[v], x[b]);
        const double v_from_a = la / (la + lb);
        auto put = [&](int32_t u, double from_a) {
            const double s = a == lo ? from_a : 1.0 - from_a;
            new_edge_params[u] = s;
            plan.new_locations.push_back({u, SurfacePoint{SurfacePoint::OnEdge, lo, hi, s, {}}});
        };
        put(v, v_from_a);
        for (int32_t end : {a, b}) {
            const auto* entry = embedding_.edge_content.find(edge_key(v, end));
            if (!entry) continue;
            for (int32_t u : embedding_.edge_content.view(*entry).vertices) {
                const double from_v = v < end ? embedding_.location[u].s : 1.0 - embedding_.location[u].s;
                put(u, end == a ? v_from_a * (1.0 - from_v) : v_from_a + (1.0 - v_from_a) * from_v);
            }
        }
    }
    // A single fan off crease lines can stop after the transfer's cost (finish_part() goes
    // on from there); several fans share one planner, and a crease may need the retry as a disk.
    defer = defer && validate && fans.size() == 1 && !crease_line;
    for (const auto& ne : plan.new_edges)  // the new feature edge; the diagonals follow per fan
        plan.longest_new_edge = std::max(plan.longest_new_edge, distance(x[ne[0]], x[ne[1]]));
    for (const Fan& fan : fans) {
        for (int32_t t : fan.triangles) {
            plan.removed_triangles.push_back(t);
            plan.worst_old_aspect = std::max(plan.worst_old_aspect, mesh_.aspect(t));
        }
        FanPlanner& planner = scratch_->planner;
        std::string why;
        FanPlanner::Stage stage;
        planner.clear_forbidden();
        if (scratch_->retry_forbid[0] >= 0) planner.forbid(scratch_->retry_forbid);
        scratch_->retry_forbid = {-1, -1};
        for (int attempt = 0;; ++attempt) {
            planner.reset(v, fan, radius, &new_edge_params, validate);
            why.clear();
            stage = planner.estimate(why);
            if (stage == FanPlanner::Stage::Estimated && !defer)
                stage = planner.finish(why) ? FanPlanner::Stage::Done : FanPlanner::Stage::Failed;
            // An original edge along the chosen diagonal: try again without it (a few times).
            if (stage != FanPlanner::Stage::Failed || attempt == 3 || planner.along_diagonal()[0] < 0) break;
            planner.forbid(planner.along_diagonal());
        }
        if (stage == FanPlanner::Stage::Failed) {
            plan.reason = why;
            return;
        }
        // What judging the estimate needs: the deviation, shapes and edges of the new triangles.
        plan.estimated = true;
        plan.estimated_deviation = std::max(plan.estimated_deviation, planner.estimated_deviation);
        if (!vertex_ridges_.empty())
            plan.sharpest_original_ridge =
                std::min(plan.sharpest_original_ridge, planner.sharpest_original_ridge(vertex_ridges_));
        for (double a : planner.tri.aspects) plan.worst_new_aspect = std::max(plan.worst_new_aspect, a);
        for (const auto& d : planner.tri.diagonals)
            plan.longest_new_edge = std::max(plan.longest_new_edge, distance(x[fan.link[d[0]]], x[fan.link[d[1]]]));
        if (stage == FanPlanner::Stage::Estimated) {
            if (defer) {
                plan.pending = true;
                plan.max_deviation = planner.estimated_deviation;
                // The new triangles too, for the intersection test that may run while
                // finish_part() validates (finish_parts_done() sets them again).
                for (const auto& t : planner.tri.triangles)
                    plan.new_triangles.push_back({fan.link[t[0]], fan.link[t[1]], fan.link[t[2]]});
                append_hole_sides(fan, planner.tri, 0, scratch_->hole_side_scratch, scratch_->hole_sides);
                measure_new_ridges(plan);
                return;
            }
            if (!planner.finish(why)) {
                plan.reason = why;
                return;
            }
        }
        add_fan(mesh_, *scratch_, fan, planner, plan);
    }
    // Along a feature line of three or more sheets the new edge a -- b must keep the
    // sheets in their order around the line: which apexes to compare, for the check at
    // commit (simplify/sheet_guard.h; most plans are never committed). Without them the
    // order could not be checked: refused.
    if (plan.feature_line && fans.size() >= 3 &&
        !line_sheets_of(plan.feature_a, plan.feature_b, fans, plan.new_triangles, plan.line_sheets)) {
        plan.reason = kSheetOrderReason;
        return;
    }
    measure_new_ridges(plan);
    finish_paths(mesh_, embedding_, *scratch_, plan);
}

void VertexRemover::measure_new_ridges(RemovalPlan& plan) {
    if (vertex_ridges_.empty()) return;
    // The fans of a vertex on a feature line are planned apart: an edge of one might be
    // an edge of another too where the star is not a plain disk (a link vertex in two
    // half-disks), which the search over all new triangles sees. Rare: searched then.
    if (scratch_->fans.size() > 1) scratch_->hole_sides.clear();
    plan.sharpest_new_ridge = sharpest_changed_ridge(mesh_, plan.removed_triangles, plan.new_triangles,
                                                     plan.feature_line ? plan.feature_a : -1,
                                                     plan.feature_line ? plan.feature_b : -1, scratch_->ridges,
                                                     scratch_->hole_sides);
}

namespace {

void add_fan(const CoarseMesh& mesh_, RemovalScratch& scratch, const Fan& fan, FanPlanner& planner, RemovalPlan& plan) {
    plan.used_floater = plan.used_floater || planner.used_floater;
    plan.max_deviation = std::max(plan.max_deviation, planner.max_deviation);
    plan.max_normal_deviation = std::max(
        plan.max_normal_deviation, std::acos(std::max(-1.0, std::min(1.0, planner.min_normal_cosine))) * (180.0 / M_PI));
    const int32_t base = static_cast<int32_t>(plan.new_triangles.size());
    const int32_t patch = mesh_.patch(fan.triangles[0]);
    for (size_t i = 0; i < planner.tri.triangles.size(); ++i) {
        const auto& t = planner.tri.triangles[i];
        plan.new_triangles.push_back({fan.link[t[0]], fan.link[t[1]], fan.link[t[2]]});
        plan.new_patches.push_back(patch);
        // The triangulation computed it already, for the same corners in the same order.
        plan.worst_new_aspect = std::max(plan.worst_new_aspect, planner.tri.aspects[i]);
    }
    append_hole_sides(fan, planner.tri, base, scratch.hole_side_scratch, scratch.hole_sides);
    for (const auto& d : planner.tri.diagonals) {
        const int32_t a = fan.link[d[0]], b = fan.link[d[1]];
        plan.new_edges.push_back({std::min(a, b), std::max(a, b)});
    }
    for (auto loc : planner.locations) {
        if (loc.second.kind == SurfacePoint::Inside) loc.second.a = -1 - (base + (-1 - loc.second.a));
        plan.new_locations.push_back(loc);
    }
    for (auto& e : planner.pieces.path_edits) scratch.edits.push_back(std::move(e));
}

void finish_paths(const CoarseMesh& mesh, const Embedding& embedding, RemovalScratch& scratch, RemovalPlan& plan) {
    const auto& x = mesh.positions();
    auto& locations = plan.new_locations;
    auto& edits = scratch.edits;
    std::sort(locations.begin(), locations.end(),
              [](const auto& p, const auto& q) { return p.first < q.first; });

    // Rewrite the paths of the edited edges, in increasing edge order.
    // A fan's edits come in this order already (its segments run by edge, then along it),
    // so only a plan of two fans needs the sort (std::stable_sort allocates its buffer).
    auto before = [](const PathEdit& p, const PathEdit& q) {
        return p.edge < q.edge || (p.edge == q.edge && p.first < q.first);
    };
    if (!std::is_sorted(edits.begin(), edits.end(), before)) std::stable_sort(edits.begin(), edits.end(), before);
    auto& points = scratch.points;
    auto& sigmas = scratch.sigmas;
    for (size_t begin = 0, end = 0; begin < edits.size(); begin = end) {
        const int32_t e = edits[begin].edge;
        for (end = begin; end < edits.size() && edits[end].edge == e; ++end) {
        }
        embedding.path_points(e, points, sigmas);
        std::vector<Crossing> crossings = scratch.planner.pieces.take();
        const int32_t last = static_cast<int32_t>(points.size()) - 1;
        size_t count = std::max(last - 1, 0);
        for (size_t k = begin; k < end; ++k) count += edits[k].middle.size();
        crossings.reserve(count);  // at most: the old middle points and all new crossings
        auto keep = [&](int32_t j) { crossings.push_back({points[j].a, points[j].b, points[j].s, sigmas[j]}); };
        int32_t j = 1;  // next old middle point to copy; points[0] and points[last] are the vertices
        for (size_t k = begin; k < end; ++k) {
            const auto& edit = edits[k];
            for (; j <= edit.first && j < last; ++j) keep(j);
            crossings.insert(crossings.end(), edit.middle.begin(), edit.middle.end());
            j = std::max(j, edit.last);
        }
        for (; j < last; ++j) keep(j);
        plan.new_paths.push_back({e, std::move(crossings)});
        plan.path_versions.push_back(embedding.path_version[e]);
    }
    for (const auto& ne : plan.new_edges)
        plan.longest_new_edge = std::max(plan.longest_new_edge, distance(x[ne[0]], x[ne[1]]));
    plan.valid = true;
}

}  // namespace

void commit_removal(CoarseMesh& mesh, Embedding& embedding, const RemovalPlan& plan) {
    // Unregister moved vertices first: their old triangles are about to disappear.
    for (const auto& loc : plan.new_locations) embedding.clear_location(loc.first);
    mesh.remove_triangles(plan.removed_triangles);
    std::vector<int32_t> ids;
    for (size_t i = 0; i < plan.new_triangles.size(); ++i)
        ids.push_back(mesh.add_triangle(plan.new_triangles[i], plan.new_patches[i]));
    embedding.ensure_triangle_capacity(mesh.triangle_capacity());
    for (auto loc : plan.new_locations) {
        if (loc.second.kind == SurfacePoint::Inside) loc.second.a = ids[-1 - loc.second.a];
        // clear_location was already called; set without unregistering twice.
        embedding.location[loc.first] = SurfacePoint::corner(loc.first);
        embedding.set_location(loc.first, loc.second);
    }
    for (const auto& p : plan.new_paths) embedding.set_path(p.first, p.second);
    // Edges at the removed vertex are gone, with their marks.
    for (const Tri& t : plan.new_triangles)
        for (int32_t x : t) mesh.set_feature_edge(plan.vertex, x, CoarseMesh::Feature::None);
    if (plan.feature_line)
        mesh.set_feature_edge(plan.feature_a, plan.feature_b, static_cast<CoarseMesh::Feature>(plan.feature_kind));
}

}  // namespace bpm::detail
