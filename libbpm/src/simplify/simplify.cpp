// Driver of the simplification: priority queue over vertices, global admissibility
// (intersections with the rest of the surface, error and edge-length limits), and
// export of the final parametrization. The local work is in vertex_removal.cpp.
#include "bpm/simplify.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <future>
#include <functional>
#include <memory>
#include <queue>
#include <stdexcept>
#include <unordered_map>

#include "bpm/check.h"
#include "bpm/errors.h"
#include "bpm/predicates.h"
#include "simplify/coarse_mesh.h"
#include "simplify/embedding.h"
#include "simplify/export_phi.h"
#include "simplify/intersection_test.h"
#include "simplify/overlay.h"
#include "simplify/planning_pool.h"
#include "simplify/removal_cost.h"
#include "simplify/vertex_removal.h"

namespace bpm {

using namespace detail;

namespace {

struct QueueEntry {
    double cost;
    int32_t vertex;
    uint32_t stamp;
    bool operator>(const QueueEntry& o) const {
        return cost > o.cost || (cost == o.cost && vertex > o.vertex);
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
          intersections_(mesh_) {
        mesh_.mark_feature_edges(options.feature_angle_degrees);
        mesh_.mark_corners(options.feature_angle_degrees, options.corner_crease_length * diagonal_,
                           options.keep_corners);
        sign_.resize(original.triangles.size());
        for (int32_t t = 0; t < original.num_triangles(); ++t) sign_[t] = mesh_.flipped_initially(t) ? -1 : 1;
        // Only with a limit: the angle costs about 5% of the planning time.
        if (options.max_normal_deviation_degrees < 180.0) oriented_normals_.resize(original.triangles.size());
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
    IntersectionTest intersections_;  // of new triangles with the rest of the surface
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
    // Queue key of v from a cheap plan (a lower bound of the full plan's cost), +infinity
    // if it cannot be removed now (reason recorded). On the remover of `thread`.
    double rank(int32_t v, RemovalPlan& plan, int thread);
    // removal_cost() of the plan to remove v, the reason for +infinity recorded.
    // CostBasis::Estimate: the cost a full plan is ranked by first (the same for a plan
    // whose validation is pending and for a complete one).
    double judge(int32_t v, const RemovalPlan& plan, CostBasis basis = CostBasis::Plan) {
        return removal_cost(plan, options_, diagonal_, basis, last_reason_[v]);
    }
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
    if (options_.prevent_intersections &&
        intersections_.intersects_rest(plan.new_triangles, plan.removed_triangles, candidates_[0])) {
        last_reason_[v] = "would create a self-intersection";
        return false;
    }
    return true;
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
    const int finish_parts = std::min<int>(VertexRemover::kMaxFinishParts, int(removers_.size()) + 1);
    std::vector<std::pair<int32_t, Tri>> grid_removed;  // of the last commit, for Job::Grid
    PlanningPool pool(static_cast<int>(removers_.size()) + 1);
    auto work = [&](int thread, size_t i) {
        Task& task = tasks[i];
        switch (task.job) {
            case Job::Rank: task.cost = rank(task.vertex, cheap_plans[thread], thread); break;
            case Job::PlanTop: candidates[task.slot].remover->plan_deferred(task.vertex, *candidates[task.slot].plan); break;
            case Job::Finish: candidates[task.slot].remover->finish_part(task.vertex, finish_parts); break;
            case Job::Intersect: {
                Candidate& c = candidates[task.slot];
                c.intersects = intersections_.intersects_rest(c.plan->new_triangles, c.plan->removed_triangles,
                                                              candidates_[thread]);
                break;
            }
            case Job::Grid: intersections_.update(grid_removed, task.vertex); break;
        }
    };

    // First ranking of all vertices, in chunks.
    {
        // 256 vertices per task; above 2^27 vertices more, so that a round has at most
        // 2^19 tasks (the pool takes fewer than 2^20). The costs do not depend on it.
        const int32_t kChunk = std::max<int32_t>(256, int32_t((int64_t(nv) + (1 << 19) - 1) >> 19));
        tasks.clear();
        for (int64_t v = 0; v < nv; v += kChunk) tasks.push_back(Task{int32_t(v)});
        std::vector<double> costs(nv, std::numeric_limits<double>::infinity());
        std::atomic<int32_t> ranked{0};
        pool.run_round(tasks.size(), [&](int thread, size_t i) {
            const int32_t first = tasks[i].vertex, last = int32_t(std::min<int64_t>(nv, int64_t(first) + kChunk));
            for (int32_t v = first; v < last; ++v) {
                remover(thread).plan(v, false, cheap_plans[thread]);
                costs[v] = judge(v, cheap_plans[thread]);
            }
            const int32_t done = ranked.fetch_add(last - first) + (last - first);
            if (thread == 0) context_.report(0.2 * done / std::max(nv, 1), "evaluating vertices");
        });
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
        pool.run_round(tasks.size(), work);
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
            const double estimate = judge(v, *c.plan, CostBasis::Estimate);
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
        pool.run_round(tasks.size(), work);
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
                if (options_.prevent_intersections && meet_improperly(original_.vertices, plan.new_triangles, candidates[0].plan->new_triangles)) {
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
        pool.run_round(tasks.size(), work);
        intersections_.rebuild_if_sparse();
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
    const double max_deviation = export_parametrization(original_, mesh_, embedding_, sign_, pool, out);
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
    if (!(options.queue_tolerance >= 0 && options.queue_tolerance <= 10))
        throw OptionError("--queue-tolerance must be between 0 and 10");
    if (!(options.corner_crease_length >= 0 && options.corner_crease_length <= 1))
        throw OptionError("the corner crease length must be between 0 and 1 (of the diagonal)");
    if (!(options.feature_angle_degrees >= 0 && options.feature_angle_degrees <= 180))
        throw OptionError("--feature-angle must be between 0 and 180 degrees");
    const int threads = planning_threads(options.threads);
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
