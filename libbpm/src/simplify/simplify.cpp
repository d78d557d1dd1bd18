// Driver of the simplification: priority queue over vertices, global admissibility
// (intersections with the rest of the surface, error and edge-length limits), and
// export of the final parametrization. The local work is in vertex_removal.cpp.
#include "bpm/simplify.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <future>
#include <functional>
#include <memory>
#include <mutex>
#include <queue>
#include <stdexcept>
#include <thread>
#include <unordered_map>

#include "bpm/check.h"
#include "bpm/errors.h"
#include "bpm/predicates.h"
#include "simplify/coarse_mesh.h"
#include "simplify/distortion.h"
#include "simplify/embedding.h"
#include "simplify/overlay.h"
#include "simplify/triangle_grid.h"
#include "simplify/vertex_removal.h"

namespace bpm {

using namespace detail;

namespace {

// Threads of a simplification: --threads, or for 0 two unless every core is busy. (The
// second thread spins between rounds, so bpm's own earlier runs count in the load too.)
int planning_threads(const SimplifyOptions& options) {
    if (options.threads > 0) return std::min(options.threads, 64);
    const unsigned cores = std::thread::hardware_concurrency();
    if (cores < 2) return 1;
    double load = 0.0;
    if (getloadavg(&load, 1) == 1 && load >= double(cores)) return 1;
    return 2;
}

struct QueueEntry {
    double cost;
    int32_t vertex;
    uint32_t stamp;
    bool operator>(const QueueEntry& o) const {
        return cost > o.cost || (cost == o.cost && vertex > o.vertex);
    }
};

// Threads that share the planning work of one round. The caller runs tasks too; a
// round returns when all its tasks are done. Which tasks a round has never depends on
// timing, so results do not depend on the number of threads.
//
// Rounds are short (a few plans, tens of microseconds) and follow each other quickly,
// so idle workers spin for a while before they sleep: waking a sleeping thread costs
// about as much as a plan.
class PlanningPool {
public:
    // `work(thread, task)` runs task `task` on thread `thread` (0 = the caller).
    PlanningPool(int threads, std::function<void(int, size_t)> work) : work_(std::move(work)) {
        for (int i = 1; i < threads; ++i) workers_.emplace_back([this, i] { serve(i); });
    }
    ~PlanningPool() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        wake_.notify_all();
        for (auto& w : workers_) w.join();
    }
    int threads() const { return static_cast<int>(workers_.size()) + 1; }

    void run_round(size_t tasks) {
        if (workers_.empty() || tasks < 2) {
            for (size_t i = 0; i < tasks; ++i) work_(0, i);
            return;
        }
        if (tasks > kIndexMask) throw std::length_error("planning round with too many tasks");
        failure_ = nullptr;
        done_.store(0);
        round_id_ = (round_id_ + 1) & kRoundMask;
        slot_.store((round_id_ << 40) | (uint64_t(tasks) << 20));
        round_.fetch_add(1);
        if (sleeping_.load() > 0) {
            std::lock_guard<std::mutex> lock(mutex_);
            wake_.notify_all();
        }
        take_tasks(0);
        while (done_.load() < tasks) pause();
        if (failure_) std::rethrow_exception(failure_);
    }

private:
    std::function<void(int, size_t)> work_;
    std::vector<std::thread> workers_;
    std::atomic<uint64_t> round_{0};  // wakes the workers
    // The round's tasks: (round id << 40) | (number of tasks << 20) | next task. A task is
    // taken by a compare-and-swap of the whole word, so a thread that comes late from an
    // earlier round can never take (or count) a task of a later one. (A shared counter
    // reset per round let a late fetch_add run a task of the next round twice, once
    // with the previous round's task count.)
    static constexpr uint64_t kIndexMask = (uint64_t(1) << 20) - 1, kRoundMask = (uint64_t(1) << 24) - 1;
    std::atomic<uint64_t> slot_{0};
    uint64_t round_id_ = 0;
    std::atomic<size_t> done_{0};
    std::atomic<int> sleeping_{0};
    std::mutex mutex_;  // guards stop_ and the sleeping side of round_
    std::condition_variable wake_;
    bool stop_ = false;
    std::mutex failure_mutex_;
    std::exception_ptr failure_;

    static void pause() {
#if defined(__x86_64__) || defined(__i386__)
        __builtin_ia32_pause();
#else
        std::this_thread::yield();
#endif
    }
    void take_tasks(int thread) {
        uint64_t v = slot_.load();
        while (true) {
            const size_t i = v & kIndexMask, tasks = (v >> 20) & kIndexMask;
            if (i >= tasks) return;
            if (!slot_.compare_exchange_weak(v, v + 1)) continue;  // v is reloaded
            try {
                work_(thread, i);
            } catch (...) {
                std::lock_guard<std::mutex> lock(failure_mutex_);
                if (!failure_) failure_ = std::current_exception();
            }
            done_.fetch_add(1);
            v = slot_.load();
        }
    }
    void serve(int thread) {
        uint64_t seen = 0;
        while (true) {
            const auto spin_until = std::chrono::steady_clock::now() + std::chrono::microseconds(200);
            bool spinning = true;
            for (int k = 0; round_.load() == seen; ++k) {
                if ((k & 255) == 255 && std::chrono::steady_clock::now() > spin_until) {
                    spinning = false;
                    break;
                }
                pause();
            }
            if (!spinning) {
                std::unique_lock<std::mutex> lock(mutex_);
                sleeping_.fetch_add(1);
                wake_.wait(lock, [&] { return stop_ || round_.load() != seen; });
                sleeping_.fetch_sub(1);
                if (stop_) return;
            }
            seen = round_.load();
            take_tasks(thread);
        }
    }
};

// A complete full plan of a removal that waits in the queue (its cost after validation
// was above the next entry), reused when the entry comes back unchanged.
struct WaitingPlan {
    uint32_t stamp = 0;      // stamp of the vertex when planned
    int64_t made_at = -1;    // number of removals committed when the intersections were tested, or -1
    bool intersects = false; // intersects_rest, valid while no removal was committed since
    RemovalPlan plan;
};

class Simplifier {
public:
    Simplifier(const Surface& original, const SimplifyOptions& options, const Context& context, int threads)
        : original_(original),
          options_(options),
          context_(context),
          mesh_(original),
          diagonal_(bounding_box_diagonal(original)),
          grid_(1.0) {
        mesh_.mark_feature_edges(options.feature_angle_degrees);
        mesh_.mark_corners(options.feature_angle_degrees, options.corner_crease_length * diagonal_,
                           options.keep_corners);
        sign_.resize(original.triangles.size());
        for (int32_t t = 0; t < original.num_triangles(); ++t) sign_[t] = mesh_.flipped_initially(t) ? -1 : 1;
        // Only with a limit: the angle costs about 5% of the planning time.
        if (options.max_normal_deviation_degrees < 180.0 || options.distortion_weight > 0) oriented_normals_.resize(original.triangles.size());
        for (int32_t t = 0; t < int32_t(oriented_normals_.size()); ++t) {
            const Tri& c = original.triangles[t];
            oriented_normals_[t] = double(sign_[t]) * triangle_normal(original.vertices[c[0]], original.vertices[c[1]],
                                                                       original.vertices[c[2]]);
        }
        embedding_.init_identity(original, mesh_.triangle_capacity());
        remover_ = std::make_unique<VertexRemover>(mesh_, embedding_, sign_, oriented_normals_);
        second_remover_ = std::make_unique<VertexRemover>(mesh_, embedding_, sign_, oriented_normals_);
        for (int i = 1; i < threads; ++i) removers_.push_back(std::make_unique<VertexRemover>(mesh_, embedding_, sign_, oriented_normals_));
        candidates_.resize(threads);
        stamp_.assign(original.vertices.size(), 0);
        rebuild_grid();
    }

    SimplifyResult run(Parametrization& out);

private:
    const Surface& original_;
    const SimplifyOptions& options_;
    const Context& context_;
    CoarseMesh mesh_;
    Embedding embedding_;
    std::vector<int8_t> sign_;
    std::vector<Vec3> oriented_normals_;  // unit normals of the original triangles, coarse orientation
    std::unique_ptr<VertexRemover> remover_;
    std::unique_ptr<VertexRemover> second_remover_;  // of the second removal of an iteration
    RemovalPlan second_plan_;
    double diagonal_;
    TriangleGrid grid_;
    int32_t grid_built_at_ = 0;  // alive triangles when the grid was last rebuilt
    std::vector<uint32_t> stamp_;
    std::priority_queue<QueueEntry, std::vector<QueueEntry>, std::greater<QueueEntry>> queue_;
    std::vector<std::string> last_reason_;
    RemovalPlan plan_;
    std::vector<std::unique_ptr<VertexRemover>> removers_;  // of threads 1.. (thread 0 uses remover_)
    std::vector<std::vector<TriangleGrid::Entry>> candidates_;  // per thread, for intersects_rest
    int32_t first_new_ = 0;
    std::atomic<int64_t> plans_[2] = {{0}, {0}};
    int64_t commits_ = 0;
    int64_t reused_plans_ = 0;

    VertexRemover& remover(int thread) { return thread == 0 ? *remover_ : *removers_[thread - 1]; }
    void rebuild_grid();
    bool intersects_rest(const RemovalPlan& plan, std::vector<TriangleGrid::Entry>& candidates) const;
    bool meet_improperly(const Tri& a, const Tri& b) const;
    // Whether a new triangle of `plan` meets one of `others` other than in what they share.
    bool meets_new_triangles(const RemovalPlan& plan, const std::vector<Tri>& others) const;
    // Queue key of v from a cheap plan (a lower bound of the full plan's cost), +infinity
    // if it cannot be removed now (reason recorded). On the remover of `thread`.
    double rank(int32_t v, RemovalPlan& plan, int thread);
    // `estimate`: the cost a full plan is ranked by first, from its estimated_deviation and
    // without the normal limit (known only after validation); the same for a plan whose
    // validation is pending and for a complete one.
    double judge(int32_t v, const RemovalPlan& plan, bool estimate = false);
    bool admissible_globally(int32_t v, const RemovalPlan& plan);
    // A full plan made earlier is still exact if its star is unchanged (stamp), no
    // edited path changed elsewhere, and its new edges still do not exist.
    bool still_current(const RemovalPlan& plan) const;
    // Full plans of entries pushed back because their real cost was higher than the
    // estimate; reused when the entry comes back with the same stamp.
    std::unordered_map<int32_t, WaitingPlan> full_plans_;
    void self_check(int32_t removed_vertex, const std::vector<int32_t>& link, int64_t step);
};

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
                                 std::to_string(removed_vertex) + ": triangle " + std::to_string(t) + " (" +
                                 std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) +
                                 ", " + std::to_string(graph.nodes.size()) + " nodes, " +
                                 std::to_string(graph.segments.size()) + " segments" +
                                 (t >= first_new_ ? ", new" : ", old") + "): " + why);
        }
    }
}

void Simplifier::rebuild_grid() {
    // Cell size: twice the mean bounding-box extent of the current triangles.
    const auto& x = original_.vertices;
    double extent = 0.0;
    int64_t count = 0;
    for (int32_t t = 0; t < mesh_.triangle_capacity(); ++t) {
        if (!mesh_.alive(t)) continue;
        const Tri& c = mesh_.triangle(t);
        for (int k = 0; k < 3; ++k) extent += distance(x[c[k]], x[c[(k + 1) % 3]]);
        count += 3;
    }
    const double cell = count ? 2.0 * extent / double(count) : 1.0;
    grid_ = TriangleGrid(cell > 0 ? cell : 1.0);
    for (int32_t t = 0; t < mesh_.triangle_capacity(); ++t) {
        if (!mesh_.alive(t)) continue;
        const Tri& c = mesh_.triangle(t);
        grid_.insert(t, x[c[0]], x[c[1]], x[c[2]]);
    }
    grid_built_at_ = mesh_.num_alive_triangles();
}

// Whether coarse triangles a and b (given by vertices) meet other than in what they share.
bool Simplifier::meet_improperly(const Tri& a, const Tri& b) const {
    const auto& x = original_.vertices;
    const Vec3 pa[3] = {x[a[0]], x[a[1]], x[a[2]]};
    int shared[3];
    int count = 0;
    for (int k = 0; k < 3; ++k) {
        shared[k] = -1;
        for (int j = 0; j < 3; ++j)
            if (a[k] == b[j]) {
                shared[k] = j;
                ++count;
            }
    }
    const Vec3 pb[3] = {x[b[0]], x[b[1]], x[b[2]]};
    // Fast exact rejection: the unshared corners of one triangle strictly on one
    // side of the other's plane means they meet at most in what they share.
    if (count < 2) {
        auto one_side = [&](const Vec3 p[3], const Vec3 q[3], const Tri& tq, const Tri& tp) {
            int side = 0;
            for (int j = 0; j < 3; ++j) {
                if (tq[j] == tp[0] || tq[j] == tp[1] || tq[j] == tp[2]) continue;
                const int o = orient3d(p[0], p[1], p[2], q[j]);
                if (o == 0 || (side != 0 && o != side)) return false;
                side = o;
            }
            return side != 0;
        };
        if (one_side(pa, pb, b, a) || one_side(pb, pa, a, b)) return false;
    }
    return triangles_intersect_improperly(pa, pb, shared);
}

bool Simplifier::meets_new_triangles(const RemovalPlan& plan, const std::vector<Tri>& others) const {
    for (const Tri& a : plan.new_triangles)
        for (const Tri& b : others)
            if (meet_improperly(a, b)) return true;
    return false;
}

bool Simplifier::intersects_rest(const RemovalPlan& plan, std::vector<TriangleGrid::Entry>& candidates) const {
    const auto& x = original_.vertices;
    const auto& new_triangles = plan.new_triangles;
    const auto& removed = plan.removed_triangles;
    const size_t count_new = new_triangles.size();
    // Boxes of the new triangles, and the box around all of them: one grid query for
    // the whole star (the new triangles overlap the same few cells) instead of one per
    // new triangle. Every triangle whose box meets a new triangle's box is in a cell
    // that box meets, so the pairs tested below are exactly those of a query per
    // triangle; the answer does not depend on the order of the tests.
    static thread_local std::vector<std::array<Vec3, 2>> boxes;
    boxes.resize(count_new);
    Vec3 all_lo{}, all_hi{};
    for (size_t i = 0; i < count_new; ++i) {
        const Tri& a = new_triangles[i];
        Vec3& lo = boxes[i][0];
        Vec3& hi = boxes[i][1];
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min({x[a[0]][k], x[a[1]][k], x[a[2]][k]});
            hi[k] = std::max({x[a[0]][k], x[a[1]][k], x[a[2]][k]});
            all_lo[k] = i == 0 ? lo[k] : std::min(all_lo[k], lo[k]);
            all_hi[k] = i == 0 ? hi[k] : std::max(all_hi[k], hi[k]);
        }
    }
    if (count_new == 0) return false;
    // Only triangles whose box meets the box of all new triangles (the grid tests the
    // boxes it stores), then the cheap box rejection per new triangle before the exact test.
    grid_.query_boxes(all_lo, all_hi, candidates);
    for (const TriangleGrid::Entry& candidate : candidates) {
        const int32_t t = candidate.id;
        if (!mesh_.alive(t)) continue;
        if (std::find(removed.begin(), removed.end(), t) != removed.end()) continue;
        const auto& blo = candidate.lo;  // float, rounded outwards: only a filter
        const auto& bhi = candidate.hi;
        for (size_t i = 0; i < count_new; ++i) {
            bool apart = false;
            for (int k = 0; k < 3 && !apart; ++k) apart = bhi[k] < boxes[i][0][k] || blo[k] > boxes[i][1][k];
            if (!apart && meet_improperly(new_triangles[i], mesh_.triangle(t))) return true;
        }
    }
    for (size_t i = 0; i < count_new; ++i)
        for (size_t j = 0; j < i; ++j)
            if (meet_improperly(new_triangles[i], new_triangles[j])) return true;
    return false;
}

double Simplifier::rank(int32_t v, RemovalPlan& plan, int thread) {
    remover(thread).plan(v, false, plan);
    plans_[0].fetch_add(1, std::memory_order_relaxed);
    return judge(v, plan);
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
    if (options_.prevent_intersections && intersects_rest(plan, candidates_[0])) {
        last_reason_[v] = "would create a self-intersection";
        return false;
    }
    return true;
}

double Simplifier::judge(int32_t v, const RemovalPlan& plan, bool estimate) {
    if (!plan.valid && !(estimate && plan.estimated)) {
        last_reason_[v] = plan.reason;
        return std::numeric_limits<double>::infinity();
    }
    const double error = (estimate ? plan.estimated_deviation : plan.max_deviation) / diagonal_;
    if (error > options_.max_error) {
        last_reason_[v] = "geometric error limit (--max-error)";
        return std::numeric_limits<double>::infinity();
    }
    if (plan.worst_new_aspect > std::max(options_.max_aspect_ratio, plan.worst_old_aspect)) {
        last_reason_[v] = "triangle shape limit (--max-aspect)";
        return std::numeric_limits<double>::infinity();
    }
    if (plan.longest_new_edge > options_.max_edge_length * diagonal_) {
        last_reason_[v] = "edge length limit (--max-edge-length)";
        return std::numeric_limits<double>::infinity();
    }
    if (!estimate && plan.max_normal_deviation > options_.max_normal_deviation_degrees) {
        last_reason_[v] = "normal deviation limit (--max-normal-deviation)";
        return std::numeric_limits<double>::infinity();
    }
    last_reason_[v].clear();
    const double aspect_term = std::log2(std::max(plan.worst_new_aspect, 2.0) / 2.0) -
                               0.5 * std::log2(std::max(plan.worst_old_aspect, 2.0) / 2.0);
    // Costs are compared after rounding to 1e-10 (relative to the diagonal), so that
    // rounding noise, e.g. between a model and its scaled copy, does not reorder
    // removals; exact ties go to the smaller vertex id.
    const double distortion = distortion_cost(plan.max_normal_deviation, options_.distortion_weight, options_.fold_limit_degrees);
    return std::round((error + options_.aspect_weight * 1e-3 * aspect_term + distortion) * 1e10) * 1e-10;
}


SimplifyResult Simplifier::run(Parametrization& out) {
    const auto start = std::chrono::steady_clock::now();
    SimplifyResult result;
    result.input_vertices = original_.num_vertices();
    result.input_triangles = original_.num_triangles();
    int64_t target = 0;
    if (options_.target_vertices > 0) target = options_.target_vertices;
    if (options_.target_ratio > 0) {
        const int64_t by_ratio = static_cast<int64_t>(std::ceil(options_.target_ratio * double(result.input_vertices)));
        target = std::max(target, by_ratio);
    }
    last_reason_.assign(original_.vertices.size(), std::string());
    result.crease_junctions = mesh_.corner_count(CoarseMesh::Corner::Junction);
    result.crease_cone_ends = mesh_.corner_count(CoarseMesh::Corner::ConeEnd);
    result.line_feature_vertices = mesh_.hard_feature_vertices();
    result.corners_kept = options_.keep_corners;
    if (options_.record_steps) result.steps.emplace();  // record of the removals (bpm-check --replay)

    const int32_t nv = original_.num_vertices();
    // Every task below reads the state and writes only its own outputs, so the tasks of
    // a round are shared by threads; the state changes only between rounds. Which tasks
    // a round has never depends on the thread count, so neither does the output.
    enum class Job : uint8_t {
        Rank,       // cheap plan of `vertex`, cost into `cost`
        PlanTop,    // full plan of candidate `slot` (VertexRemover::plan_deferred)
        Finish,     // part `vertex` of the validation of candidate `slot`'s plan (VertexRemover::finish_part)
        Intersect,  // intersects_rest for candidate `slot` (whose triangles the Finish parts do not touch)
        Export,     // export_task(vertex), at the end
        Grid,       // grid_removed out of the grid, the triangles from `vertex` on into it
    };
    struct Task {
        int32_t vertex = -1;
        Job job = Job::Rank;
        double cost = 0.0;
        int8_t slot = 0;  // candidate of PlanTop, Finish and Intersect
    };
    // The (at most two) removals tried in one iteration.
    struct Candidate {
        QueueEntry entry{};
        RemovalPlan* plan;
        VertexRemover* remover;     // of the plan (a pending plan's validation is in it)
        int known_intersection = -1;  // -1 unknown, else whether it intersects the rest
        bool intersects = false;    // result of Job::Intersect
        bool live = false;          // still to be committed in this iteration
    };
    Candidate candidates[2] = {{{}, &plan_, remover_.get()}, {{}, &second_plan_, second_remover_.get()}};
    std::vector<Task> tasks;
    std::vector<RemovalPlan> cheap_plans(removers_.size() + 1);
    std::function<void(size_t)> export_task;  // chunk `vertex` of the export (set there)
    const int finish_parts = std::min<int>(VertexRemover::kMaxFinishParts, int(removers_.size()) + 1);
    std::vector<std::pair<int32_t, Tri>> grid_removed;  // of the last commit, for Job::Grid
    PlanningPool pool(static_cast<int>(removers_.size()) + 1, [&](int thread, size_t i) {
        Task& task = tasks[i];
        switch (task.job) {
            case Job::Rank: task.cost = rank(task.vertex, cheap_plans[thread], thread); break;
            case Job::PlanTop: candidates[task.slot].remover->plan_deferred(task.vertex, *candidates[task.slot].plan); break;
            case Job::Finish: candidates[task.slot].remover->finish_part(task.vertex, finish_parts); break;
            case Job::Intersect: {
                Candidate& c = candidates[task.slot];
                c.intersects = intersects_rest(*c.plan, candidates_[thread]);
                break;
            }
            case Job::Export: export_task(size_t(task.vertex)); break;
            case Job::Grid: {
                const auto& x = original_.vertices;
                for (const auto& [t, c] : grid_removed) grid_.remove(t, x[c[0]], x[c[1]], x[c[2]]);
                for (int32_t t = task.vertex; t < mesh_.triangle_capacity(); ++t) {
                    const Tri& c = mesh_.triangle(t);
                    grid_.insert(t, x[c[0]], x[c[1]], x[c[2]]);
                }
                break;
            }
        }
    });

    // First ranking of all vertices, in chunks.
    {
        // 256 vertices per task; above 2^27 vertices more, so that a round has at most
        // 2^19 tasks (the pool takes fewer than 2^20). The costs do not depend on it.
        const int32_t kChunk = std::max<int32_t>(256, int32_t((int64_t(nv) + (1 << 19) - 1) >> 19));
        tasks.clear();
        for (int64_t v = 0; v < nv; v += kChunk) tasks.push_back(Task{int32_t(v)});
        std::vector<double> costs(nv, std::numeric_limits<double>::infinity());
        std::atomic<int32_t> ranked{0};
        PlanningPool ranking(pool.threads(), [&](int thread, size_t i) {
            const int32_t first = tasks[i].vertex, last = int32_t(std::min<int64_t>(nv, int64_t(first) + kChunk));
            for (int32_t v = first; v < last; ++v) {
                remover(thread).plan(v, false, cheap_plans[thread]);
                costs[v] = judge(v, cheap_plans[thread]);
            }
            const int32_t done = ranked.fetch_add(last - first) + (last - first);
            if (thread == 0) context_.report(0.2 * done / std::max(nv, 1), "evaluating vertices");
        });
        ranking.run_round(tasks.size());
        plans_[0] += nv;
        for (int32_t v = 0; v < nv; ++v) {
            ++stamp_[v];
            if (std::isfinite(costs[v])) queue_.push({costs[v], v, stamp_[v]});
        }
    }
    const int64_t start_vertices = mesh_.num_vertices_alive();
    std::vector<int32_t> affected;
    std::string stop = "no vertex can be removed any more";
    double error_so_far = 0.0;  // largest error of a committed removal (of the diagonal), for progress
    int64_t next_report = 256;  // removals
    auto current = [&](const QueueEntry& e) { return e.stamp == stamp_[e.vertex] && mesh_.vertex_alive(e.vertex); };
    std::vector<int32_t> star_a;       // the link of the first candidate, and itself
    std::vector<QueueEntry> skipped;   // entries passed over when looking for a second candidate
    while (true) {
        if (mesh_.num_vertices_alive() <= target) {
            stop = "target reached";
            result.target_reached = true;
            break;
        }
        while (!queue_.empty() && !current(queue_.top())) queue_.pop();
        if (queue_.empty()) break;
        // Up to two removals per iteration: the queue's top, and the best entry among the
        // next few that is not in the top's star, so that its star shares no triangle
        // with the top's. Their plans, validations and re-rankings share the rounds (the
        // second thread otherwise idles while the top is planned). The second is
        // committed after the first only if its plan is still valid then (its star's
        // triangles are still there, no path it edits changed, its new edges and
        // triangles are still new: what a reused waiting plan is checked for), else it
        // goes back into the queue as it was; and it is refused if its new triangles
        // meet the first's. (The plan is valid, not necessarily the one a planner would
        // choose after the first removal: an ear the first removal blocked could have
        // changed a near-tie, or let a crease be followed where the plan ends it.)
        int count = 0;
        candidates[count++].entry = queue_.top();
        queue_.pop();
        if (options_.batch_removals) {
            star_a.assign(1, candidates[0].entry.vertex);
            for (int32_t t : mesh_.triangles_of(candidates[0].entry.vertex))
                for (int32_t u : mesh_.triangle(t)) star_a.push_back(u);
            skipped.clear();
            while (!queue_.empty() && skipped.size() < 3) {
                const QueueEntry e = queue_.top();
                queue_.pop();
                if (!current(e)) continue;
                if (std::find(star_a.begin(), star_a.end(), e.vertex) == star_a.end()) {
                    candidates[count++].entry = e;
                    break;
                }
                skipped.push_back(e);
            }
            for (const QueueEntry& e : skipped) queue_.push(e);
        }
        // The neighbourhood of a candidate is unchanged since its ranking (stamp), but
        // other removals may have changed things near it: plan again, or reuse a full plan
        // that is provably still the same.
        tasks.clear();
        for (int k = 0; k < count; ++k) {
            Candidate& c = candidates[k];
            c.known_intersection = -1;
            c.live = true;
            const int32_t v = c.entry.vertex;
            auto cached = full_plans_.find(v);
            if (cached != full_plans_.end() && cached->second.stamp == c.entry.stamp && still_current(cached->second.plan)) {
                WaitingPlan& wp = cached->second;
                if (wp.made_at == commits_) c.known_intersection = wp.intersects;
                *c.plan = std::move(wp.plan);
                full_plans_.erase(cached);
                ++reused_plans_;
            } else {
                tasks.push_back(Task{v, Job::PlanTop, 0.0, int8_t(k)});
            }
        }
        pool.run_round(tasks.size());
        plans_[1].fetch_add(int64_t(tasks.size()), std::memory_order_relaxed);
        // A full plan is ranked by its estimate first (the cost before validation): if
        // that is above the next entry by more than the queue tolerance, the removal
        // waits, unvalidated (most such plans never come back unchanged).
        auto waits = [&](int k, double c) {
            double next = std::numeric_limits<double>::infinity();
            if (!queue_.empty()) next = queue_.top().cost;
            for (int j = k + 1; j < count; ++j)
                if (candidates[j].live) next = std::min(next, candidates[j].entry.cost);
            if (!(c > candidates[k].entry.cost + 1e-15) || !std::isfinite(next)) return false;
            return c > next + options_.queue_tolerance * std::abs(next);
        };
        for (int k = 0; k < count; ++k) {
            Candidate& c = candidates[k];
            const int32_t v = c.entry.vertex;
            const double estimate = judge(v, *c.plan, true);
            if (!std::isfinite(estimate)) {
                c.live = false;
            } else if (waits(k, estimate)) {
                queue_.push({estimate, v, stamp_[v]});
                c.live = false;
            }
        }
        // The validations, and in the same round the intersection tests of the new
        // triangles against the rest of the surface; parts 0 first (the other parts wait
        // for their preparation).
        tasks.clear();
        for (int k = 0; k < count; ++k)
            if (candidates[k].live && candidates[k].plan->pending) tasks.push_back(Task{0, Job::Finish, 0.0, int8_t(k)});
        for (int k = 0; k < count; ++k)
            if (candidates[k].live && options_.prevent_intersections && candidates[k].known_intersection < 0)
                tasks.push_back(Task{candidates[k].entry.vertex, Job::Intersect, 0.0, int8_t(k)});
        for (int part = 1; part < finish_parts; ++part)
            for (int k = 0; k < count; ++k)
                if (candidates[k].live && candidates[k].plan->pending) tasks.push_back(Task{part, Job::Finish, 0.0, int8_t(k)});
        pool.run_round(tasks.size());
        for (const Task& task : tasks) {
            Candidate& c = candidates[task.slot];
            if (task.job == Job::Intersect) c.known_intersection = c.intersects;
            if (task.job == Job::Finish && task.vertex == 0) c.remover->finish_parts_done(*c.plan, finish_parts);
        }
        const int64_t commits_before = commits_;
        const int32_t first_new = mesh_.triangle_capacity();
        affected.clear();
        grid_removed.clear();
        int committed = 0;  // removals in this step
        for (int k = 0; k < count; ++k) {
            Candidate& c = candidates[k];
            if (!c.live) continue;
            const int32_t v = c.entry.vertex;
            RemovalPlan& plan = *c.plan;
            const bool after_first = k > 0 && commits_ > commits_before;
            // After the first removal of this step: is this plan still valid? (Its
            // intersection test saw the first one's old triangles, which may be all it
            // met: then it is tested again later.)
            if (after_first &&
                (mesh_.num_vertices_alive() <= target || !still_current(plan) || c.known_intersection == 1)) {
                queue_.push(c.entry);
                continue;
            }
            // Floater's map or the normal limit may still raise the cost; then it waits
            // with its complete plan.
            const double cost = judge(v, plan);
            if (!std::isfinite(cost)) continue;
            if (waits(k, cost)) {
                WaitingPlan& wp = full_plans_[v];
                wp.stamp = stamp_[v];
                wp.made_at = c.known_intersection < 0 ? -1 : commits_before;
                wp.intersects = c.known_intersection == 1;
                wp.plan = std::move(plan);
                queue_.push({cost, v, stamp_[v]});
                continue;
            }
            if (after_first) {
                if (options_.prevent_intersections && meets_new_triangles(plan, candidates[0].plan->new_triangles)) {
                    last_reason_[v] = "would create a self-intersection";
                    continue;
                }
            } else if (c.known_intersection >= 0 ? c.known_intersection == 1 : !admissible_globally(v, plan)) {
                if (c.known_intersection == 1) last_reason_[v] = "would create a self-intersection";
                continue;
            }
            if (options_.trace_removals) {
                char line[200];
                std::snprintf(line, sizeof line,
                              "remove vertex %d: cost %.10g, error %.6g, worst aspect %.4g (was %.4g), normal deviation %.3g deg",
                              v, cost, plan.max_deviation / diagonal_, plan.worst_new_aspect, plan.worst_old_aspect,
                              plan.max_normal_deviation);
                context_.debug(line);
            }
            const size_t affected_begin = affected.size();
            for (int32_t t : plan.removed_triangles)
                for (int32_t u : mesh_.triangle(t))
                    if (u != v) affected.push_back(u);
            // The grid follows in the round below (its planning does not read the grid).
            for (int32_t t : plan.removed_triangles) grid_removed.push_back({t, mesh_.triangle(t)});
            first_new_ = mesh_.triangle_capacity();
            commit_removal(mesh_, embedding_, plan);
            if (result.steps) result.steps->append(v, plan.new_triangles, plan.new_patches);
            ++commits_;
            ++committed;
            error_so_far = std::max(error_so_far, plan.max_deviation / diagonal_);
            ++stamp_[v];
            full_plans_.erase(v);
            ++result.removed;
            if (plan.used_floater) ++result.shape_preserving_repairs;
            if (options_.self_check)
                self_check(v, std::vector<int32_t>(affected.begin() + affected_begin, affected.end()), result.removed);
        }
        if (committed == 0) continue;
        if (committed == 2) ++result.paired_steps;
        // Neither removed vertex was in the other's star: `affected` holds live vertices only.
        std::sort(affected.begin(), affected.end());
        affected.erase(std::unique(affected.begin(), affected.end()), affected.end());

        // The round: new costs of the vertices around the removals (their stars changed),
        // and the grid update.
        tasks.assign(1, Task{first_new, Job::Grid});
        for (int32_t u : affected) {
            ++stamp_[u];
            full_plans_.erase(u);
            tasks.push_back(Task{u});
        }
        pool.run_round(tasks.size());
        if (mesh_.num_alive_triangles() * 4 < grid_built_at_) rebuild_grid();
        for (const Task& task : tasks)
            if (task.job == Job::Rank && std::isfinite(task.cost)) queue_.push({task.cost, task.vertex, stamp_[task.vertex]});
        if (result.removed >= next_report) {
            next_report = result.removed + 256;
            const double done = start_vertices > target
                                    ? double(start_vertices - mesh_.num_vertices_alive()) / double(start_vertices - target)
                                    : 1.0;
            char line[128];
            std::snprintf(line, sizeof line, "simplifying: %d vertices left, error %.2g of diagonal",
                          mesh_.num_vertices_alive(), error_so_far);
            context_.report(0.2 + 0.75 * std::min(done, 1.0), line);
        }
    }
    if (mesh_.num_vertices_alive() <= target) {
        result.target_reached = true;
        stop = "target reached";
    } else if (target == 0 && std::isfinite(options_.max_error)) {
        // Only an error limit was asked for: stopping at it is the goal.
        result.target_reached = true;
        stop = "every further removal would exceed the error limit or another limit";
    }
    if (!result.target_reached && target > 0 && target < result.kept_feature_vertices()) {
        // Say what the target runs into, not only that nothing could be removed.
        stop = "the target of " + std::to_string(target) + " vertices is below the " +
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
    if (!result.target_reached) {
        for (int32_t v = 0; v < nv; ++v) {
            if (!mesh_.vertex_alive(v)) continue;
            std::string why = last_reason_[v];
            if (why.empty()) {
                std::string reason;
                remover_->plan(v, true, plan_);
                why = plan_.valid ? "not reached" : plan_.reason;
            }
            ++result.blocked[why];
            if (options_.trace_removals) context_.debug("vertex " + std::to_string(v) + " kept: " + why);
        }
    }

    // Export.
    context_.report(0.95, "writing the parametrization");
    out = Parametrization();
    out.original = original_;
    out.coarse = mesh_.to_surface(out.coarse_vertex_origin);
    // The parametrization of every coarse triangle, in chunks of consecutive triangles
    // that the threads share; the chunks are concatenated in order.
    std::vector<int32_t> alive;
    for (int32_t t = 0; t < mesh_.triangle_capacity(); ++t)
        if (mesh_.alive(t)) alive.push_back(t);
    struct ExportChunk {
        size_t begin = 0, end = 0;  // into `alive`
        Parametrization part;       // its node_* and piece* arrays, offsets from 0
        double max_deviation = 0.0;
        size_t failed = SIZE_MAX;   // index into `alive` of the first invalid triangle
        std::string why;
    };
    // Likewise at most 2^19 chunks (the output is concatenated in order either way).
    const size_t kExportChunk = std::max<size_t>(512, (alive.size() + (size_t(1) << 19) - 1) >> 19);
    std::vector<ExportChunk> chunks((alive.size() + kExportChunk - 1) / kExportChunk);
    for (size_t c = 0; c < chunks.size(); ++c) {
        chunks[c].begin = c * kExportChunk;
        chunks[c].end = std::min(alive.size(), (c + 1) * kExportChunk);
    }
    auto export_chunk = [&](ExportChunk& chunk) {
        TriangleGraph graph;
        std::vector<OverlayFace> faces;
        std::vector<Tri> pieces;
        std::vector<int32_t> piece_triangle;
        const auto& x = original_.vertices;
        Parametrization& part = chunk.part;
        part.node_offsets.push_back(0);
        part.piece_offsets.push_back(0);
        for (size_t i = chunk.begin; i < chunk.end; ++i) {
            const int32_t t = alive[i];
            build_triangle_graph(mesh_, embedding_, t, graph);
            if (!compute_faces(graph, embedding_, sign_, faces, &chunk.why) ||
                !triangulate_faces(graph, embedding_, sign_, faces, pieces, piece_triangle, &chunk.why)) {
                chunk.failed = i;
                return;
            }
            const Tri& c = mesh_.triangle(t);
            for (const GraphNode& g : graph.nodes) {
                part.node_barycentric.push_back(g.bary);
                const Vec3 image = node_image(g, embedding_);
                part.node_image.push_back(image);
                chunk.max_deviation =
                    std::max(chunk.max_deviation, distance(image, barycentric_point(x[c[0]], x[c[1]], x[c[2]], g.bary)));
                part.node_kind.push_back(g.kind);
                part.node_original_vertex.push_back(g.kind == NodeKind::EdgeCrossing ? -1 : g.vertex);
                if (g.kind == NodeKind::EdgeCrossing) {
                    part.node_original_edge.push_back(embedding_.edges[g.edge]);
                    part.node_edge_parameter.push_back(g.sigma);
                } else {
                    part.node_original_edge.push_back({-1, -1});
                    part.node_edge_parameter.push_back(std::nan(""));
                }
            }
            part.pieces.insert(part.pieces.end(), pieces.begin(), pieces.end());
            part.piece_original_triangle.insert(part.piece_original_triangle.end(), piece_triangle.begin(),
                                                piece_triangle.end());
            part.node_offsets.push_back(static_cast<int64_t>(part.node_kind.size()));
            part.piece_offsets.push_back(static_cast<int64_t>(part.pieces.size()));
        }
    };
    tasks.clear();
    for (size_t c = 0; c < chunks.size(); ++c) tasks.push_back(Task{int32_t(c), Job::Export});
    export_task = [&](size_t c) { export_chunk(chunks[c]); };
    pool.run_round(tasks.size());
    double max_deviation = 0.0;
    out.node_offsets.push_back(0);
    out.piece_offsets.push_back(0);
    for (ExportChunk& chunk : chunks) {
        if (chunk.failed != SIZE_MAX)
            throw AlgorithmError("internal error: coarse triangle " + std::to_string(chunk.failed) +
                                 " has an invalid parametrization (" + chunk.why + ")");
        const Parametrization& part = chunk.part;
        const int64_t node_base = out.node_offsets.back(), piece_base = out.piece_offsets.back();
        auto append = [](auto& to, const auto& from) { to.insert(to.end(), from.begin(), from.end()); };
        append(out.node_barycentric, part.node_barycentric);
        append(out.node_image, part.node_image);
        append(out.node_kind, part.node_kind);
        append(out.node_original_vertex, part.node_original_vertex);
        append(out.node_original_edge, part.node_original_edge);
        append(out.node_edge_parameter, part.node_edge_parameter);
        append(out.pieces, part.pieces);
        append(out.piece_original_triangle, part.piece_original_triangle);
        for (size_t k = 1; k < part.node_offsets.size(); ++k) {
            out.node_offsets.push_back(node_base + part.node_offsets[k]);
            out.piece_offsets.push_back(piece_base + part.piece_offsets[k]);
        }
        max_deviation = std::max(max_deviation, chunk.max_deviation);
        chunk.part = Parametrization();
    }
    result.output_vertices = out.coarse.num_vertices();
    result.output_triangles = out.coarse.num_triangles();
    result.max_error = diagonal_ > 0 ? max_deviation / diagonal_ : 0.0;
    for (const Tri& t : out.coarse.triangles)
        result.worst_aspect_ratio = std::max(
            result.worst_aspect_ratio,
            aspect_ratio(out.coarse.vertices[t[0]], out.coarse.vertices[t[1]], out.coarse.vertices[t[2]]));
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    context_.debug("plans: " + std::to_string(plans_[0].load()) + " cheap, " + std::to_string(plans_[1].load()) +
                   " full (" + std::to_string(reused_plans_) + " reused); " + std::to_string(result.paired_steps) +
                   " steps removed two vertices; " +
                   std::to_string(result.shape_preserving_repairs) + " removals re-embedded with Floater's map");
    context_.report(1.0, "done");
    return result;
}

}  // namespace

SimplifyResult simplify(const Surface& original, const SimplifyOptions& options, const Context& context,
                        Parametrization& out) {
    if (options.target_ratio < 0 || options.target_ratio > 1)
        throw OptionError("--ratio must be between 0 and 1, got " + std::to_string(options.target_ratio));
    if (options.target_vertices < 0) throw OptionError("--vertices must not be negative");
    if (!(options.max_error >= 0)) throw OptionError("--max-error must not be negative");
    if (!(options.max_edge_length > 0)) throw OptionError("--max-edge-length must be positive");
    if (!(options.max_aspect_ratio >= 2)) throw OptionError("--max-aspect must be at least 2 (equilateral)");
    if (!(options.max_normal_deviation_degrees >= 0 && options.max_normal_deviation_degrees <= 180))
        throw OptionError("--max-normal-deviation must be between 0 and 180 degrees");
    if (!(options.distortion_weight >= 0) || !(options.fold_limit_degrees >= 0 && options.fold_limit_degrees <= 180))
        throw OptionError("--distortion-weight must be >= 0 and --fold-limit between 0 and 180 degrees");
    if (!(options.queue_tolerance >= 0 && options.queue_tolerance <= 10))
        throw OptionError("--queue-tolerance must be between 0 and 10");
    if (!(options.corner_crease_length >= 0 && options.corner_crease_length <= 1))
        throw OptionError("the corner crease length must be between 0 and 1 (of the diagonal)");
    if (!(options.feature_angle_degrees >= 0 && options.feature_angle_degrees <= 180))
        throw OptionError("--feature-angle must be between 0 and 180 degrees");
    const int threads = planning_threads(options);
    context.debug(std::to_string(threads) + (threads == 1 ? " thread" : " threads") +
                  (options.threads == 0 ? " (automatic: --threads 0)" : ""));
    std::unique_ptr<Simplifier> simplifier;
    if (options.reject_self_intersecting_input) {
        context.report(0.0, "checking the input for self-intersections");
        CheckOptions check_options;
        check_options.max_problems = 1;
        CheckResult r;
        if (threads > 1) {
            // The check and the set-up of the simplification (coarse mesh, features,
            // embedding, grid) only read the input: side by side.
            auto check = std::async(std::launch::async, [&] {
                return check_intersections(original, check_options, Context{}, "input intersections");
            });
            simplifier = std::make_unique<Simplifier>(original, options, context, threads);
            r = check.get();
        } else {
            r = check_intersections(original, check_options, context, "input intersections");
        }
        if (!r.passed)
            throw AlgorithmError("the input surface intersects itself (" + std::to_string(r.problem_count) +
                                 " problems; first: " + (r.problems.empty() ? std::string("?") : r.problems[0].describe()) +
                                 "); bpm needs a surface without self-intersections to produce a coarse surface "
                                 "without them. Repair the input, or use --allow-self-intersecting-input");
    }
    if (!simplifier) simplifier = std::make_unique<Simplifier>(original, options, context, threads);
    SimplifyResult result = simplifier->run(out);
    result.threads = threads;
    return result;
}

}  // namespace bpm
