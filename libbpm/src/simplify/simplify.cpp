// Driver of the simplification: a priority queue over the vertices, and the loop of
// steps in Simplifier::run (pick, plan, validate, commit, re-rank). Its parts, each with
// its contract in its header:
//   vertex_removal.h     the local work: plan and commit the removal of one vertex
//   removal_cost.h       the queue key of a removal and the limits that refuse one
//   intersection_test.h  new triangles against the rest of the coarse surface
//   planning_pool.h      the threads that share a round's tasks
//   edge_flip.h          the final flips of needles and of edges under thin tetrahedra
//   export_phi.h         the final phi written out as a Parametrization
#include "bpm/simplify.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <future>
#include <limits>
#include <deque>
#include <memory>
#include <mutex>
#include <functional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "bpm/check.h"
#include "bpm/errors.h"
#include "core/crease_chains.h"
#include "core/edge_uses.h"
#include "core/free_memory.h"
#include "core/number_text.h"
#include "simplify/coarse_mesh.h"
#include "simplify/edge_flip.h"
#include "simplify/embedding.h"
#include "simplify/export_phi.h"
#include "simplify/input_intersections.h"
#include "simplify/intersection_test.h"
#include "simplify/island_guard.h"
#include "simplify/overlay.h"
#include "simplify/planning_pool.h"
#include "simplify/removal_cost.h"
#include "simplify/ridge_guard.h"
#include "simplify/wedge_guard.h"
#include "simplify/clearance_guard.h"
#include "simplify/corner_wedge_guard.h"
#include "simplify/sheet_guard.h"
#include "simplify/vertex_order.h"
#include "simplify/vertex_removal.h"

namespace bpm {

using namespace detail;

namespace {

struct QueueEntry {
    double cost;
    int32_t vertex;
    uint32_t stamp;  // of the vertex when ranked: the entry is stale once the stamp moved on
    bool operator>(const QueueEntry& o) const {
        return cost > o.cost || (cost == o.cost && vertex > o.vertex);
    }
};

// The queue of removals, cheapest first: std::priority_queue's operations (push_heap and
// pop_heap over a vector, so the same order), with room reserved once. Stale entries stay
// until they reach the top, so the heap grows to several entries per vertex, and growing
// by doubling held the old and the new array at once (208k-triangle input: 4 + 8 MB at
// the peak of the loop); untouched reserved pages cost nothing.
class RemovalQueue {
public:
    void reserve(size_t n) { heap_.reserve(n); }
    bool empty() const { return heap_.empty(); }
    const QueueEntry& top() const { return heap_.front(); }
    void push(const QueueEntry& e) {
        heap_.push_back(e);
        std::push_heap(heap_.begin(), heap_.end(), std::greater<QueueEntry>());
    }
    void pop() {
        std::pop_heap(heap_.begin(), heap_.end(), std::greater<QueueEntry>());
        heap_.pop_back();
    }
    void release() { decltype(heap_)().swap(heap_); }

private:
    std::vector<QueueEntry> heap_;
};

// A complete full plan of a removal that waits in the queue (its cost after validation
// was above the next entry), reused when the entry comes back unchanged.
struct WaitingPlan {
    uint32_t stamp = 0;      // stamp of the vertex when planned
    int64_t made_at = -1;    // number of removals committed when the intersections were tested, or -1
    bool intersects = false; // intersects_rest, valid while no removal was committed since
    RemovalPlan plan;
};

// Why each vertex could not be removed when last tried: per vertex an index into the
// distinct texts (0: none). A std::string per vertex was 32 bytes each (3.3 MB for 104k
// vertices) for a handful of different texts. set() runs on the planning threads, each
// for its own vertices and with its own index of the texts it has met: a text is looked
// up behind the lock only the first time a thread meets it (a handful of times per run),
// not for every refused plan. The numbers are never shown: only the texts are.
class ReasonTable {
public:
    void reset(size_t vertices, int threads) {
        of_.assign(vertices, 0);
        texts_.assign(1, std::string());
        index_.clear();
        known_.assign(size_t(std::max(threads, 1)), {});
    }
    // On planning thread `thread` (of the pool's round, or 0 between rounds).
    void set(int32_t v, const std::string& why, int thread) {
        if (why.empty()) {
            of_[size_t(v)] = 0;
            return;
        }
        auto& known = known_[size_t(thread)];
        auto it = known.find(why);
        if (it == known.end()) it = known.emplace(why, intern(why)).first;
        of_[size_t(v)] = it->second;
    }
    // Not while set() may run.
    const std::string& operator[](int32_t v) const { return texts_[of_[size_t(v)]]; }
    void release() {
        decltype(of_)().swap(of_);
        decltype(texts_)().swap(texts_);
        decltype(index_)().swap(index_);
        decltype(known_)().swap(known_);
    }

private:
    uint32_t intern(const std::string& why) {
        std::lock_guard<std::mutex> lock(mutex_);
        auto [it, added] = index_.try_emplace(why, uint32_t(texts_.size()));
        if (added) texts_.push_back(why);
        return it->second;
    }
    std::vector<uint32_t> of_;        // per vertex
    std::deque<std::string> texts_;   // [0] empty
    std::unordered_map<std::string, uint32_t> index_;  // of texts_, behind mutex_
    std::vector<std::unordered_map<std::string, uint32_t>> known_;  // per thread: the texts it has met
    std::mutex mutex_;
};

// One of the removals tried in a step (at most SimplifyOptions::removals_per_step). A
// cache line or more each: a planning thread writes its candidate's fields at the end of
// its task while another thread works on the next candidate.
struct alignas(64) Candidate {
    QueueEntry entry{};
    RemovalPlan* plan = nullptr;
    VertexRemover* remover = nullptr;  // of the plan (a pending plan's validation is in it)
    int known_intersection = -1;       // -1 unknown, else whether it intersects the rest
    bool intersects = false;           // result of the validation round's intersection test
    bool live = false;                 // still to be committed in this step
    bool committed = false;            // removed in this step
    bool validated_early = false;      // tested and validated in the planning round (plan_round)
    bool replanned = false;            // its validation in plan_round made a new plan (finish_parts_done)
    // The commit-time guards already asked in plan_round or validate_round, on the surface
    // as the step found it: exact for the step's first commit (nothing changed since), asked
    // again after one.
    bool guarded_early = false;
    const char* guard_refusal = nullptr;  // refused_by_guards' answer then
};

// The buffers of the commit-time guards (simplify/*_guard.h): one set per planning thread
// (plan_round and validate_round ask the guards too).
struct GuardScratch {
    std::vector<int32_t> sheet;                  // keeps_sheet_order's
    IslandGuard::Scratch island;                 // sweeps_island's
    WedgeScratch wedge;                          // keeps_feature_wedges'
    std::vector<TriangleGrid::Entry> clearance;  // keeps_clearance's
};

// What one planning thread writes during a round besides its remover, on cache lines of
// its own: the threads change these for every plan (a vector's end with every push), and
// two threads writing the same line make it travel between their cores each time.
struct alignas(64) ThreadState {
    RemovalPlan cheap_plan;                    // of rank()
    std::vector<TriangleGrid::Entry> grid;     // intersects_rest's buffer
    GuardScratch guards;                       // refused_by_guards' buffers
    std::string why;                           // judge()'s reason
    int64_t cheap_plans = 0;                   // made on this thread (debug log)
};

// A step's plan of one slot, on cache lines of its own (written by the thread planning it).
struct alignas(64) SlotPlan {
    RemovalPlan plan;
};

// The removals of one step of the loop, and what their commits changed.
struct Step {
    std::vector<Candidate> candidates;  // removals_per_step slots, each with its plan and planner
    int count = 0;                      // slots used by this step
    int64_t commits_before = 0;     // commits when the step began to commit
    int32_t first_new = 0;          // first triangle id the step's commits created
    std::vector<int32_t> affected;  // the vertices around the committed removals
    std::vector<std::pair<int32_t, Tri>> grid_removed;  // the triangles the commits removed
    std::vector<int32_t> star;         // pick(): the candidates so far and their links
    std::vector<QueueEntry> skipped;   // pick(): entries passed over (in a candidate's star)
};

// Wall and process CPU seconds of simplify()'s phases (SimplifyResult::phases): each
// phase runs from its start() to the next one's, or to finish(). Measured here rather
// than told apart by the progress stages, which are free text for the user.
class PhaseTimer {
public:
    void start(std::string name) {
        close();
        open_ = true;
        current_.name = std::move(name);
        now(current_.wall_seconds, current_.cpu_seconds);
    }
    // Ends the current phase; the phases so far, in order.
    std::vector<SimplifyPhaseTime> finish() {
        close();
        return std::move(phases_);
    }

private:
    void close() {
        if (!open_) return;
        double wall = 0, cpu = 0;
        now(wall, cpu);
        current_.wall_seconds = wall - current_.wall_seconds;
        current_.cpu_seconds = cpu - current_.cpu_seconds;
        phases_.push_back(current_);
        open_ = false;
    }
    static void now(double& wall, double& cpu) {
        wall = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
        timespec c{};
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c);
        cpu = double(c.tv_sec) + 1e-9 * double(c.tv_nsec);
    }
    bool open_ = false;
    SimplifyPhaseTime current_;
    std::vector<SimplifyPhaseTime> phases_;
};

constexpr int kMaxRemovalsPerStep = 64;  // SimplifyOptions::removals_per_step
// The kinds of the steps' rounds (PlanningPool::run_round): after each the other threads
// wait differently long (the caller's slower plan; the commits; the next pick), so the
// pool learns a spin budget per kind. Only timing.
constexpr int kPlanRound = 1, kValidationRound = 2, kRerankRound = 3;
const std::string kSelfIntersection = "would create a self-intersection";

// The vertex count to stop at (0: none): the larger of the two targets asked for.
int64_t target_vertex_count(const SimplifyOptions& options, int64_t input_vertices) {
    int64_t target = 0;
    if (options.target_vertices > 0) target = options.target_vertices;
    if (options.target_ratio > 0) {
        const int64_t by_ratio = static_cast<int64_t>(std::ceil(options.target_ratio * double(input_vertices)));
        target = std::max(target, by_ratio);
    }
    return target;
}

// The simplification as a loop of steps over a priority queue of vertices (cheapest
// removal first). A step picks up to two removals, plans them in full, validates them,
// commits those still admissible and re-ranks the vertices around them; run() reads as
// that loop. The work of a step is shared by threads in rounds (PlanningPool): every task
// of a round reads the state and writes only its own outputs, and the state changes only
// between rounds. Which tasks a round has never depends on the thread count, so neither
// does the output.
class Simplifier {
public:
    Simplifier(const Surface& original, const SimplifyOptions& options, const Context& context, int threads,
               PhaseTimer& timer)
        : Simplifier(original, options, context, threads, timer, EdgeUses(original)) {}

    SimplifyResult run(Parametrization& out);

    // True when check_intersections(original) passes, decided on the grid of the set-up
    // (simplify/input_intersections.h); false: run the check for its verdict and report.
    // Before run().
    bool input_surely_passes_intersection_check() const {
        return surely_passes_intersection_check(original_, intersections_.grid());
    }

    // Messages (trace_removals, self_check) name vertices by the caller's ids: `user_vertex`
    // maps the ids of `original` (simplify/vertex_order.h) to them; must outlive run().
    void name_vertices_by(const std::vector<int32_t>& user_vertex) { user_vertex_ = &user_vertex; }

private:
    // The wedge guard's floor (simplify/wedge_guard.h): --min-ridge-angle 0 turns it off
    // with the ridge guard, a lower one lowers it too.
    double junction_wedge_floor() const {
        return std::min(kJunctionWedgeFloorDegrees, options_.min_ridge_angle_degrees);
    }
    double clearance_floor() const {
        return options_.min_ridge_angle_degrees > 0 ? (mesh_.one_patch() ? kClearanceFloor : kMultiPatchClearanceFloor) : 0.0;
    }
    double crease_wedge_floor() const { return std::min(kCreaseWedgeFloorDegrees, options_.min_ridge_angle_degrees); }
    double corner_wedge_floor() const { return std::min(kCornerWedgeFloorDegrees, options_.min_ridge_angle_degrees); }
    // `uses`: the original's sides grouped by edge, counted once for the coarse mesh's
    // orientation walk and the embedding's edges (each used to collect its own).
    Simplifier(const Surface& original, const SimplifyOptions& options, const Context& context, int threads,
               PhaseTimer& timer, const EdgeUses& uses)
        : original_(original),
          options_(options),
          context_(context),
          timer_(timer),
          mesh_(original, uses),
          diagonal_(bounding_box_diagonal(original)),
          target_(target_vertex_count(options, original.num_vertices())),
          intersections_(mesh_),
          islands_(mesh_) {
        // Room for the triangle ids the removals will make, at once (the per-triangle arrays
        // grew by doubling: a copy of the old arrays beside the new ones). A removal of a
        // vertex of valence d makes d - 2 triangles and the mean valence is 3 T / V, so
        // this is about 4 per removal: an upper estimate (armadillo: 3.2 to 3.3), and
        // reserved pages that are never written are never resident.
        if (target_ > 0 && original.num_vertices() > target_ && original.num_vertices() > 0) {
            const double made = std::clamp(3.0 * double(original.num_triangles()) / double(original.num_vertices()) - 2.0,
                                           1.0, 8.0);
            mesh_.reserve_triangles(size_t(double(original.num_triangles()) +
                                           made * double(original.num_vertices() - target_) * 1.01) + 1024);
        }
        CreaseRule crease_rule;
        crease_rule.feature_angle_degrees = options.feature_angle_degrees;
        crease_rule.chain_angle_degrees = options.crease_chain_angle_degrees;
        crease_rule.min_chain_length = options.crease_chain_length * diagonal_;
        mesh_.mark_feature_edges(crease_rule);
        mesh_.mark_corners(options.feature_angle_degrees, options.corner_crease_length * diagonal_,
                           options.keep_corners);
        sign_.resize(original.triangles.size());
        for (int32_t t = 0; t < original.num_triangles(); ++t) sign_[t] = mesh_.flipped_initially(t) ? -1 : 1;
        // Only with a limit: the angle costs about 5% of the planning time.
        if (options.max_normal_deviation_degrees < 180.0 || options.distortion_weight > 0 ||
            options.fold_limit_degrees < 180.0 || options.fold_weight > 0)
            oriented_normals_.resize(original.triangles.size());
        for (int32_t t = 0; t < int32_t(oriented_normals_.size()); ++t) {
            const Tri& c = original.triangles[t];
            oriented_normals_[t] = double(sign_[t]) * triangle_normal(original.vertices[c[0]], original.vertices[c[1]],
                                                                       original.vertices[c[2]]);
        }
        embedding_.init_identity(original, mesh_.triangle_capacity(), uses);
        // The ridge guard (simplify/ridge_guard.h), only when asked for.
        if (options.min_ridge_angle_degrees > 0) vertex_ridges_ = vertex_ridge_angles(original, embedding_);
        remover_ = std::make_unique<VertexRemover>(mesh_, embedding_, sign_, oriented_normals_, vertex_ridges_);
        for (int i = 1; i < threads; ++i) removers_.push_back(std::make_unique<VertexRemover>(mesh_, embedding_, sign_, oriented_normals_, vertex_ridges_));
        // A pending plan keeps its validation in its planner: one planner per slot of a
        // step (slot 0 shares thread 0's, which ranks only after the step's commits).
        const int slots = std::max(1, options.removals_per_step);
        step_plans_.resize(size_t(slots));
        step_.candidates.resize(size_t(slots));
        for (int k = 0; k < slots; ++k) {
            if (k > 0) candidate_removers_.push_back(std::make_unique<VertexRemover>(mesh_, embedding_, sign_, oriented_normals_, vertex_ridges_));
            step_.candidates[size_t(k)].plan = &step_plans_[size_t(k)].plan;
            step_.candidates[size_t(k)].remover = k == 0 ? remover_.get() : candidate_removers_.back().get();
        }
        // Large stars that removal_cost would refuse for their shape are refused unplanned.
        remover_->set_aspect_limit(options.max_aspect_ratio);
        for (auto& r : removers_) r->set_aspect_limit(options.max_aspect_ratio);
        for (auto& r : candidate_removers_) r->set_aspect_limit(options.max_aspect_ratio);
        finish_parts_ = std::min<int>(VertexRemover::kMaxFinishParts, threads);
        per_thread_.resize(size_t(threads));
        stamp_.assign(original.vertices.size(), 0);
        // The clearance guard's bound on the longest edge: the original's, then every
        // commit's new triangles (and, for the report, the flips').
        for (const Tri& t : original.triangles) longest_edge_ = std::max(longest_edge_, longest_edge(original.vertices, t));
    }

    // The caller's id of vertex v, for messages.
    int32_t user_id(int32_t v) const { return user_vertex_ ? (*user_vertex_)[size_t(v)] : v; }

    const Surface& original_;
    const std::vector<int32_t>* user_vertex_ = nullptr;  // name_vertices_by
    const SimplifyOptions& options_;
    const Context& context_;
    PhaseTimer& timer_;
    CoarseMesh mesh_;
    Embedding embedding_;
    std::vector<int8_t> sign_;
    std::vector<Vec3> oriented_normals_;  // unit normals of the original triangles, coarse orientation
    std::vector<float> vertex_ridges_;    // the original's vertex_ridge_angles, or empty (ridge guard off)
    std::unique_ptr<VertexRemover> remover_;         // of thread 0 and of the first removal of a step
    std::vector<std::unique_ptr<VertexRemover>> candidate_removers_;  // of the step's removals 1..
    std::vector<std::unique_ptr<VertexRemover>> removers_;  // of threads 1..
    std::vector<SlotPlan> step_plans_;               // of the step's removals (Candidate::plan)
    std::vector<int> to_plan_;                       // plan_round: the slots planned anew
    std::vector<ThreadState> per_thread_;            // per planning thread
    int finish_parts_ = 1;                           // of a deferred validation (VertexRemover::finish_part)
    double diagonal_;
    int64_t target_;                  // vertices to stop at, 0: none
    IntersectionTest intersections_;  // of new triangles with the rest of the surface
    IslandGuard islands_;                  // of the components (two or more: removals must not sweep one)
    std::vector<Tri> clearance_also_;  // the new triangles of this step's earlier commits (not in the grid yet)
    double longest_edge_ = 0;          // at least the longest edge of the coarse surface
    std::vector<uint32_t> stamp_;     // per vertex, moved on when its star changes
    RemovalQueue queue_;
    // Full plans of entries pushed back because their real cost was higher than the
    // estimate; reused when the entry comes back with the same stamp.
    std::unordered_map<int32_t, WaitingPlan> full_plans_;
    ReasonTable last_reason_;  // per vertex: why it could not be removed when last tried
    Step step_;
    std::vector<double> rerank_costs_;
    int32_t first_new_ = 0;  // first triangle id of the last commit (self_check)
    int64_t full_plans_made_ = 0;
    int64_t cheap_plans_made_ = 0;  // summed from ThreadState::cheap_plans when they are freed
    int64_t commits_ = 0;
    int64_t reused_plans_ = 0;
    // What became of the candidates of the steps (debug log): taken, held back by their
    // estimate, waiting after validation, gone stale or intersecting after an earlier
    // commit of their step, meeting an earlier commit's new triangles.
    int64_t taken_ = 0, held_back_ = 0, waited_ = 0, stale_ = 0, met_ = 0, steps_ = 0;
    // Wall seconds of the steps' parts: queue (pick, hold back), plan round, validation
    // round, commits, re-ranking round; and of the grid updates (a task of the latter).
    double step_seconds_[6] = {};
    // For progress reports.
    int64_t start_vertices_ = 0;
    int64_t next_report_ = 256;  // removals
    double error_so_far_ = 0.0;  // largest error of a committed removal (of the diagonal)

    // The phases of run().
    SimplifyResult describe_input() const;
    void rank_all(PlanningPool& pool);
    bool pick();
    void plan_round(PlanningPool& pool);
    void hold_back_by_estimate();
    void validate_round(PlanningPool& pool);
    int commit_step(SimplifyResult& result);
    void rerank_round(PlanningPool& pool);
    void report_progress(const SimplifyResult& result);
    void state_stop_reason(SimplifyResult& result) const;
    void count_blocked(SimplifyResult& result);
    void report_slivers(SimplifyResult& result);
    void flip_edges_phase(SimplifyResult& result);
    void release_planning_state();
    void summarize(const Parametrization& out, double max_deviation, std::chrono::steady_clock::time_point start,
                   SimplifyResult& result) const;

    // Their pieces.
    VertexRemover& remover(int thread) { return thread == 0 ? *remover_ : *removers_[thread - 1]; }
    bool current(const QueueEntry& e) const { return e.stamp == stamp_[e.vertex] && mesh_.vertex_alive(e.vertex); }
    // Queue key of v from a cheap plan (a lower bound of the full plan's cost), +infinity
    // if it cannot be removed now (reason recorded). On the remover of `thread`.
    double rank(int32_t v, RemovalPlan& plan, int thread);
    // removal_cost() of the plan to remove v, the reason for +infinity recorded.
    // CostBasis::Estimate: the cost a full plan is ranked by first (the same for a plan
    // whose validation is pending and for a complete one).
    // On planning thread `thread` (0 between rounds).
    double judge(int32_t v, const RemovalPlan& plan, int thread, CostBasis basis = CostBasis::Plan) {
        std::string& why = per_thread_[size_t(thread)].why;
        const double cost = removal_cost(plan, options_, diagonal_, basis, why);
        last_reason_.set(v, why, thread);
        return cost;
    }
    // Whether candidate k, at cost `cost`, waits: its cost is above the next entry's (the
    // queue's top, or a later candidate of the step) by more than the queue tolerance.
    bool waits(int k, double cost) const;
    // Whether candidate k is removed now (its cost in `cost`); else it went back into
    // the queue (with its plan, if complete) or was refused (reason recorded).
    bool ready_to_commit(int k, double& cost);
    void commit(int k, double cost, SimplifyResult& result);
    bool admissible_globally(int32_t v, const RemovalPlan& plan);
    // The guards a plan to remove v meets at commit, on the surface as it is now: sheet
    // order, islands, wedges, clearance (simplify/*_guard.h); the reason of the first
    // that refuses it, or nullptr. `first_unindexed`: the first triangle the grid lacks;
    // `also`: new triangles the grid lacks (this step's earlier commits). Reads the state
    // only (a planning thread may ask, with its own `scratch`).
    const char* refused_by_guards(int32_t v, const RemovalPlan& plan, int32_t first_unindexed,
                                  const std::vector<Tri>& also, GuardScratch& scratch) const;
    // A full plan made earlier is still exact if its star is unchanged (stamp), no
    // edited path changed elsewhere, and its new edges still do not exist.
    bool still_current(const RemovalPlan& plan) const;
    void self_check(int32_t removed_vertex, const std::vector<int32_t>& link, int64_t step);
};

SimplifyResult Simplifier::run(Parametrization& out) {
    const auto start = std::chrono::steady_clock::now();
    SimplifyResult result = describe_input();
    PlanningPool pool(static_cast<int>(removers_.size()) + 1);
    timer_.start("first ranking");
    rank_all(pool);
    timer_.start("removals");
    start_vertices_ = mesh_.num_vertices_alive();
    // Wall seconds of the parts of the steps (debug log): which parts are serial.
    auto lap = [last = std::chrono::steady_clock::now(), this](int part) mutable {
        const auto now = std::chrono::steady_clock::now();
        step_seconds_[part] += std::chrono::duration<double>(now - last).count();
        last = now;
    };
    while (mesh_.num_vertices_alive() > target_ && pick()) {
        lap(0);
        ++steps_;
        taken_ += step_.count;
        plan_round(pool);
        lap(1);
        hold_back_by_estimate();
        lap(0);
        validate_round(pool);
        lap(2);
        const int committed = commit_step(result);
        lap(3);
        if (committed == 0) continue;
        if (committed >= 2) ++result.paired_steps;
        rerank_round(pool);
        report_progress(result);
        lap(4);
    }
    result.refused_in_step = met_;
    state_stop_reason(result);
    count_blocked(result);
    if (options_.flip_edges) timer_.start("edge flips");
    flip_edges_phase(result);
    report_slivers(result);
    timer_.start("export of phi");
    release_planning_state();
    context_.report(0.95, "writing the parametrization");
    const double max_deviation = export_parametrization(original_, mesh_, embedding_, sign_, pool, out);
    summarize(out, max_deviation, start, result);
    context_.report(1.0, "done");
    return result;
}

SimplifyResult Simplifier::describe_input() const {
    SimplifyResult result;
    result.input_vertices = original_.num_vertices();
    result.input_triangles = original_.num_triangles();
    result.crease_junctions = mesh_.corner_count(CoarseMesh::Corner::Junction);
    result.crease_cone_ends = mesh_.corner_count(CoarseMesh::Corner::ConeEnd);
    result.line_feature_vertices = mesh_.hard_feature_vertices();
    result.corners_kept = options_.keep_corners;
    if (options_.record_steps) result.steps.emplace();  // record of the removals (bpm-check --replay)
    return result;
}

// First ranking of all vertices by cheap plans, in chunks.
void Simplifier::rank_all(PlanningPool& pool) {
    const int32_t nv = original_.num_vertices();
    last_reason_.reset(original_.vertices.size(), pool.threads());
    // 256 vertices per task; above 2^27 vertices more, so that a round has at most
    // 2^19 tasks (the pool takes fewer than 2^20). The costs do not depend on it.
    const int32_t chunk = std::max<int32_t>(256, int32_t((int64_t(nv) + (1 << 19) - 1) >> 19));
    const size_t chunks = size_t((int64_t(nv) + chunk - 1) / chunk);
    std::vector<double> costs(nv, std::numeric_limits<double>::infinity());
    std::atomic<int32_t> ranked{0};
    pool.run_round(chunks, [&](int thread, size_t i) {
        const int32_t first = int32_t(int64_t(i) * chunk), last = int32_t(std::min<int64_t>(nv, int64_t(first) + chunk));
        for (int32_t v = first; v < last; ++v) {
            RemovalPlan& plan = per_thread_[size_t(thread)].cheap_plan;
            remover(thread).plan(v, false, plan);
            costs[v] = judge(v, plan, thread);
        }
        const int32_t done = ranked.fetch_add(last - first) + (last - first);
        if (thread == 0) context_.report(0.2 * done / std::max(nv, 1), "evaluating vertices");
    });
    per_thread_[0].cheap_plans += nv;
    // The heap reaches 3 to 5 entries per vertex (208k-triangle input: ~400k for 104k
    // vertices); beyond the reservation it grows as before.
    queue_.reserve(8 * size_t(nv) + 1024);
    for (int32_t v = 0; v < nv; ++v) {
        ++stamp_[v];
        if (std::isfinite(costs[v])) queue_.push({costs[v], v, stamp_[v]});
    }
}

// Up to removals_per_step removals per step: the queue's top, then in queue order the
// next entries that are in none of the earlier candidates' stars (so that no two stars
// share a triangle), passing over at most 3 entries per further candidate (the passed
// over go back). Their plans, validations and re-rankings share the rounds (other threads
// otherwise idle while the top is planned). A later candidate is committed after the
// earlier ones only if its plan is still valid then (ready_to_commit), else it goes back
// into the queue as it was. (The plan is valid, not necessarily the one a planner would
// choose after the earlier removals: an ear they blocked could have changed a near-tie,
// or let a crease be followed where the plan ends it.) Which entries are taken depends
// on the queue only, never on the thread count. False: the queue is empty.
bool Simplifier::pick() {
    while (!queue_.empty() && !current(queue_.top())) queue_.pop();
    if (queue_.empty()) return false;
    Step& s = step_;
    const int slots = int(s.candidates.size());
    s.count = 0;
    s.candidates[size_t(s.count++)].entry = queue_.top();
    queue_.pop();
    if (slots == 1) return true;
    s.star.clear();
    auto add_star = [&](int32_t v) {
        s.star.push_back(v);
        for (int32_t t : mesh_.triangles_of(v))
            for (int32_t u : mesh_.triangle(t)) s.star.push_back(u);
    };
    add_star(s.candidates[0].entry.vertex);
    s.skipped.clear();
    const size_t max_skipped = 3 * size_t(slots - 1);
    while (s.count < slots && !queue_.empty() && s.skipped.size() < max_skipped) {
        const QueueEntry e = queue_.top();
        queue_.pop();
        if (!current(e)) continue;
        if (std::find(s.star.begin(), s.star.end(), e.vertex) == s.star.end()) {
            s.candidates[size_t(s.count++)].entry = e;
            if (s.count < slots) add_star(e.vertex);
        } else {
            s.skipped.push_back(e);
        }
    }
    for (const QueueEntry& e : s.skipped) queue_.push(e);
    return true;
}

// The full plans of the candidates. The neighbourhood of a candidate is unchanged since
// its ranking (stamp), but other removals may have changed things near it: plan again
// (one task per candidate, the validation deferred), or reuse a waiting full plan that
// is provably still the same.
void Simplifier::plan_round(PlanningPool& pool) {
    std::vector<int>& to_plan = to_plan_;
    to_plan.clear();
    for (int k = 0; k < step_.count; ++k) {
        Candidate& c = step_.candidates[k];
        c.known_intersection = -1;
        c.live = true;
        c.committed = false;
        c.validated_early = false;
        c.replanned = false;
        c.guarded_early = false;
        auto cached = full_plans_.find(c.entry.vertex);
        if (cached != full_plans_.end() && cached->second.stamp == c.entry.stamp && still_current(cached->second.plan)) {
            WaitingPlan& wp = cached->second;
            if (wp.made_at == commits_) c.known_intersection = wp.intersects;
            *c.plan = std::move(wp.plan);
            full_plans_.erase(cached);
            ++reused_plans_;
        } else {
            to_plan.push_back(k);
        }
    }
    // A plan whose estimate is not above its queue key never waits (waits()): it is
    // tested and validated in the same task, exactly as the validation round would do it
    // (the state does not change in between; the test sees the triangles planned before
    // the validation, which may re-plan), which spares that round most of its tasks.
    const size_t count = to_plan.size();
    pool.run_round(count, [&](int thread, size_t i) {
        Candidate& c = step_.candidates[to_plan[i]];
        const int32_t v = c.entry.vertex;
        c.remover->plan_deferred(v, *c.plan);
        c.validated_early = false;
        c.replanned = false;
        if (!c.plan->pending) return;
        const double estimate = judge(v, *c.plan, thread, CostBasis::Estimate);
        if (!std::isfinite(estimate) || estimate > c.entry.cost + 1e-15) return;
        if (options_.prevent_intersections)
            c.intersects = intersections_.intersects_rest(c.plan->new_triangles, c.plan->removed_triangles,
                                                          per_thread_[size_t(thread)].grid);
        c.remover->finish_part(0, 1);
        c.replanned = c.remover->finish_parts_done(*c.plan, 1);
        c.validated_early = true;
        // The guards too (ready_to_commit asks them last), while the state is the one the
        // step's first commit will see (they were a third of the serial commit time); only
        // for the queue's top, which is nearly always that commit: a later candidate is
        // asked again after it (asking every candidate here cost ~4 % more CPU on one thread:
        // a second candidate is asked again after the first commit in 3 of 5 steps).
        if (to_plan[i] == 0 && !c.replanned && c.plan->valid && !(options_.prevent_intersections && c.intersects)) {
            c.guard_refusal = refused_by_guards(v, *c.plan, mesh_.triangle_capacity(), {}, per_thread_[size_t(thread)].guards);
            c.guarded_early = true;
        }
    }, kPlanRound);
    // A plan made again during its validation was not tested: the validation round tests it.
    for (int k : to_plan) {
        Candidate& c = step_.candidates[k];
        if (c.validated_early && options_.prevent_intersections && !c.replanned) c.known_intersection = c.intersects;
    }
    full_plans_made_ += int64_t(count);
}

// A full plan is ranked by its estimate first (the cost before validation): if that is
// above the next entry by more than the queue tolerance, the removal waits, unvalidated
// (most such plans never come back unchanged).
void Simplifier::hold_back_by_estimate() {
    for (int k = 0; k < step_.count; ++k) {
        Candidate& c = step_.candidates[k];
        if (c.validated_early) continue;  // its estimate did not wait (plan_round)
        const int32_t v = c.entry.vertex;
        const double estimate = judge(v, *c.plan, 0, CostBasis::Estimate);
        if (!std::isfinite(estimate)) {
            c.live = false;
        } else if (waits(k, estimate)) {
            ++held_back_;
            queue_.push({estimate, v, stamp_[v]});
            c.live = false;
        }
    }
}

bool Simplifier::waits(int k, double cost) const {
    // The queue's top may be stale (a vertex re-ranked or removed since): about half the
    // calls on a 208k-triangle input see one, and 105 of 158k decisions would differ.
    // Popping stale tops first (what pick() does) was tried: 0.05 % fewer full plans,
    // every output different, and the Hausdorff distance of femur at 390 vertices 10 %
    // worse (0.00841 vs 0.00763), fandisk at 648 11 % better: a change of the removal
    // order, not of its quality. Kept as it is.
    double next = std::numeric_limits<double>::infinity();
    if (!queue_.empty()) next = queue_.top().cost;
    for (int j = k + 1; j < step_.count; ++j)
        if (step_.candidates[j].live) next = std::min(next, step_.candidates[j].entry.cost);
    if (!(cost > step_.candidates[k].entry.cost + 1e-15) || !std::isfinite(next)) return false;
    return cost > next + options_.queue_tolerance * std::abs(next);
}

// The validations of the live candidates' pending plans, and in the same round the
// intersection tests of their new triangles against the rest of the surface (which the
// validations do not touch). Parts 0 first: the other parts of a validation wait for
// their preparation (VertexRemover::finish_part).
void Simplifier::validate_round(PlanningPool& pool) {
    struct Check {
        int8_t slot;  // candidate
        int8_t part;  // of its validation; -1: its intersection test; -2: its guards
    };
    Check checks[kMaxRemovalsPerStep * (VertexRemover::kMaxFinishParts + 1) + 1];
    size_t count = 0;
    auto validating = [&](int k) { return step_.candidates[k].live && step_.candidates[k].plan->pending; };
    for (int k = 0; k < step_.count; ++k)
        if (validating(k)) checks[count++] = {int8_t(k), 0};
    // A validation is split into parts only when there are fewer than two validations per
    // thread (a part waits for its validation's preparation); the result is the same
    // either way.
    const int parts = int(count) >= 2 * pool.threads() ? 1 : finish_parts_;
    for (int k = 0; k < step_.count; ++k)
        if (step_.candidates[k].live && options_.prevent_intersections && step_.candidates[k].known_intersection < 0)
            checks[count++] = {int8_t(k), -1};
    for (int part = 1; part < parts; ++part)
        for (int k = 0; k < step_.count; ++k)
            if (validating(k)) checks[count++] = {int8_t(k), int8_t(part)};
    // The queue top's guards, if plan_round did not ask them, beside its validation: on
    // the plan's triangles, which its validation keeps unless it plans again (as for the
    // intersection test). Only with other threads to share the round: on one thread they
    // are asked at the commit, and not at all for a plan its validation refuses.
    const Candidate& top = step_.candidates[0];
    if (pool.threads() > 1 && top.live && !top.guarded_early && top.known_intersection != 1 &&
        (top.plan->pending || top.plan->valid))
        checks[count++] = {0, -2};
    pool.run_round(count, [&](int thread, size_t i) {
        Candidate& c = step_.candidates[checks[i].slot];
        if (checks[i].part == -2)
            c.guard_refusal = refused_by_guards(c.entry.vertex, *c.plan, mesh_.triangle_capacity(), {},
                                                per_thread_[size_t(thread)].guards);
        else if (checks[i].part < 0)
            c.intersects = intersections_.intersects_rest(c.plan->new_triangles, c.plan->removed_triangles,
                                                          per_thread_[size_t(thread)].grid);
        else
            c.remover->finish_part(checks[i].part, parts);
    }, kValidationRound);
    bool replanned[kMaxRemovalsPerStep] = {};
    bool guarded_top = false;
    for (size_t i = 0; i < count; ++i) {
        Candidate& c = step_.candidates[checks[i].slot];
        if (checks[i].part == -2) guarded_top = true;
        else if (checks[i].part < 0) c.known_intersection = c.intersects;
        if (checks[i].part == 0) replanned[checks[i].slot] = c.remover->finish_parts_done(*c.plan, parts);
    }
    if (guarded_top && !replanned[0]) step_.candidates[0].guarded_early = true;
    // The test of a plan made again during this validation saw the pending plan's
    // triangles: unknown again (the first candidate is tested at its commit, a later one
    // goes back into the queue).
    for (int k = 0; k < step_.count; ++k)
        if (replanned[k]) step_.candidates[k].known_intersection = -1;
}

// Commits the live candidates that are still ready, in order; returns how many.
int Simplifier::commit_step(SimplifyResult& result) {
    step_.commits_before = commits_;
    step_.first_new = mesh_.triangle_capacity();
    step_.affected.clear();
    step_.grid_removed.clear();
    int committed = 0;
    for (int k = 0; k < step_.count; ++k) {
        double cost = 0.0;
        if (!step_.candidates[k].live || !ready_to_commit(k, cost)) continue;
        commit(k, cost, result);
        step_.candidates[k].committed = true;
        ++committed;
    }
    return committed;
}

bool Simplifier::ready_to_commit(int k, double& cost) {
    Candidate& c = step_.candidates[k];
    const int32_t v = c.entry.vertex;
    RemovalPlan& plan = *c.plan;
    const bool after_first = k > 0 && commits_ > step_.commits_before;
    // After an earlier removal of this step: is this plan still valid? (Its intersection
    // test saw the earlier ones' old triangles, which may be all it met: then it is tested
    // again later; so is a plan without a test, made again during its validation.)
    const bool untested = options_.prevent_intersections && c.known_intersection < 0;
    if (after_first && (mesh_.num_vertices_alive() <= target_ || !still_current(plan) || c.known_intersection == 1 ||
                        untested)) {
        ++stale_;
        queue_.push(c.entry);
        return false;
    }
    // Floater's map or the normal limit may still raise the cost; then it waits with its
    // complete plan.
    cost = judge(v, plan, 0);
    if (!std::isfinite(cost)) return false;
    if (waits(k, cost)) {
        ++waited_;
        WaitingPlan& wp = full_plans_[v];
        wp.stamp = stamp_[v];
        wp.made_at = c.known_intersection < 0 ? -1 : step_.commits_before;
        wp.intersects = c.known_intersection == 1;
        wp.plan = std::move(plan);
        queue_.push({cost, v, stamp_[v]});
        return false;
    }
    if (after_first) {
        // Its new triangles must not meet those of any earlier removal of the step (its
        // intersection test saw the surface before them).
        if (options_.prevent_intersections)
            for (int j = 0; j < k; ++j)
                if (step_.candidates[j].committed &&
                    meet_improperly(original_.vertices, plan.new_triangles, step_.candidates[j].plan->new_triangles)) {
                    last_reason_.set(v, kSelfIntersection, 0);
                    ++met_;
                    return false;
                }
    } else if (c.known_intersection >= 0 ? c.known_intersection == 1 : !admissible_globally(v, plan)) {
        if (c.known_intersection == 1) last_reason_.set(v, kSelfIntersection, 0);
        return false;
    }
    // Last, the guards on the surface as it is now (the grid lacks the triangles this
    // step's commits made: passed on).
    clearance_also_.clear();
    for (int j = 0; j < k; ++j)
        if (step_.candidates[j].committed)
            for (const Tri& t : step_.candidates[j].plan->new_triangles) clearance_also_.push_back(t);
    // Asked in plan_round or validate_round on the surface as the step found it: the same
    // answer unless an earlier removal of this step was committed since.
    const char* why = c.guarded_early && !after_first
                          ? c.guard_refusal
                          : refused_by_guards(v, plan, step_.first_new, clearance_also_, per_thread_[0].guards);
    if (why) {
        last_reason_.set(v, why, 0);
        return false;
    }
    return true;
}

const char* Simplifier::refused_by_guards(int32_t v, const RemovalPlan& plan, int32_t first_unindexed,
                                          const std::vector<Tri>& also, GuardScratch& scratch) const {
    // The sheets on the other side of a junction edge may have changed since the plan was
    // made, without touching its star.
    if (!keeps_line_sheet_order(mesh_.positions(), plan.feature_a, v, plan.feature_b, plan.line_sheets) ||
        !keeps_sheet_order(mesh_, plan.removed_triangles, plan.new_triangles, scratch.sheet))
        return kSheetOrderReason;
    // No other component inside the volume the star sweeps (only with two or more).
    if (islands_.active() &&
        islands_.sweeps_island(mesh_, intersections_.grid(), first_unindexed, v,
                               plan.feature_line ? plan.feature_a : -1, plan.feature_line ? plan.feature_b : -1,
                               plan.removed_triangles, plan.new_triangles, scratch.island))
        return kIslandReason;
    if (!keeps_feature_wedges(mesh_, plan.removed_triangles, plan.new_triangles, plan.feature_a, v, plan.feature_b,
                              scratch.wedge, junction_wedge_floor(), crease_wedge_floor()))
        return kJunctionWedgeReason;
    if (!keeps_corner_wedges(mesh_, plan.removed_triangles, plan.new_triangles, corner_wedge_floor()))
        return kCornerWedgeReason;
    if (options_.prevent_intersections && clearance_floor() > 0 &&
        !keeps_clearance(mesh_, intersections_.grid(), plan.removed_triangles, plan.new_triangles, also,
                         longest_edge_, scratch.clearance, clearance_floor()))
        return kClearanceReason;
    return nullptr;
}

void Simplifier::commit(int k, double cost, SimplifyResult& result) {
    const Candidate& c = step_.candidates[k];
    const int32_t v = c.entry.vertex;
    const RemovalPlan& plan = *c.plan;
    if (options_.trace_removals) {
        char line[200];
        std::snprintf(line, sizeof line,
                      "remove vertex %d: cost %.10g, error %.6g, worst aspect %.4g (was %.4g), normal deviation %.3g deg",
                      user_id(v), cost, plan.max_deviation / diagonal_, plan.worst_new_aspect, plan.worst_old_aspect,
                      plan.max_normal_deviation);
        context_.debug(line);
    }
    std::vector<int32_t>& affected = step_.affected;
    const size_t affected_begin = affected.size();
    for (int32_t t : plan.removed_triangles)
        for (int32_t u : mesh_.triangle(t))
            if (u != v) affected.push_back(u);
    // The grid follows in the re-ranking round (its planning does not read the grid).
    for (int32_t t : plan.removed_triangles) step_.grid_removed.push_back({t, mesh_.triangle(t)});
    first_new_ = mesh_.triangle_capacity();
    for (const Tri& t : plan.new_triangles) longest_edge_ = std::max(longest_edge_, longest_edge(mesh_.positions(), t));
    commit_removal(mesh_, embedding_, plan);
    if (result.steps) result.steps->append(v, plan.new_triangles, plan.new_patches);
    ++commits_;
    error_so_far_ = std::max(error_so_far_, plan.max_deviation / diagonal_);
    ++stamp_[v];
    full_plans_.erase(v);
    ++result.removed;
    if (plan.used_floater) ++result.shape_preserving_repairs;
    if (options_.self_check)
        self_check(v, std::vector<int32_t>(affected.begin() + affected_begin, affected.end()), result.removed);
}

// New costs of the vertices around the step's removals (their stars changed), and in
// the same round the grid update (cheap plans do not read the grid).
void Simplifier::rerank_round(PlanningPool& pool) {
    std::vector<int32_t>& affected = step_.affected;
    // No removed vertex was in another's star: `affected` holds live vertices only.
    std::sort(affected.begin(), affected.end());
    affected.erase(std::unique(affected.begin(), affected.end()), affected.end());
    for (int32_t u : affected) {
        ++stamp_[u];
        full_plans_.erase(u);
    }
    rerank_costs_.assign(affected.size(), 0.0);
    pool.run_round(affected.size() + 1, [&](int thread, size_t i) {
        if (i == 0) {
            const auto t0 = std::chrono::steady_clock::now();
            intersections_.update(step_.grid_removed, step_.first_new);
            step_seconds_[5] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        }
        else
            rerank_costs_[i - 1] = rank(affected[i - 1], per_thread_[size_t(thread)].cheap_plan, thread);
    }, kRerankRound);
    intersections_.rebuild_if_sparse();
    for (size_t i = 0; i < affected.size(); ++i)
        if (std::isfinite(rerank_costs_[i])) queue_.push({rerank_costs_[i], affected[i], stamp_[affected[i]]});
}

void Simplifier::report_progress(const SimplifyResult& result) {
    if (result.removed < next_report_) return;
    next_report_ = result.removed + 256;
    const double done = start_vertices_ > target_ ? double(start_vertices_ - mesh_.num_vertices_alive()) /
                                                        double(start_vertices_ - target_)
                                                  : 1.0;
    char line[128];
    std::snprintf(line, sizeof line, "simplifying: %d vertices left, error %.2g of diagonal",
                  mesh_.num_vertices_alive(), error_so_far_);
    context_.report(0.2 + 0.74 * std::min(done, 1.0), line);  // up to 0.94: the edge flips report 0.94
}

// Whether the target was reached, and why the loop ended.
void Simplifier::state_stop_reason(SimplifyResult& result) const {
    std::string stop = "no vertex can be removed any more";
    if (mesh_.num_vertices_alive() <= target_) {
        result.target_reached = true;
        stop = "target reached";
    } else if (target_ == 0 && std::isfinite(options_.max_error)) {
        // Only an error limit was asked for: stopping at it is the goal.
        result.target_reached = true;
        stop = "every further removal would exceed the error limit or another limit";
    }
    if (!result.target_reached && target_ > 0 && target_ < result.kept_feature_vertices()) {
        // Say what the target runs into, not only that nothing could be removed.
        stop = "the target of " + std::to_string(target_) + " vertices is below the " +
               std::to_string(result.kept_feature_vertices()) + " feature vertices, which are never removed (";
        std::string parts;
        auto part = [&](int64_t n, const char* what) {
            if (n > 0) parts += (parts.empty() ? "" : ", ") + std::to_string(n) + " " + what;
        };
        if (result.corners_kept) {
            part(result.crease_junctions, "corners where three or more feature edges meet");
            part(result.crease_cone_ends, "ends of creases at sharp cones");
        }
        part(result.line_feature_vertices, "ends or junctions of boundaries, patch borders or non-manifold lines");
        stop += parts + ")";
        const int64_t others = mesh_.num_vertices_alive() - result.kept_feature_vertices();
        if (others > 0) stop += "; " + std::to_string(others) + " other vertices could not be removed either";
    }
    result.stop_reason = stop;
}

// Why the vertices that remain could not be removed, counted by reason, when the target
// was not reached.
void Simplifier::count_blocked(SimplifyResult& result) {
    if (result.target_reached) return;
    for (int32_t v = 0; v < original_.num_vertices(); ++v) {
        if (!mesh_.vertex_alive(v)) continue;
        std::string why = last_reason_[v];
        if (why.empty()) {
            RemovalPlan& plan = step_plans_[0].plan;
            remover_->plan(v, true, plan);
            why = plan.valid ? "not reached" : plan.reason;
        }
        ++result.blocked[why];
        if (options_.trace_removals) context_.debug("vertex " + std::to_string(user_id(v)) + " kept: " + why);
    }
}

// The coarse triangles worse than max_aspect_ratio at the end (no removal or flip makes
// one, so they are input slivers that stayed), the worst with why each corner stays: a
// full plan of its removal now, judged as the loop would. Only a report: the surface is
// not changed. Without it a sliver of R/r 1e21 reached bpm-mesh silently.
void Simplifier::report_slivers(SimplifyResult& result) {
    std::vector<int32_t> alive;
    mesh_.alive_triangles(alive);
    const auto& x = mesh_.positions();
    std::vector<std::pair<double, int32_t>> bad;
    for (int32_t t : alive) {
        const Tri& c = mesh_.triangle(t);
        const double r = aspect_ratio(x[c[0]], x[c[1]], x[c[2]]);
        if (!(r <= options_.max_aspect_ratio)) bad.push_back({r, t});
    }
    result.slivers = int64_t(bad.size());
    // Worst first; ties (and NaN-free infinities) by triangle id: deterministic.
    std::sort(bad.begin(), bad.end(), [](const auto& p, const auto& q) {
        return p.first > q.first || (p.first == q.first && p.second < q.second);
    });
    if (bad.size() > SimplifyResult::kListedSlivers) bad.resize(SimplifyResult::kListedSlivers);
    // The clearance guard's bound on the longest edge, which the final edge flips kept
    // for themselves (a flip's new diagonal may be longer than the edges before it).
    if (!bad.empty())
        for (int32_t t : alive) longest_edge_ = std::max(longest_edge_, longest_edge(x, mesh_.triangle(t)));
    RemovalPlan& plan = step_plans_[0].plan;
    for (const auto& [r, t] : bad) {
        const Tri& c = mesh_.triangle(t);
        SliverReport s;
        s.aspect_ratio = r;
        s.centroid = (1.0 / 3.0) * (x[c[0]] + x[c[1]] + x[c[2]]);
        for (int k = 0; k < 3; ++k) {
            const int32_t v = c[k];
            s.vertices[size_t(k)] = v;
            remover_->plan(v, true, plan);
            std::string why;
            const double cost = removal_cost(plan, options_, diagonal_, CostBasis::Plan, why);
            if (std::isfinite(cost)) {
                if (options_.prevent_intersections &&
                    intersections_.intersects_rest(plan.new_triangles, plan.removed_triangles, per_thread_[0].grid))
                    why = kSelfIntersection;
                else if (const char* guard = refused_by_guards(v, plan, mesh_.triangle_capacity(), {}, per_thread_[0].guards))
                    why = guard;
                else {
                    char text[160];
                    std::snprintf(text, sizeof text, "removable (new triangles up to R/r %.3g, error %.3g of diagonal), %s",
                                  plan.worst_new_aspect, plan.max_deviation / diagonal_,
                                  result.target_reached ? "but the target was reached first" : "after the last removals");
                    why = text;
                }
            }
            if (why.empty()) why = "its removal is refused (no reason recorded)";
            s.kept[size_t(k)] = why;
        }
        result.worst_slivers.push_back(std::move(s));
    }
}

// Frees what only the loop needs (the grid, the queue, the waiting plans, the planners
// and their buffers) before phi is exported: the export's arrays reuse that memory, so
// the peak of a run is lower (the export needs the coarse mesh and the embedding only).
void Simplifier::release_planning_state() {
    intersections_.release();
    queue_.release();
    decltype(full_plans_)().swap(full_plans_);
    last_reason_.release();
    decltype(stamp_)().swap(stamp_);
    decltype(oriented_normals_)().swap(oriented_normals_);
    decltype(vertex_ridges_)().swap(vertex_ridges_);
    decltype(rerank_costs_)().swap(rerank_costs_);
    for (const ThreadState& t : per_thread_) cheap_plans_made_ += t.cheap_plans;
    decltype(per_thread_)().swap(per_thread_);
    decltype(step_plans_)().swap(step_plans_);
    decltype(to_plan_)().swap(to_plan_);
    step_ = Step();
    remover_.reset();
    candidate_removers_.clear();
    removers_.clear();
    // The flips are done: no triangle is added any more.
    mesh_.release_aspects();
    mesh_.shrink_to_fit();
    // No path changes now; only the planners compared the versions of paths (still_current).
    embedding_.freeze();
}

// Edge flips of needles and of edges under thin tetrahedra (edge_flip.h), within the
// largest error a removal reached.
void Simplifier::flip_edges_phase(SimplifyResult& result) {
    if (!options_.flip_edges) return;
    context_.report(0.94, "flipping edges of needles and slivers");
    FlipLimits limits;
    limits.needle_aspect = options_.max_aspect_ratio;
    limits.sliver_dihedral_degrees = options_.flip_min_dihedral_degrees;
    limits.max_deviation = error_so_far_ * diagonal_;
    limits.prevent_intersections = options_.prevent_intersections;
    limits.junction_wedge_floor = junction_wedge_floor();
    limits.crease_wedge_floor = crease_wedge_floor();
    limits.corner_wedge_floor = corner_wedge_floor();
    limits.clearance_floor = clearance_floor();
    limits.min_ridge_angle_degrees = options_.min_ridge_angle_degrees;
    const FlipStats stats = flip_edges(mesh_, embedding_, sign_, intersections_, limits, &islands_, &vertex_ridges_);
    result.needle_flips = stats.needle_flips;
    result.sliver_flips = stats.sliver_flips;
    context_.debug("edge flips: " + std::to_string(stats.needle_flips) + " of needles, " +
                   std::to_string(stats.sliver_flips) + " under thin tetrahedra, " + std::to_string(stats.refused) +
                   " refused");
}

// What was achieved: sizes, error and shape of the coarse surface, time, and the
// planner's statistics in the debug log.
void Simplifier::summarize(const Parametrization& out, double max_deviation,
                           std::chrono::steady_clock::time_point start, SimplifyResult& result) const {
    result.output_vertices = out.coarse.num_vertices();
    result.output_triangles = out.coarse.num_triangles();
    result.max_error = diagonal_ > 0 ? max_deviation / diagonal_ : 0.0;
    for (const Tri& t : out.coarse.triangles)
        result.worst_aspect_ratio = std::max(
            result.worst_aspect_ratio,
            aspect_ratio(out.coarse.vertices[t[0]], out.coarse.vertices[t[1]], out.coarse.vertices[t[2]]));
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    context_.debug("plans: " + std::to_string(cheap_plans_made_) + " cheap, " + std::to_string(full_plans_made_) +
                   " full (" + std::to_string(reused_plans_) + " reused); " + std::to_string(result.paired_steps) +
                   " steps removed two or more vertices; " + std::to_string(steps_) + " steps took " +
                   std::to_string(taken_) + " candidates: " + std::to_string(held_back_) + " held back by the estimate, " +
                   std::to_string(waited_) + " waited after validation, " + std::to_string(stale_) +
                   " stale after an earlier commit, " + std::to_string(met_) + " met an earlier commit; " +
                   std::to_string(result.shape_preserving_repairs) + " removals re-embedded with Floater's map");
    char line[300];
    std::snprintf(line, sizeof line,
                  "step parts, wall s: queue %.3f, plan rounds %.3f, validation rounds %.3f, commits %.3f, "
                  "re-ranking rounds %.3f (of which grid updates %.3f)",
                  step_seconds_[0], step_seconds_[1], step_seconds_[2], step_seconds_[3], step_seconds_[4],
                  step_seconds_[5]);
    context_.debug(line);
}

double Simplifier::rank(int32_t v, RemovalPlan& plan, int thread) {
    remover(thread).plan(v, false, plan);
    ++per_thread_[size_t(thread)].cheap_plans;
    return judge(v, plan, thread);
}

bool Simplifier::still_current(const RemovalPlan& plan) const {
    for (size_t i = 0; i < plan.new_paths.size(); ++i)
        if (embedding_.path_version[plan.new_paths[i].first] != plan.path_versions[i]) return false;
    for (const auto& e : plan.new_edges)
        if (mesh_.has_edge(e[0], e[1])) return false;
    for (const Tri& t : plan.new_triangles)
        if (mesh_.find_triangle(t[0], t[1], t[2]) >= 0) return false;
    return true;
}

bool Simplifier::admissible_globally(int32_t v, const RemovalPlan& plan) {
    if (options_.prevent_intersections &&
        intersections_.intersects_rest(plan.new_triangles, plan.removed_triangles, per_thread_[0].grid)) {
        last_reason_.set(v, kSelfIntersection, 0);
        return false;
    }
    return true;
}

void Simplifier::self_check(int32_t removed_vertex, const std::vector<int32_t>& link, int64_t step) {
    TriangleGraph graph;
    std::vector<OverlayFace> faces;
    std::vector<Tri> pieces;
    std::vector<int32_t> piece_triangle;
    std::vector<int32_t> tris;
    for (int32_t u : link) tris.insert(tris.end(), mesh_.triangles_of(u).begin(), mesh_.triangles_of(u).end());
    std::sort(tris.begin(), tris.end());
    tris.erase(std::unique(tris.begin(), tris.end()), tris.end());
    for (int32_t t : tris) {
        build_triangle_graph(mesh_, embedding_, t, graph);
        std::string why;
        if (!compute_faces(graph, embedding_, sign_, faces, &why) ||
            !triangulate_faces(graph, embedding_, sign_, faces, pieces, piece_triangle, &why)) {
            const Tri& c = mesh_.triangle(t);
            throw AlgorithmError("self-check after removal " + std::to_string(step) + " of vertex " +
                                 std::to_string(user_id(removed_vertex)) + ": coarse triangle " + std::to_string(t) +
                                 " (" + std::to_string(user_id(c[0])) + "," + std::to_string(user_id(c[1])) + "," +
                                 std::to_string(user_id(c[2])) +
                                 ", " + std::to_string(graph.nodes.size()) + " nodes, " +
                                 std::to_string(graph.segments.size()) + " segments" +
                                 (t >= first_new_ ? ", new" : ", old") + "): " + why);
        }
    }
}

}  // namespace

namespace {

// \throw OptionError for contradictory options.
void check_options(const SimplifyOptions& options) {
    if (options.target_ratio < 0 || options.target_ratio > 1)
        throw OptionError("target_ratio must be between 0 and 1, got " + detail::significant_text(options.target_ratio, 6));
    if (options.target_vertices < 0) throw OptionError("target_vertices must not be negative");
    if (!(options.max_error >= 0)) throw OptionError("max_error must not be negative");
    if (!(options.max_edge_length > 0)) throw OptionError("max_edge_length must be positive");
    if (!(options.max_aspect_ratio >= 2)) throw OptionError("max_aspect_ratio must be at least 2 (equilateral)");
    if (!(options.flip_min_dihedral_degrees >= 0 && options.flip_min_dihedral_degrees <= 60))
        throw OptionError("flip_min_dihedral_degrees must be between 0 and 60 degrees");
    if (!(options.max_normal_deviation_degrees >= 0 && options.max_normal_deviation_degrees <= 180))
        throw OptionError("max_normal_deviation_degrees must be between 0 and 180 degrees");
    if (!(options.distortion_weight >= 0) || !(options.fold_limit_degrees >= 0 && options.fold_limit_degrees <= 180))
        throw OptionError("distortion_weight must be >= 0 and fold_limit_degrees between 0 and 180 degrees");
    if (!(options.fold_weight >= 0) || !std::isfinite(options.fold_weight))
        throw OptionError("fold_weight must be finite and >= 0");
    if (!(options.removals_per_step >= 1 && options.removals_per_step <= kMaxRemovalsPerStep))
        throw OptionError("removals_per_step must be between 1 and " + std::to_string(kMaxRemovalsPerStep) + ", got " +
                          std::to_string(options.removals_per_step));
    if (!(options.queue_tolerance >= 0 && options.queue_tolerance <= 10))
        throw OptionError("queue_tolerance must be between 0 and 10");
    if (!(options.corner_crease_length >= 0 && options.corner_crease_length <= 1))
        throw OptionError("the corner crease length must be between 0 and 1 (of the diagonal)");
    detail::check_crease_rule_numbers(options.feature_angle_degrees, options.crease_chain_angle_degrees,
                                      options.crease_chain_length);
    if (!(options.min_ridge_angle_degrees >= 0 && options.min_ridge_angle_degrees <= 90))
        throw OptionError("min_ridge_angle_degrees must be between 0 and 90 degrees");
}

// The input check's verdict and first problem named by the caller's ids: on a failure
// found in the simplifier's numbering, the check again on a copy in the caller's order
// (only for the message: the first problem in that order, as the caller numbers it).
// When the first problem's two triangles are in different patches, it says so: one
// surface per material (per label of a segmentation, per segment) meshed separately meets
// its neighbour in an interface that is not the same triangles on both sides, and the
// user has to know that the overlap is there, not a defect inside one material's surface.
CheckResult check_intersections_in_user_order(const Surface& original, const InputOrder& order,
                                              const CheckOptions& options, const Context& context) {
    Surface user = original;
    to_user_order(user, order);
    CheckResult r = check_intersections(user, options, context, "input intersections");
    if (!r.problems.empty()) {
        CheckProblem& first = r.problems.front();
        const int64_t a = first.id("triangle"), b = first.id("other_triangle");
        const auto has_patch = [&](int64_t t) { return t >= 0 && t < int64_t(user.patches.size()); };
        const auto patch_of = [&](int64_t t) { return user.patches[size_t(t)]; };  // any int32
        if (has_patch(a) && has_patch(b) && patch_of(a) != patch_of(b))
            first.message += ", in patches " + std::to_string(patch_of(a)) + " and " + std::to_string(patch_of(b)) +
                             " (if these are the surfaces of two materials, meshed one material at a time, their "
                             "common interface must be the same triangles in both, or be stored once as in an "
                             "Amira .surf or a Gmsh physical surface named A|B)";
    }
    return r;
}

// simplify() after check_options(), on `original` (out.original) in the simplifier's
// numbering `order` (simplify/vertex_order.h); the results still in that numbering.
SimplifyResult simplify_checked(const Surface& original, const InputOrder& order, const SimplifyOptions& options,
                                const Context& context, Parametrization& out) {
    const int threads = planning_threads(options.threads, original.num_triangles());
    context.debug(std::to_string(threads) + (threads == 1 ? " thread" : " threads") +
                  (options.threads == 0 ? " (automatic: threads = 0)" : ""));
    std::unique_ptr<Simplifier> simplifier;
    PhaseTimer timer;
    if (options.reject_self_intersecting_input) {
        context.report(0.0, "checking the input for self-intersections");
        CheckOptions check_options;
        check_options.max_problems = 1;
        CheckResult r;
        if (threads > 1) {
            // The check and the set-up of the simplification (coarse mesh, features,
            // embedding, grid) only read the input: side by side.
            timer.start("input intersection check with set-up");
            auto check = std::async(std::launch::async, [&] {
                return check_intersections(original, check_options, Context{}, "input intersections");
            });
            simplifier = std::make_unique<Simplifier>(original, options, context, threads, timer);
            r = check.get();
            if (!r.passed) r = check_intersections_in_user_order(original, order, check_options, Context{});
        } else {
            // One thread: the set-up first, then the check walks the set-up's grid
            // instead of building a structure of its own; the check itself runs only
            // when that walk cannot prove that it passes (for its report).
            timer.start("set-up");
            simplifier = std::make_unique<Simplifier>(original, options, context, threads, timer);
            timer.start("input intersection check");
            if (simplifier->input_surely_passes_intersection_check())
                r.passed = true;
            else
                r = check_intersections_in_user_order(original, order, check_options, context);
        }
        if (!r.passed)
            throw AlgorithmError("the input surface intersects itself (" + detail::count_text(r.problem_count, "problem") +
                                 "; first: " + (r.problems.empty() ? std::string("?") : r.problems[0].describe()) +
                                 "); bpm needs a surface without self-intersections to produce a coarse surface "
                                 "without them. Repair the input (repair_self_intersections() replaces the triangles around "
                                 "a few local ones), or set reject_self_intersecting_input = false");
    }
    if (!simplifier) {
        timer.start("set-up");
        simplifier = std::make_unique<Simplifier>(original, options, context, threads, timer);
    }
    simplifier->name_vertices_by(order.user_vertex);
    SimplifyResult result = simplifier->run(out);
    result.threads = threads;
    timer.start("freeing the simplifier's state");
    simplifier.reset();
    return_free_memory();
    result.phases = timer.finish();
    return result;
}

// simplify() after check_options() on out.original (the input as the caller gave it, the
// rest of `out` empty): renumbered in Morton order for the run and given back as it came,
// every id of the results mapped back to the caller's (simplify/vertex_order.h: why).
SimplifyResult simplify_in_morton_order(const SimplifyOptions& options, const Context& context, Parametrization& out) {
    const InputOrder order = morton_order(out.original);
    to_internal_order(out.original, order);
    SimplifyResult result;
    try {
        result = simplify_checked(out.original, order, options, context, out);
    } catch (...) {
        to_user_order(out.original, order);
        throw;
    }
    to_user_order(out.original, order);
    phi_to_user_order(out, order);
    if (result.steps) steps_to_user_order(*result.steps, order);
    for (SliverReport& s : result.worst_slivers)
        for (int32_t& v : s.vertices) v = order.user_vertex[size_t(v)];
    return result;
}

}  // namespace

SimplifyResult simplify(const Surface& original, const SimplifyOptions& options, const Context& context,
                        Parametrization& out) {
    check_options(options);
    // Before anything is computed (or, for the overload taking it, `original` taken).
    if (const std::string why = coordinate_range_problem(original); !why.empty()) throw AlgorithmError(why);
    if (&original == &out.original) {  // simplify(p.original, ..., p): keep it, drop the rest
        Surface kept = std::move(out.original);
        out = Parametrization();
        out.original = std::move(kept);
    } else {
        out = Parametrization();
        out.original = original;
    }
    return simplify_in_morton_order(options, context, out);
}

SimplifyResult simplify(Surface&& original, const SimplifyOptions& options, const Context& context,
                        Parametrization& out) {
    check_options(options);
    // Before anything is computed (or, for the overload taking it, `original` taken).
    if (const std::string why = coordinate_range_problem(original); !why.empty()) throw AlgorithmError(why);
    out = Parametrization();
    out.original = std::move(original);
    return simplify_in_morton_order(options, context, out);
}

}  // namespace bpm
