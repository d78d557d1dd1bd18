#pragma once
// deal.II adapter, part 1: a dealii::Manifold<3> whose new points are phi of the combined
// parameter points (Krause & Sander §3: new boundary vertices of a refined grid land on the
// original surface S0 through phi).
//
// deal.II hands a manifold physical points only (Manifold::get_new_point(surrounding_points,
// weights)); phi needs parameter points (a coarse triangle and barycentric coordinates,
// bpm::SurfacePoint). So PhiBoundary keeps, for every vertex it knows, the parameter point
// of its exact position: the level-0 vertices on S from the tet mesh
// (TetMesh::vertex_parameter_points), and every point it creates
// itself. A new point's parameter point is the weighted combination of the surrounding
// points' parameter points, expressed in one coarse triangle that contains all of them
// (every edge and face of a red-refined boundary triangle lies in one coarse triangle), and
// the new point is phi of it. A surrounding point it does not know (a vertex someone else
// moved) goes through `inverse`, when set; otherwise the new point is the plain weighted
// average, counted in fallbacks() so that a caller can report it instead of silently
// losing phi.
//
// Header-only; needs deal.II 9.4 (Debian libdeal.ii-dev) and libbpm.

#include <deal.II/base/array_view.h>
#include <deal.II/base/point.h>
#include <deal.II/base/table.h>
#include <deal.II/grid/manifold.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <mutex>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "bpm/errors.h"
#include "bpm/parametrization.h"
#include "bpm/phi_evaluation.h"
#include "bpm/surface_point.h"

namespace bpm::dealii {

inline Vec3 to_vec3(const ::dealii::Point<3>& p) { return Vec3{p[0], p[1], p[2]}; }
inline ::dealii::Point<3> to_dealii_point(const Vec3& v) { return ::dealii::Point<3>(v[0], v[1], v[2]); }

// The manifold id the adapter gives every face on S (boundary and interfaces) and its lines.
constexpr ::dealii::types::manifold_id kPhiManifoldId = 17;

// Shared state of all clones of a PhiManifold (deal.II stores a clone of the manifold it is
// given, and may clone it again): the parametrization, phi, and the parameter points of the
// known positions. Not copyable; hold it by shared_ptr.
class PhiBoundary {
public:
    // Keeps a reference to `param`, which must outlive this object and not change.
    // apply_phi = false: new points at the weighted average of the surrounding points, with
    // the same bookkeeping of parameter points (the flat comparison series).
    explicit PhiBoundary(const Parametrization& param, bool apply_phi = true)
        : param_(param), phi_(param), apply_phi_(apply_phi) {
        const Surface& s = param.coarse;
        vertex_triangles_.resize(static_cast<size_t>(s.num_vertices()));
        for (int32_t t = 0; t < s.num_triangles(); ++t)
            for (int32_t c : s.triangles[t]) vertex_triangles_[static_cast<size_t>(c)].push_back(t);
    }
    PhiBoundary(const PhiBoundary&) = delete;
    PhiBoundary& operator=(const PhiBoundary&) = delete;

    const Parametrization& parametrization() const { return param_; }
    const PhiEvaluator& phi() const { return phi_; }
    bool applies_phi() const { return apply_phi_.load(); }
    // Switches placement (phi, or the weighted average) for the points made from now on;
    // the parameter points are recorded either way. The adapter's refinement with repair
    // lets deal.II place new points at the midpoints and the repair move them to phi
    // (bpm/dealii/global_refinement.h).
    void set_applies_phi(bool apply_phi) { apply_phi_.store(apply_phi); }

    // Inverse phi for positions the map does not know (e.g. bpm::PhiInverse); returns an
    // invalid SurfacePoint when it finds none.
    std::function<SurfacePoint(const Vec3&)> inverse;

    // Records that the vertex at exactly `position` has parameter point `p` (replacing any
    // earlier entry for that position).
    void remember(const Vec3& position, const SurfacePoint& p) {
        std::lock_guard<std::mutex> lock(mutex_);
        known_[key(position)] = p;
    }
    void forget_all() {
        std::lock_guard<std::mutex> lock(mutex_);
        known_.clear();
    }
    // The parameter point of a known position; invalid if unknown.
    SurfacePoint known(const Vec3& position) const {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto it = known_.find(key(position));
        return it == known_.end() ? SurfacePoint{} : it->second;
    }
    // known(), else inverse(); invalid if neither finds one.
    SurfacePoint parameter_point(const Vec3& position) const {
        SurfacePoint p = known(position);
        if (!p.valid() && inverse) {
            p = inverse(position);
            if (p.valid()) inverse_uses_.fetch_add(1);
        }
        return p;
    }

    // The new point for deal.II: phi(sum_i w_i p_i) with p_i the parameter points of
    // `points`, combined in a coarse triangle that contains all of them; remembered, so that
    // the next level can refine the edges that end at it. Falls back to sum_i w_i x_i (and
    // counts it) when a point has no parameter point or no coarse triangle holds them all.
    // \pre points.size() == weights.size() >= 1, weights sum to 1.
    Vec3 new_point(const std::vector<Vec3>& points, const std::vector<double>& weights) const {
        std::vector<SurfacePoint> p(points.size());
        for (size_t i = 0; i < points.size(); ++i) p[i] = parameter_point(points[i]);
        const SurfacePoint combined = combine(p, weights);
        Vec3 average{0, 0, 0};
        for (size_t i = 0; i < points.size(); ++i) average = average + weights[i] * points[i];
        if (!combined.valid()) {
            fallbacks_.fetch_add(1);
            return average;
        }
        const Vec3 x = apply_phi_.load() ? phi_.evaluate(combined.triangle, combined.barycentric).position : average;
        const_cast<PhiBoundary*>(this)->remember(x, combined);
        return x;
    }

    // sum_i w_i p_i in one coarse triangle containing every p_i (the lowest-numbered one);
    // invalid if some p_i is invalid or no coarse triangle contains them all.
    SurfacePoint combine(const std::vector<SurfacePoint>& p, const std::vector<double>& w) const {
        if (p.empty()) return {};
        for (const SurfacePoint& q : p)
            if (!q.valid()) return {};
        for (int32_t t : candidate_triangles(p[0])) {
            Vec3 b{0, 0, 0};
            bool inside = true;
            for (size_t i = 0; i < p.size() && inside; ++i) {
                Vec3 bi;
                inside = express_in(p[i], t, bi);
                b = b + w[i] * bi;
            }
            if (!inside) continue;
            const double sum = b[0] + b[1] + b[2];
            return SurfacePoint{t, (1.0 / sum) * b};
        }
        return {};
    }

    // Barycentric coordinates of `p` in coarse triangle t; false if p does not lie in t
    // (a corner with a nonzero coordinate is not a corner of t). Exact zeros decide: the
    // parameter points of refined vertices are midpoints of exact ones.
    bool express_in(const SurfacePoint& p, int32_t t, Vec3& out) const {
        out = Vec3{0, 0, 0};
        if (p.triangle == t) {
            out = p.barycentric;
            return true;
        }
        const Tri& from = param_.coarse.triangles[static_cast<size_t>(p.triangle)];
        const Tri& to = param_.coarse.triangles[static_cast<size_t>(t)];
        for (int k = 0; k < 3; ++k) {
            if (p.barycentric[k] == 0) continue;
            int j = 0;
            while (j < 3 && to[j] != from[k]) ++j;
            if (j == 3) return false;
            out[j] += p.barycentric[k];
        }
        return true;
    }

    // Coarse triangles that contain p: its own, then those around one of its corners with
    // a nonzero coordinate (a point on an edge or at a corner lies in several).
    std::vector<int32_t> candidate_triangles(const SurfacePoint& p) const {
        std::vector<int32_t> out{p.triangle};
        const Tri& tri = param_.coarse.triangles[static_cast<size_t>(p.triangle)];
        int k = 0;
        while (k < 3 && p.barycentric[k] == 0) ++k;
        if (k == 3) return out;
        for (int32_t t : vertex_triangles_[static_cast<size_t>(tri[k])])
            if (t != p.triangle) out.push_back(t);
        return out;
    }

    int64_t fallbacks() const { return fallbacks_.load(); }
    int64_t inverse_uses() const { return inverse_uses_.load(); }
    size_t known_count() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return known_.size();
    }

private:
    using Key = std::array<uint64_t, 3>;
    struct KeyHash {
        size_t operator()(const Key& k) const {
            uint64_t h = k[0] * 0x9E3779B97F4A7C15ull;
            h ^= k[1] + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
            h ^= k[2] + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
            return static_cast<size_t>(h);
        }
    };
    // Bit patterns: a vertex is found again only at exactly the position recorded (+0 and
    // -0 are folded together, since deal.II may compute either for the same point).
    static Key key(const Vec3& x) {
        Key k;
        for (int i = 0; i < 3; ++i) {
            const double v = x[i] == 0 ? 0.0 : x[i];
            std::memcpy(&k[static_cast<size_t>(i)], &v, sizeof v);
        }
        return k;
    }

    const Parametrization& param_;
    PhiEvaluator phi_;
    std::atomic<bool> apply_phi_;
    std::vector<std::vector<int32_t>> vertex_triangles_;  // coarse vertex -> coarse triangles around it
    mutable std::mutex mutex_;
    std::unordered_map<Key, SurfacePoint, KeyHash> known_;
    mutable std::atomic<int64_t> fallbacks_{0};
    mutable std::atomic<int64_t> inverse_uses_{0};
};

// The manifold deal.II calls for every new point on a line or face with kPhiManifoldId.
class PhiManifold : public ::dealii::Manifold<3> {
public:
    explicit PhiManifold(std::shared_ptr<PhiBoundary> boundary) : boundary_(std::move(boundary)) {
        if (!boundary_) throw OptionError("PhiManifold: no PhiBoundary given");
    }
    std::unique_ptr<::dealii::Manifold<3>> clone() const override { return std::make_unique<PhiManifold>(boundary_); }

    ::dealii::Point<3> get_new_point(const ::dealii::ArrayView<const ::dealii::Point<3>>& surrounding_points,
                                     const ::dealii::ArrayView<const double>& weights) const override {
        std::vector<Vec3> x(surrounding_points.size());
        std::vector<double> w(weights.begin(), weights.end());
        for (size_t i = 0; i < x.size(); ++i) x[i] = to_vec3(surrounding_points[static_cast<unsigned>(i)]);
        return to_dealii_point(boundary_->new_point(x, w));
    }

    // deal.II's default goes through get_intermediate_point / project_to_manifold, which
    // this manifold does not have: compute every row with get_new_point instead.
    void get_new_points(const ::dealii::ArrayView<const ::dealii::Point<3>>& surrounding_points,
                        const ::dealii::Table<2, double>& weights,
                        ::dealii::ArrayView<::dealii::Point<3>> new_points) const override {
        std::vector<double> row(weights.size(1));
        for (unsigned r = 0; r < weights.size(0); ++r) {
            for (unsigned c = 0; c < weights.size(1); ++c) row[c] = weights(r, c);
            new_points[r] = get_new_point(surrounding_points, ::dealii::make_array_view(row));
        }
    }

    const std::shared_ptr<PhiBoundary>& boundary() const { return boundary_; }

private:
    std::shared_ptr<PhiBoundary> boundary_;
};

}  // namespace bpm::dealii
