// Interior-vertex smoothing of tetrahedral meshes (bpm/tetmesh_smooth.h).
//
// References: L. A. Freitag, "On combining Laplacian and optimization-based mesh smoothing
// techniques", AMD-Vol. 220, Trends in Unstructured Mesh Generation, ASME 1997 (smart
// Laplacian, then optimisation where Laplacian does not help); L. A. Freitag and
// P. Plassmann, "Local optimization-based simplicial mesh untangling and improvement",
// Int. J. Numer. Meth. Engng. 49 (2000) 109-125 (max-min of the dihedral angles around a
// vertex by steepest ascent on the convex hull of the active gradients).

#include "bpm/tetmesh_smooth.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

#include "bpm/errors.h"
#include "bpm/predicates.h"
#include "core/tetrahedron_quality.h"
#include "tetmesh/tetmesh_internal.h"

namespace bpm {

namespace detail {

namespace {

constexpr double kPi = 3.14159265358979323846;

class TetMeshSmoother {
public:
    TetMeshSmoother(std::vector<Vec3>& x, const std::vector<Tet>& tets, const std::vector<bool>& negative,
             const std::vector<char>& movable, const TetSmoothOptions& o)
        : x_(x),
          tets_(tets),
          negative_(negative),
          movable_(movable),
          o_(o),
          target_(pseudo_from_radians(o.target_degrees * kPi / 180)) {
        // Tetrahedra around each movable vertex (CSR).
        offsets_.assign(x_.size() + 1, 0);
        for (const Tet& t : tets_)
            for (int32_t v : t)
                if (movable_[v]) ++offsets_[v + 1];
        std::partial_sum(offsets_.begin(), offsets_.end(), offsets_.begin());
        incident_.resize(static_cast<size_t>(offsets_.back()));
        std::vector<int64_t> fill(offsets_.begin(), offsets_.end() - 1);
        for (size_t t = 0; t < tets_.size(); ++t)
            for (int32_t v : tets_[t])
                if (movable_[v]) incident_[fill[v]++] = static_cast<int32_t>(t);
        quality_.resize(tets_.size());
        for (size_t t = 0; t < tets_.size(); ++t) quality_[t] = quality(t);
    }

    double mesh_min() const {
        return quality_.empty() ? 0 : *std::min_element(quality_.begin(), quality_.end());
    }

    // dirty[v]: the tetrahedra around v changed since v was last visited (sized #V, kept
    // between calls; a vertex that could not improve is not visited again until then).
    void run(TetSmoothResult& result, std::vector<char>& dirty, const Context& context, double base, double span) {
        std::vector<char> moved(x_.size(), 0);
        for (int sweep = 0; sweep < o_.sweeps; ++sweep) {
            // Vertices with a tetrahedron below the target around them, worst first.
            std::vector<std::pair<double, int32_t>> order;
            for (size_t v = 0; v < x_.size(); ++v) {
                if (!movable_[v] || !dirty[v]) continue;
                const double m = patch_min(static_cast<int32_t>(v));
                if (m < target_) order.emplace_back(m, static_cast<int32_t>(v));
            }
            if (order.empty()) break;
            std::sort(order.begin(), order.end());
            for (const auto& e : order) dirty[e.second] = 0;
            int64_t moves = 0;
            for (const auto& [q, v] : order) {
                ++result.visits;
                const int64_t n = improve(v);
                if (n == 0) continue;
                moves += n;
                moved[v] = 1;
                for (int32_t u : neighbours_) dirty[u] = 1;
                dirty[v] = 1;
            }
            result.moves += moves;
            context.report(base + span * (sweep + 1) / o_.sweeps, "smoothing interior vertices");
            if (moves == 0) break;
        }
        for (char m : moved) result.moved_vertices += m;
    }

private:
    Tet oriented(size_t t) const {
        Tet T = tets_[t];
        if (!negative_.empty() && negative_[t]) std::swap(T[2], T[3]);
        return T;
    }
    double quality(size_t t) const {
        const Tet T = oriented(t);
        return min_dihedral_pseudo(x_[T[0]], x_[T[1]], x_[T[2]], x_[T[3]]);
    }
    bool positive(size_t t) const {
        const Tet T = oriented(t);
        return orient3d(x_[T[0]], x_[T[1]], x_[T[2]], x_[T[3]]) == 1;
    }
    double patch_min(int32_t v) const {
        double m = std::numeric_limits<double>::infinity();
        for (int64_t k = offsets_[v]; k < offsets_[v + 1]; ++k) m = std::min(m, quality_[incident_[k]]);
        return m;
    }

    // Moves v to p if that raises the smallest angle around v above `bar` and keeps every
    // tetrahedron that was positive positive (exact). Returns whether it moved.
    bool trial(int32_t v, const Vec3& p, double bar) {
        const Vec3 home = x_[v];
        x_[v] = p;
        const int64_t begin = offsets_[v], end = offsets_[v + 1];
        scratch_.resize(static_cast<size_t>(end - begin));
        bool ok = true;
        // The tetrahedra that were worst first: a failing trial usually stops at once.
        for (int64_t k = begin; ok && k < end; ++k) {
            scratch_[k - begin] = quality(incident_[k]);
            ok = scratch_[k - begin] > bar;
        }
        for (int64_t k = begin; ok && k < end; ++k)
            if (was_positive_[k - begin] && !positive(incident_[k])) ok = false;
        if (!ok) {
            x_[v] = home;
            return false;
        }
        for (int64_t k = begin; k < end; ++k) quality_[incident_[k]] = scratch_[k - begin];
        return true;
    }

    // All six angles of every tetrahedron around v, with v at its current position.
    void patch_angles(int32_t v, std::vector<double>& out) const {
        const int64_t begin = offsets_[v], end = offsets_[v + 1];
        out.resize(static_cast<size_t>(6 * (end - begin)));
        for (int64_t k = begin; k < end; ++k) {
            const Tet T = oriented(incident_[k]);
            dihedral_pseudo_angles(x_[T[0]], x_[T[1]], x_[T[2]], x_[T[3]], &out[6 * (k - begin)]);
        }
    }

    int64_t improve(int32_t v) {
        const int64_t begin = offsets_[v], end = offsets_[v + 1];
        if (begin == end) return 0;
        double current = patch_min(v);
        if (current >= target_) return 0;
        // Worst tetrahedra first, so that a failing trial stops early.
        std::sort(incident_.begin() + begin, incident_.begin() + end,
                  [&](int32_t a, int32_t b) { return quality_[a] < quality_[b]; });
        was_positive_.resize(static_cast<size_t>(end - begin));
        for (int64_t k = begin; k < end; ++k) was_positive_[k - begin] = positive(incident_[k]);
        // Edge neighbours and the local length scale.
        neighbours_.clear();
        for (int64_t k = begin; k < end; ++k)
            for (int32_t u : tets_[incident_[k]])
                if (u != v) neighbours_.push_back(u);
        std::sort(neighbours_.begin(), neighbours_.end());
        neighbours_.erase(std::unique(neighbours_.begin(), neighbours_.end()), neighbours_.end());
        Vec3 centroid{0, 0, 0};
        double scale = 0;
        for (int32_t u : neighbours_) {
            centroid = centroid + x_[u];
            scale += distance(x_[u], x_[v]);
        }
        centroid = (1.0 / neighbours_.size()) * centroid;
        scale /= neighbours_.size();
        if (!(scale > 0)) return 0;

        int64_t moves = 0;
        if (o_.laplacian) {
            const Vec3 home = x_[v];
            for (double f : {1.0, 0.5, 0.25})
                if (trial(v, home + f * (centroid - home), current)) {
                    ++moves;
                    current = patch_min(v);
                    break;
                }
        }
        if (!o_.optimize) return moves;
        const double h = 1e-7 * scale;  // finite-difference step, relative to the local edge length
        for (int it = 0; it < o_.max_iterations && current < target_; ++it) {
            const Vec3 home = x_[v];
            patch_angles(v, angles_);
            const size_t n = angles_.size();
            double low = std::numeric_limits<double>::infinity();
            for (double a : angles_) low = std::min(low, a);
            // Only angles near the smallest matter for this step (the step is limited to
            // where the next one catches up): gradients by forward differences for those.
            const double near = low + 0.2;  // pseudo-angle, about 11 degrees above
            candidates_.clear();
            for (size_t i = 0; i < n; ++i)
                if (angles_[i] < near) candidates_.push_back(i);
            gradients_.resize(n);
            for (int axis = 0; axis < 3; ++axis) {
                x_[v] = home;
                x_[v][axis] += h;
                size_t done = n;  // the tetrahedron (local index) whose angles are in shifted6_
                for (size_t i : candidates_) {
                    if (i / 6 != done) {
                        done = i / 6;
                        const Tet T = oriented(incident_[offsets_[v] + static_cast<int64_t>(done)]);
                        dihedral_pseudo_angles(x_[T[0]], x_[T[1]], x_[T[2]], x_[T[3]], shifted6_);
                    }
                    gradients_[i][axis] = (shifted6_[i % 6] - angles_[i]) / h;
                }
            }
            x_[v] = home;
            // Active angles: within a small tolerance of the smallest.
            const double tolerance = 0.02 * std::fabs(low) + 1e-6;
            active_.clear();
            for (size_t i : candidates_)
                if (angles_[i] <= low + tolerance) active_.push_back(i);
            // Smallest vector in the convex hull of the active gradients (Gilbert's algorithm):
            // a direction in which every active angle grows.
            Vec3 d = gradients_[active_[0]];
            for (int k = 0; k < 64 && active_.size() > 1; ++k) {
                size_t best = active_[0];
                double best_dot = std::numeric_limits<double>::infinity();
                for (size_t i : active_) {
                    const double g = dot(gradients_[i], d);
                    if (g < best_dot) best_dot = g, best = i;
                }
                const double dd = dot(d, d);
                if (dd - best_dot <= 1e-12 * dd) break;
                const Vec3 diff = gradients_[best] - d;
                const double t = std::clamp(-dot(d, diff) / dot(diff, diff), 0.0, 1.0);
                d = d + t * diff;
            }
            const double rate = dot(d, d);  // growth of the active angles per unit step (first order)
            if (!(std::sqrt(rate) * scale > 1e-9)) break;  // stationary: no direction helps
            // First-order step to where an inactive angle meets the active ones, at most half
            // the local edge length and at most to where the smallest angle would grow by
            // the window of angles considered.
            double step = std::min(0.5 * scale / std::sqrt(rate), 0.2 / rate);
            for (size_t i : candidates_) {
                if (angles_[i] <= low + tolerance) continue;
                const double r = dot(gradients_[i], d);
                if (r < rate) step = std::min(step, (angles_[i] - low) / (rate - r));
            }
            bool accepted = false;
            for (int halving = 0; halving < 16 && !accepted; ++halving, step *= 0.5)
                accepted = trial(v, home + step * d, current);
            if (!accepted) break;
            ++moves;
            const double before = current;
            current = patch_min(v);
            if (current - before < 0.005 * std::fabs(before) + 1e-9) break;  // no real progress
        }
        return moves;
    }

    std::vector<Vec3>& x_;
    const std::vector<Tet>& tets_;
    const std::vector<bool>& negative_;
    const std::vector<char>& movable_;
    const TetSmoothOptions& o_;
    const double target_;
    std::vector<int64_t> offsets_;
    std::vector<int32_t> incident_;
    std::vector<double> quality_;
    // scratch
    std::vector<double> scratch_, angles_;
    std::vector<Vec3> gradients_;
    std::vector<size_t> active_, candidates_;
    double shifted6_[6];
    std::vector<int32_t> neighbours_;
    std::vector<char> was_positive_;
};

}  // namespace

void check_smooth_options(const TetSmoothOptions& o) {
    if (o.sweeps < 0) throw OptionError("smoothing sweeps must be >= 0");
    if (o.max_iterations < 0) throw OptionError("smoothing iterations must be >= 0");
    if (!(o.target_degrees > 0 && o.target_degrees < 180))
        throw OptionError("the smoothing target angle must be in (0, 180) degrees");
}

TetSmoothResult smooth_interior(std::vector<Vec3>& x, const std::vector<Tet>& tets, const std::vector<bool>& negative,
                                const std::vector<char>& movable, std::vector<char>* dirty,
                                const TetSmoothOptions& options, const Context& context, double progress_base,
                                double progress_span) {
    using clock = std::chrono::steady_clock;
    const auto start = clock::now();
    check_smooth_options(options);
    TetSmoothResult result;
    TetMeshSmoother smoother(x, tets, negative, movable, options);
    result.min_dihedral_before_degrees = radians_from_pseudo(smoother.mesh_min()) * 180 / kPi;
    std::vector<char> all;
    if (!dirty) all.assign(x.size(), 1);
    smoother.run(result, dirty ? *dirty : all, context, progress_base, progress_span);
    result.min_dihedral_after_degrees = radians_from_pseudo(smoother.mesh_min()) * 180 / kPi;
    result.seconds = std::chrono::duration<double>(clock::now() - start).count();
    return result;
}

}  // namespace detail

double tet_min_dihedral_degrees(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    return detail::min_dihedral_degrees(a, b, c, d);
}

namespace detail {

TetSmoothResult smooth_tetmesh_within(TetMesh& mesh, const TetSmoothOptions& options, const Context& context,
                                      double progress_base, double progress_span) {
    check_smooth_options(options);
    std::vector<char> movable(mesh.vertices.size(), 0);
    for (size_t v = 0; v < movable.size(); ++v)
        movable[v] = v < mesh.vertex_parameter_points.size() && !mesh.vertex_parameter_points[v].valid();
    return smooth_interior(mesh.vertices, mesh.tetrahedra, {}, movable, nullptr, options, context, progress_base,
                           progress_span);
}

}  // namespace detail

TetSmoothResult smooth_tetmesh(TetMesh& mesh, const TetSmoothOptions& options, const Context& context) {
    const TetSmoothResult r = detail::smooth_tetmesh_within(mesh, options, context, 0, 1);
    context.report(1.0, "smoothing done");
    return r;
}

}  // namespace bpm
