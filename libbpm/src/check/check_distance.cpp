// check_distance: the --max-distance gate of bpm-check. How far phi's image and the coarse
// surface S are from the original surface S0, as two-sided Hausdorff distances relative
// to the bounding-box diagonal of S0, plus the exact bound max |phi(x) - x| over the
// nodes of phi. The only file of the checker that includes CGAL's AABB tree.
//
// Four one-sided distances are estimated, each as the maximum over a sample set of the
// distance from a sample to the other surface:
//   image -> S0   samples on every piece's image triangle
//   S0 -> image   samples on every original triangle, to the pieces' image triangles
//   S -> S0       samples on every coarse triangle
//   S0 -> S       samples on every original triangle
// Samples of a triangle: a barycentric grid with an even number n of divisions per side
// (so corners and edge midpoints are grid points) such that longest side / n is at most
// the requested spacing (n capped at kMaxDivisions), plus the centroid. No randomness:
// the same file gives the same numbers.
//
// Closest points come from CGAL AABB trees (CGAL::Epick, double precision). To be fast on
// a million triangles the search is a branch and bound on the maximum: every sample gets
// a cheap upper bound of its distance (the distance to a few candidate triangles that
// phi names: the original triangle a piece maps into, the coarse triangles whose pieces
// cover an original triangle, ...); a sample whose bound is below the maximum found so
// far cannot raise it and needs no query, and a sample whose bound is at rounding level
// (kFloor) is taken with its bound. Elements are visited in decreasing order of their
// bound, so that the search stops as soon as the largest remaining bound is below the
// maximum. Trees are built only when a query is needed (for a correct phi the image
// directions never need one).
//
// Element bounds: image -> S0 uses the exact bound max over the piece's corners of
// their distance to its original triangle (distance to a convex set is convex);
// S -> S0 uses max over the coarse triangle's nodes of |phi(x) - x| plus that image
// bound, exact wherever the pieces tile their coarse triangle (check_bijectivity);
// S0 -> image and S0 -> S use the largest per-sample bound of the original triangle.
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bpm/check.h"
#include "check/check_internal.h"

namespace bpm {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Triangle3 = K::Triangle_3;
using TriangleIterator = std::vector<Triangle3>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<K, TriangleIterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
using Ids = std::vector<std::pair<std::string, int64_t>>;

constexpr int kMaxDivisions = 256;   // per triangle side: at most 33 153 grid samples per triangle
constexpr double kFloor = 1e-12;     // rounding level, relative to diagonal + largest |coordinate|
constexpr double kLargestCoordinate = 1e150;  // beyond this, squared distances may overflow
constexpr double kSmallestDiagonal = 1e-30;    // below this, squared areas of ordinary triangles underflow
// CGAL's closest point on a triangle whose squared normal (|ab x ac|^2) underflows, which
// happens for sides below about 1e-80 whatever the rest of the surface, is NaN, and NaN
// handed to its exact fallback raises SIGFPE (GMP; found by fuzz_read_bpm with pieces of
// side 1e-155). Triangles below this squared normal are measured by hand instead.
constexpr double kSmallestTreeNormal2 = 1e-200;
constexpr size_t kMaxCandidates = 48;  // local-bound candidates per sample, beyond which only the tree is asked
constexpr double kInf = std::numeric_limits<double>::infinity();

Point to_point(const Vec3& v) { return Point(v[0], v[1], v[2]); }

double squared(const Vec3& v) { return dot(v, v); }

double segment_squared_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double len = dot(ab, ab);
    const double t = len > 0 ? std::clamp(dot(p - a, ab) / len, 0.0, 1.0) : 0.0;
    return squared(p - (a + t * ab));
}

// Squared distance from p to triangle (a, b, c) (Ericson, Real-Time Collision Detection,
// §5.1.5). Where the closest point is inside, the barycentric projection is inaccurate
// for slivers (pieces of phi often are), so the distance to the three sides, which is
// well conditioned and never smaller than the true one, is taken when smaller; this also
// covers degenerate triangles.
double triangle_squared_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    double result;
    if (d1 <= 0 && d2 <= 0) return squared(ap);
    const Vec3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return squared(bp);
    const double vc = d1 * d4 - d3 * d2;
    const Vec3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    const double vb = d5 * d2 - d1 * d6;
    const double va = d3 * d6 - d5 * d4;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        result = squared(p - (a + (d1 / (d1 - d3)) * ab));
    } else if (d6 >= 0 && d5 <= d6) {
        return squared(cp);
    } else if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        result = squared(p - (a + (d2 / (d2 - d6)) * ac));
    } else if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        result = squared(p - (b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b)));
    } else {
        const double denom = 1.0 / (va + vb + vc);
        result = squared(p - (a + (vb * denom) * ab + (vc * denom) * ac));
        const double sides = std::min({segment_squared_distance(p, a, b), segment_squared_distance(p, b, c),
                                       segment_squared_distance(p, c, a)});
        return std::isfinite(result) ? std::min(result, sides) : sides;
    }
    if (std::isfinite(result)) return result;
    return std::min({segment_squared_distance(p, a, b), segment_squared_distance(p, b, c),
                     segment_squared_distance(p, c, a)});
}

double triangle_distance(const Vec3& p, const std::array<Vec3, 3>& t) {
    return std::sqrt(triangle_squared_distance(p, t[0], t[1], t[2]));
}

// The number of divisions per side of triangle t's sample grid (see the file comment).
int sample_divisions(const std::array<Vec3, 3>& t, double spacing) {
    const double longest = std::max({distance(t[0], t[1]), distance(t[1], t[2]), distance(t[2], t[0])});
    int n = 2;
    if (spacing > 0 && std::isfinite(longest)) {
        const double halves = std::ceil(longest / (2.0 * spacing));
        n = halves >= kMaxDivisions / 2 ? kMaxDivisions : std::max(2, 2 * static_cast<int>(halves));
    }
    return n;
}

// Calls visit(point, index) for every sample of triangle t (see the file comment), where
// index numbers the samples in the order visited: grid point (i, j), at barycentric
// ((n - i - j) / n, i / n, j / n), is sample_index(n, i, j), and the centroid comes last
// ((n + 1)(n + 2) / 2). Returns the spacing reached: longest side / number of divisions.
int64_t sample_index(int n, int i, int j) { return int64_t(i) * (n + 1) - int64_t(i) * (i - 1) / 2 + j; }

template <class Visit>
double for_each_indexed_sample(const std::array<Vec3, 3>& t, double spacing, Visit&& visit) {
    const double longest = std::max({distance(t[0], t[1]), distance(t[1], t[2]), distance(t[2], t[0])});
    const int n = sample_divisions(t, spacing);
    int64_t index = 0;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j) {
            const Vec3 b{double(n - i - j) / n, double(i) / n, double(j) / n};
            visit(barycentric_point(t[0], t[1], t[2], b), index++);
        }
    visit(barycentric_point(t[0], t[1], t[2], {1.0 / 3, 1.0 / 3, 1.0 / 3}), index);
    return longest / n;
}

// Calls visit(point) for every sample of triangle t; returns the spacing reached.
template <class Visit>
double for_each_sample(const std::array<Vec3, 3>& t, double spacing, Visit&& visit) {
    return for_each_indexed_sample(t, spacing, [&](const Vec3& x, int64_t) { visit(x); });
}

// Closest-point queries on a fixed set of triangles. The tree is built on first use.
// A query with a hint (a triangle known to be near, e.g. the local candidate) starts
// from that triangle's nearest corner, so the tree's internal KD-tree of hints, costly
// on a million triangles, is only built if a query without one comes.
class ClosestPoints {
public:
    ClosestPoints(int64_t count, std::function<std::array<Vec3, 3>(int64_t)> corners)
        : count_(count), corners_(std::move(corners)) {}
    // Distance from p to the nearest triangle, and that triangle's index (-1 if there are none).
    std::pair<double, int64_t> query(const Vec3& p, int64_t hint = -1) {
        ++queries;
        if (count_ == 0) return {kInf, -1};
        if (!built_) build();
        std::pair<double, int64_t> best{kInf, -1};
        if (tree_) {
            const Point q = to_point(p);
            Tree::Point_and_primitive_id hit;
            const int64_t at = hint >= 0 && hint < count_ ? tree_position_[static_cast<size_t>(hint)] : -1;
            if (at >= 0) {
                const Triangle3& t = triangles_[static_cast<size_t>(at)];
                int nearest_corner = 0;
                for (int k = 1; k < 3; ++k)
                    if (CGAL::squared_distance(q, t.vertex(k)) < CGAL::squared_distance(q, t.vertex(nearest_corner)))
                        nearest_corner = k;
                hit = tree_->closest_point_and_primitive(q, {t.vertex(nearest_corner), triangles_.cbegin() + at});
            } else {
                hit = tree_->closest_point_and_primitive(q);
            }
            const Vec3 nearest{hit.first.x(), hit.first.y(), hit.first.z()};
            best = {distance(p, nearest), tree_ids_[static_cast<size_t>(hit.second - triangles_.cbegin())]};
        }
        for (int64_t i : tiny_) {
            const auto c = corners_(i);
            const double d = std::sqrt(triangle_squared_distance(p, c[0], c[1], c[2]));
            if (d < best.first || best.second < 0) best = {d, i};
        }
        return best;
    }
    int64_t queries = 0;

private:
    int64_t count_;
    std::function<std::array<Vec3, 3>(int64_t)> corners_;
    std::vector<Triangle3> triangles_;     // those in the tree
    std::vector<int64_t> tree_ids_;        // index of each of triangles_
    std::vector<int64_t> tree_position_;   // per index: position in triangles_, or -1 (tiny)
    std::vector<int64_t> tiny_;            // indices of the triangles measured by hand
    std::unique_ptr<Tree> tree_;
    bool built_ = false;

    void build() {
        built_ = true;
        tree_position_.assign(static_cast<size_t>(count_), -1);
        for (int64_t i = 0; i < count_; ++i) {
            const auto c = corners_(i);
            if (!(squared(cross(c[1] - c[0], c[2] - c[0])) >= kSmallestTreeNormal2)) {
                tiny_.push_back(i);
                continue;
            }
            tree_position_[static_cast<size_t>(i)] = static_cast<int64_t>(triangles_.size());
            tree_ids_.push_back(i);
            triangles_.emplace_back(to_point(c[0]), to_point(c[1]), to_point(c[2]));
        }
        if (!triangles_.empty()) tree_ = std::make_unique<Tree>(triangles_.begin(), triangles_.end());
    }
};

// The largest distance found so far and where.
struct Extreme {
    double value = 0.0;
    bool found = false;
    Ids ids;
    // Can a sample whose distance is at most `bound` change the result? (Ties are kept by
    // the first one found, so they cannot.)
    bool could_raise(double bound) const { return !found || bound > value; }
    void offer(double d, Ids where) {
        if (could_raise(d)) {
            value = d;
            found = true;
            ids = std::move(where);
        }
    }
};

// Elements with key <= floor are settled by their key (an upper bound of all their
// samples' distances at rounding level), offered to `best` at where_settled(id); the
// others are evaluated by `exact`, in decreasing key order, until the key is below the
// maximum found. Keys must be upper bounds of the distances `exact` can find.
void branch_and_bound(std::vector<std::pair<double, int64_t>>& keyed, double floor, Extreme& best,
                      const std::function<Ids(int64_t)>& where_settled, const std::function<void(int64_t)>& exact) {
    std::vector<std::pair<double, int64_t>> open;
    for (const auto& [key, id] : keyed) {
        if (key <= floor) {
            if (best.could_raise(key)) best.offer(key, where_settled(id));
        } else {
            open.emplace_back(key, id);
        }
    }
    std::sort(open.begin(), open.end(), [](const auto& a, const auto& b) {
        return a.first > b.first || (a.first == b.first && a.second < b.second);
    });
    for (const auto& [key, id] : open) {
        if (!best.could_raise(key)) break;
        exact(id);
    }
}

// A sample's local bound `dist` (to triangle `nearest`) lowered to its distance to the
// whole triangle set, by a tree query starting from `hint`, unless it is at rounding
// level (floor) already.
void tighten(ClosestPoints& tree, const Vec3& x, int64_t hint, double floor, double& dist, int64_t& nearest) {
    if (!(dist > floor)) return;
    const auto hit = tree.query(x, hint);
    if (hit.first < dist) {
        dist = hit.first;
        nearest = hit.second;
    }
}

// Why the distances cannot be measured in double precision, if they cannot: phi unsafe
// to read, empty surfaces, a bad sample spacing, or coordinates too small or too large.
// Otherwise the bounding-box diagonal of S0 and its largest |coordinate|.
std::optional<std::string> why_not_measurable(const Parametrization& p, const CheckOptions& options, double& diagonal,
                                              double& magnitude) {
    if (auto why = detail::parametrization_unsafe(p)) return why;
    diagonal = bounding_box_diagonal(p.original);
    if (!(diagonal > 0) || p.original.num_triangles() == 0 || p.coarse.num_triangles() == 0)
        return "the surfaces are empty or S0 has no extent";
    if (!(options.error_sample_spacing > 0) || !std::isfinite(options.error_sample_spacing))
        return "the sample spacing must be a positive number";
    magnitude = 0.0;
    for (const Vec3& x : p.original.vertices)
        magnitude = std::max({magnitude, std::abs(x[0]), std::abs(x[1]), std::abs(x[2])});
    // Squared distances of coordinates beyond ~1e150 overflow to inf, and inf or NaN handed
    // to CGAL's exact number types raises SIGFPE (GMP): refuse such a file instead.
    double largest = magnitude;
    for (const auto* points : {&p.coarse.vertices, &p.node_image})
        for (const Vec3& x : *points) largest = std::max({largest, std::abs(x[0]), std::abs(x[1]), std::abs(x[2])});
    if (!(diagonal >= kSmallestDiagonal))
        return "the original surface is too small to measure distances in double precision (diagonal " +
               detail::format_number(diagonal) + ", limit " + detail::format_number(kSmallestDiagonal) + "): scale it";
    if (!(largest <= kLargestCoordinate))
        return "coordinates up to " + detail::format_number(largest) +
               " are too large to measure distances in double precision (limit " +
               detail::format_number(kLargestCoordinate) + ")";
    return std::nullopt;
}

// What the four directions share: the triangles of S0, of S and of phi's image (the
// pieces), which coarse triangle each piece belongs to, the pieces by the original
// triangle they map into, the closest-point searches on the three triangle sets, and the
// running totals of samples and spacing reached.
struct DistanceProblem {
    DistanceProblem(const Parametrization& param, double floor_level, double sample_spacing)
        : p(param),
          num_pieces(param.num_pieces()),
          num_original(param.original.num_triangles()),
          num_coarse(param.coarse.num_triangles()),
          floor(floor_level),
          spacing(sample_spacing),
          piece_coarse(static_cast<size_t>(num_pieces)),
          to_original(num_original, [this](int64_t t) { return original_corners(t); }),
          to_coarse(num_coarse, [this](int64_t t) { return coarse_corners(t); }),
          to_image(num_pieces, [this](int64_t q) { return image_corners(q); }) {
        for (int32_t t = 0; t < num_coarse; ++t)
            for (int64_t q = p.piece_offsets[t]; q < p.piece_offsets[t + 1]; ++q) piece_coarse[q] = t;
        // Pieces by the original triangle they map into (CSR).
        by_original_offsets.assign(static_cast<size_t>(num_original) + 1, 0);
        for (int32_t o : p.piece_original_triangle) ++by_original_offsets[static_cast<size_t>(o) + 1];
        for (int32_t o = 0; o < num_original; ++o) by_original_offsets[o + 1] += by_original_offsets[o];
        by_original.resize(static_cast<size_t>(num_pieces));
        std::vector<int64_t> fill(by_original_offsets.begin(), by_original_offsets.end() - 1);
        for (int64_t q = 0; q < num_pieces; ++q) by_original[fill[p.piece_original_triangle[q]]++] = q;
    }
    DistanceProblem(const DistanceProblem&) = delete;  // the searches hold `this`
    DistanceProblem& operator=(const DistanceProblem&) = delete;

    std::array<Vec3, 3> original_corners(int64_t t) const {
        const Tri& c = p.original.triangles[static_cast<size_t>(t)];
        return {p.original.vertices[c[0]], p.original.vertices[c[1]], p.original.vertices[c[2]]};
    }
    std::array<Vec3, 3> coarse_corners(int64_t t) const {
        const Tri& c = p.coarse.triangles[static_cast<size_t>(t)];
        return {p.coarse.vertices[c[0]], p.coarse.vertices[c[1]], p.coarse.vertices[c[2]]};
    }
    std::array<Vec3, 3> image_corners(int64_t q) const {
        const int64_t base = p.node_offsets[piece_coarse[q]];
        const Tri& c = p.pieces[static_cast<size_t>(q)];
        return {p.node_image[base + c[0]], p.node_image[base + c[1]], p.node_image[base + c[2]]};
    }
    // Samples triangle t (for_each_sample), counting them and the spacing reached.
    template <class Visit>
    void sample(const std::array<Vec3, 3>& t, Visit&& visit) {
        sample_indexed(t, [&](const Vec3& x, int64_t) { visit(x); });
    }
    // The same with each sample's index (for_each_indexed_sample).
    template <class Visit>
    void sample_indexed(const std::array<Vec3, 3>& t, Visit&& visit) {
        reached = std::max(reached, for_each_indexed_sample(t, spacing, [&](const Vec3& x, int64_t index) {
            ++samples;
            visit(x, index);
        }));
    }
    int64_t queries() const { return to_original.queries + to_coarse.queries + to_image.queries; }

    const Parametrization& p;
    const int64_t num_pieces;
    const int32_t num_original, num_coarse;
    const double floor;    // distances at rounding level, settled by their bounds
    const double spacing;  // requested sample spacing (absolute)
    std::vector<int32_t> piece_coarse;
    std::vector<int64_t> by_original_offsets, by_original;
    ClosestPoints to_original, to_coarse, to_image;
    double reached = 0.0;  // largest spacing of a sampled triangle
    int64_t samples = 0;
};

// image -> S0: samples on every piece's image, to S0. piece_bound[q] (out): the exact
// bound of piece q, the largest distance of its image's corners to its original triangle.
Extreme measure_image_to_original(DistanceProblem& d, std::vector<double>& piece_bound) {
    const Parametrization& p = d.p;
    Extreme best;
    piece_bound.assign(static_cast<size_t>(d.num_pieces), 0.0);
    std::vector<std::pair<double, int64_t>> keyed(static_cast<size_t>(d.num_pieces));
    for (int64_t q = 0; q < d.num_pieces; ++q) {
        const auto img = d.image_corners(q);
        const auto target = d.original_corners(p.piece_original_triangle[q]);
        double e = 0.0;
        for (const Vec3& x : img) e = std::max(e, triangle_distance(x, target));
        piece_bound[q] = e;
        keyed[q] = {e, q};
    }
    auto where = [&](int64_t q) { return Ids{{"coarse_triangle", d.piece_coarse[q]}, {"piece", q}}; };
    branch_and_bound(
        keyed, d.floor, best,
        where,
        [&](int64_t q) {
            const auto target = d.original_corners(p.piece_original_triangle[q]);
            d.sample(d.image_corners(q), [&](const Vec3& x) {
                const double u = triangle_distance(x, target);
                if (!best.could_raise(u)) return;
                const double dist =
                    u <= d.floor ? u : std::min(u, d.to_original.query(x, p.piece_original_triangle[q]).first);
                best.offer(dist, where(q));
            });
        });
    return best;
}

// The local upper bounds of a sample x of original triangle o: its distance to the
// images of the pieces that map into o, and to the coarse triangles those pieces belong
// to, with the nearest piece or coarse triangle.
class OriginalSampleBounds {
public:
    explicit OriginalSampleBounds(const DistanceProblem& d) : d_(d) {}
    // Selects the coarse triangles of the pieces in o, for coarse_bound.
    void select_coarse_candidates(int32_t o) {
        candidates_.clear();
        for (int64_t i = d_.by_original_offsets[o]; i < d_.by_original_offsets[o + 1]; ++i)
            candidates_.push_back(d_.piece_coarse[d_.by_original[i]]);
        std::sort(candidates_.begin(), candidates_.end());
        candidates_.erase(std::unique(candidates_.begin(), candidates_.end()), candidates_.end());
    }
    double image_bound(int32_t o, const Vec3& x, int64_t& nearest) const {
        double best = kInf;
        nearest = -1;
        for (int64_t i = d_.by_original_offsets[o]; i < d_.by_original_offsets[o + 1]; ++i) {
            const double e = triangle_distance(x, d_.image_corners(d_.by_original[i]));
            if (e < best) {
                best = e;
                nearest = d_.by_original[i];
            }
        }
        return best;
    }
    // \pre select_coarse_candidates(o) for the o that x samples.
    double coarse_bound(const Vec3& x, int64_t& nearest) const {
        double best = kInf;
        nearest = -1;
        for (int32_t c : candidates_) {
            const double e = triangle_distance(x, d_.coarse_corners(c));
            if (e < best) {
                best = e;
                nearest = c;
            }
        }
        return best;
    }

private:
    const DistanceProblem& d_;
    std::vector<int32_t> candidates_;
};

// Every original triangle keyed by the largest local bound of its samples, towards the
// image (keyed_image) and towards S (keyed_coarse): one sampling pass for both.
void key_original_triangles(DistanceProblem& d, OriginalSampleBounds& bounds, const Context& context,
                            std::vector<std::pair<double, int64_t>>& keyed_image,
                            std::vector<std::pair<double, int64_t>>& keyed_coarse) {
    const int32_t nt0 = d.num_original;
    keyed_image.assign(static_cast<size_t>(nt0), {});
    keyed_coarse.assign(static_cast<size_t>(nt0), {});
    for (int32_t o = 0; o < nt0; ++o) {
        if ((o & 0xffff) == 0) context.report(0.25 + 0.25 * o / nt0, "distance: S0 to phi's image and to S");
        bounds.select_coarse_candidates(o);
        double ki = 0.0, kc = 0.0;
        d.sample(d.original_corners(o), [&](const Vec3& x) {
            int64_t nearest;
            ki = std::max(ki, bounds.image_bound(o, x, nearest));
            kc = std::max(kc, bounds.coarse_bound(x, nearest));
        });
        keyed_image[o] = {ki, o};
        keyed_coarse[o] = {kc, o};
    }
}

// S0 -> image: the samples of the original triangles, to phi's image. (Not counted in
// samples: key_original_triangles visited them.)
Extreme measure_original_to_image(DistanceProblem& d, const OriginalSampleBounds& bounds,
                                  std::vector<std::pair<double, int64_t>>& keyed) {
    Extreme best;
    branch_and_bound(
        keyed, d.floor, best,
        [](int64_t o) { return Ids{{"original_triangle", o}}; },
        [&](int64_t o) {
            for_each_sample(d.original_corners(o), d.spacing, [&](const Vec3& x) {
                int64_t nearest;
                double dist = bounds.image_bound(static_cast<int32_t>(o), x, nearest);
                if (!best.could_raise(dist)) return;
                tighten(d.to_image, x, nearest, d.floor, dist, nearest);
                Ids where{{"original_triangle", o}};
                if (nearest >= 0) {
                    where.emplace_back("coarse_triangle", d.piece_coarse[nearest]);
                    where.emplace_back("piece", nearest);
                }
                best.offer(dist, std::move(where));
            });
        });
    return best;
}

// S0 -> S: the samples of the original triangles, to the coarse surface.
Extreme measure_original_to_coarse(DistanceProblem& d, OriginalSampleBounds& bounds,
                                   std::vector<std::pair<double, int64_t>>& keyed) {
    Extreme best;
    branch_and_bound(
        keyed, d.floor, best,
        [](int64_t o) { return Ids{{"original_triangle", o}}; },
        [&](int64_t o) {
            bounds.select_coarse_candidates(static_cast<int32_t>(o));
            for_each_sample(d.original_corners(o), d.spacing, [&](const Vec3& x) {
                int64_t nearest;
                double dist = bounds.coarse_bound(x, nearest);
                if (!best.could_raise(dist)) return;
                tighten(d.to_coarse, x, nearest, d.floor, dist, nearest);
                Ids where{{"original_triangle", o}};
                if (nearest >= 0) where.emplace_back("coarse_triangle", nearest);
                best.offer(dist, std::move(where));
            });
        });
    return best;
}

// The exact bound max |phi(x) - x| over the nodes (node_bound, out), and every coarse
// triangle keyed by its bound: the largest |phi(x) - x| of its nodes plus the largest
// piece_bound of its pieces.
std::vector<std::pair<double, int64_t>> key_coarse_triangles(const DistanceProblem& d,
                                                              const std::vector<double>& piece_bound,
                                                              Extreme& node_bound) {
    const Parametrization& p = d.p;
    std::vector<std::pair<double, int64_t>> keyed(static_cast<size_t>(d.num_coarse));
    for (int32_t t = 0; t < d.num_coarse; ++t) {
        const auto c = d.coarse_corners(t);
        double deviation = 0.0, image = 0.0;
        for (int64_t n = p.node_offsets[t]; n < p.node_offsets[t + 1]; ++n) {
            const double e = distance(barycentric_point(c[0], c[1], c[2], p.node_barycentric[n]), p.node_image[n]);
            deviation = std::max(deviation, e);
            if (node_bound.could_raise(e)) node_bound.offer(e, Ids{{"coarse_triangle", t}, {"node", n}});
        }
        for (int64_t q = p.piece_offsets[t]; q < p.piece_offsets[t + 1]; ++q) image = std::max(image, piece_bound[q]);
        keyed[t] = {deviation + image, t};
    }
    return keyed;
}

// The original triangle that phi maps each sample of coarse triangle t into (that of a
// piece containing the sample in the parameter triangle), or -1 where none was found, for
// the sample grid of n divisions (indices as for_each_indexed_sample): home (out).
// Each piece is scan-converted over the grid in barycentric coordinates (u, v) = n (b1, b2),
// column by column, so the cost is the pieces' columns plus the samples they cover, even
// for slivers. Samples on a shared side (up to kSlack grid units) go to the first piece;
// which one does not matter: any original triangle bounds a sample's distance to S0.
void locate_samples(const Parametrization& p, int32_t t, int n, std::vector<int32_t>& home) {
    constexpr double kSlack = 1e-9;
    const int64_t grid = sample_index(n, n, 0) + 1;  // the last grid point is (n, 0)
    home.assign(static_cast<size_t>(grid) + 1, -1);  // + the centroid
    const int64_t base = p.node_offsets[t];
    const double third = n / 3.0;
    for (int64_t q = p.piece_offsets[t]; q < p.piece_offsets[t + 1]; ++q) {
        const Tri& c = p.pieces[static_cast<size_t>(q)];
        std::array<double, 3> u, v;
        for (int k = 0; k < 3; ++k) {
            const Vec3& b = p.node_barycentric[static_cast<size_t>(base + c[k])];
            u[k] = n * b[1];
            v[k] = n * b[2];
        }
        if (!std::isfinite(u[0] + u[1] + u[2] + v[0] + v[1] + v[2])) continue;
        const int32_t original = p.piece_original_triangle[static_cast<size_t>(q)];
        // The centroid, by its barycentric coordinates in the piece.
        const double area = (u[1] - u[0]) * (v[2] - v[0]) - (u[2] - u[0]) * (v[1] - v[0]);
        if (home[static_cast<size_t>(grid)] < 0 && area != 0) {
            bool inside = true;
            for (int k = 0; k < 3; ++k) {
                const int a = (k + 1) % 3, b = (k + 2) % 3;
                const double lambda =
                    ((u[b] - u[a]) * (third - v[a]) - (third - u[a]) * (v[b] - v[a])) / area;
                inside = inside && lambda >= -kSlack;
            }
            if (inside) home[static_cast<size_t>(grid)] = original;
        }
        // (Clamped before the conversions: a damaged file may have any barycentrics.)
        const double lo = std::clamp(std::ceil(std::min({u[0], u[1], u[2]}) - kSlack), 0.0, n + 1.0);
        const double hi = std::clamp(std::floor(std::max({u[0], u[1], u[2]}) + kSlack), -1.0, double(n));
        for (int i = static_cast<int>(lo); i <= static_cast<int>(hi); ++i) {
            // The piece's extent along column u = i: where its sides cross the column.
            double v_lo = kInf, v_hi = -kInf;
            for (int k = 0; k < 3; ++k) {
                const int m = (k + 1) % 3;
                const double du = u[m] - u[k];
                if (std::abs(du) <= kSlack) {  // a side along the column (or a corner on it)
                    if (std::abs(u[k] - i) <= kSlack) {
                        v_lo = std::min({v_lo, v[k], v[m]});
                        v_hi = std::max({v_hi, v[k], v[m]});
                    }
                    continue;
                }
                const double s = (i - u[k]) / du;
                if (s < -kSlack || s > 1 + kSlack) continue;
                const double at = v[k] + std::clamp(s, 0.0, 1.0) * (v[m] - v[k]);
                v_lo = std::min(v_lo, at);
                v_hi = std::max(v_hi, at);
            }
            if (!(v_lo <= v_hi)) continue;
            const int j_lo = static_cast<int>(std::clamp(std::ceil(v_lo - kSlack), 0.0, n - i + 1.0));
            const int j_hi = static_cast<int>(std::clamp(std::floor(v_hi + kSlack), -1.0, double(n - i)));
            for (int j = j_lo; j <= j_hi; ++j) {
                int32_t& h = home[static_cast<size_t>(sample_index(n, i, j))];
                if (h < 0) h = original;
            }
        }
    }
}

// S -> S0: samples on every coarse triangle, to S0. A sample's first bound is its distance
// to the original triangle phi maps it into (locate_samples): wherever S is close to S0
// that triangle is about the nearest, so most samples fall below the maximum found
// without a tree query. Flat faces need this most: a coarse triangle of a CAD face covers
// hundreds of original triangles, beyond kMaxCandidates, and every one of its (up to
// 33 153) samples used to ask the tree (L-block 1 %: 980 000 queries, 6.7 s). Where the
// coarse triangle has few original ones, the samples the first bound does not settle
// take the least distance to all of them, as before.
Extreme measure_coarse_to_original(DistanceProblem& d, std::vector<std::pair<double, int64_t>>& keyed) {
    const Parametrization& p = d.p;
    Extreme best;
    std::vector<int32_t> originals, home;
    branch_and_bound(
        keyed, d.floor, best,
        [](int64_t t) { return Ids{{"coarse_triangle", t}}; },
        [&](int64_t t) {
            originals.clear();
            for (int64_t q = p.piece_offsets[t]; q < p.piece_offsets[t + 1]; ++q)
                originals.push_back(p.piece_original_triangle[q]);
            std::sort(originals.begin(), originals.end());
            originals.erase(std::unique(originals.begin(), originals.end()), originals.end());
            // A large coarse triangle covers hundreds of original ones: then the tree
            // is cheaper than the local bound.
            if (originals.size() > kMaxCandidates) originals.clear();
            const auto corners = d.coarse_corners(static_cast<int32_t>(t));
            locate_samples(p, static_cast<int32_t>(t), sample_divisions(corners, d.spacing), home);
            d.sample_indexed(corners, [&](const Vec3& x, int64_t index) {
                double dist = kInf;
                int64_t nearest = home[static_cast<size_t>(index)];
                if (nearest >= 0) {
                    dist = triangle_distance(x, d.original_corners(nearest));
                    if (!best.could_raise(dist)) return;
                }
                if (!originals.empty()) {  // (they include the home triangle)
                    dist = kInf;
                    nearest = -1;
                    for (int32_t o : originals) {
                        const double e = triangle_distance(x, d.original_corners(o));
                        if (e < dist) {
                            dist = e;
                            nearest = o;
                        }
                    }
                }
                if (!best.could_raise(dist)) return;
                int64_t hint = nearest;
                if (hint < 0 && p.piece_offsets[t] < p.piece_offsets[t + 1])
                    hint = p.piece_original_triangle[p.piece_offsets[t]];
                tighten(d.to_original, x, hint, d.floor, dist, nearest);
                Ids where{{"coarse_triangle", t}};
                if (nearest >= 0) where.emplace_back("original_triangle", nearest);
                best.offer(dist, std::move(where));
            });
        });
    return best;
}

// The four one-sided distances and the node bound (absolute).
struct Distances {
    Extreme image_to_original, original_to_image, coarse_to_original, original_to_coarse, node_bound;
};

// Fills r: the measures relative to the diagonal, the counts, the problems against
// options.max_error and the summary.
void report_distances(CheckResult& r, const DistanceProblem& d, const Distances& m, double diagonal,
                      const CheckOptions& options) {
    auto relative = [&](const Extreme& e, const std::string& name) {
        return WorstValue{name, e.value / diagonal, e.ids};
    };
    const WorstValue img_to = relative(m.image_to_original, "image_to_original");
    const WorstValue img_from = relative(m.original_to_image, "original_to_image");
    const WorstValue s_to = relative(m.coarse_to_original, "coarse_to_original");
    const WorstValue s_from = relative(m.original_to_coarse, "original_to_coarse");
    WorstValue image = img_to.value >= img_from.value ? img_to : img_from;
    image.name = "image_hausdorff";
    WorstValue coarse = s_to.value >= s_from.value ? s_to : s_from;
    coarse.name = "coarse_hausdorff";
    WorstValue bound = relative(m.node_bound, "coarse_to_original_bound");
    r.measures = {coarse, s_to, s_from, bound, image, img_to, img_from,
                  WorstValue{"sample_spacing", d.reached / diagonal, {}}};
    r.worst = coarse;
    r.add_count("coarse_triangles", d.num_coarse);
    r.add_count("original_triangles", d.num_original);
    r.add_count("pieces", d.num_pieces);
    r.add_count("samples", d.samples);
    r.add_count("closest_point_queries", d.queries());

    using detail::format_number;
    if (options.max_error) {
        const double limit = *options.max_error;
        if (!(image.value <= limit))
            r.add_problem({image.ids, "phi's image is " + format_number(image.value) +
                                          " of the diagonal away from S0 (" +
                                          (img_to.value >= img_from.value ? "image -> S0" : "S0 -> image") +
                                          "), more than the limit max_error = " + format_number(limit)},
                          options.max_problems);
        if (!(coarse.value <= limit))
            r.add_problem({coarse.ids, "the coarse surface is " + format_number(coarse.value) +
                                           " of the diagonal away from S0 (" +
                                           (s_to.value >= s_from.value ? "S -> S0" : "S0 -> S") +
                                           "), more than the limit max_error = " + format_number(limit) +
                                           " (exact bound of S -> S0: max |phi(x) - x| = " +
                                           format_number(bound.value) + ")"},
                          options.max_problems);
    }
    r.summary = "coarse surface within " + format_number(coarse.value) + " of the diagonal of S0 (S->S0 " +
                format_number(s_to.value) + ", S0->S " + format_number(s_from.value) + "; bound max|phi(x)-x| " +
                format_number(bound.value) + "), phi's image within " + format_number(image.value) +
                (options.max_error ? "; limit " + format_number(*options.max_error) : std::string()) + "; " +
                std::to_string(d.samples) + " samples, spacing " + format_number(d.reached / diagonal);
}

}  // namespace

CheckResult check_distance(const Parametrization& p, const CheckOptions& options, const Context& context) {
    CheckResult r;
    r.name = "distance";
    double diagonal = 0.0, magnitude = 0.0;
    if (auto why = why_not_measurable(p, options, diagonal, magnitude)) {
        detail::refuse(r, *why);
        return r;
    }
    DistanceProblem d(p, kFloor * (diagonal + magnitude), options.error_sample_spacing * diagonal);
    Distances m;

    context.report(0.0, "distance: phi's image to S0");
    std::vector<double> piece_bound;
    m.image_to_original = measure_image_to_original(d, piece_bound);

    context.report(0.25, "distance: S0 to phi's image and to S");
    OriginalSampleBounds bounds(d);
    std::vector<std::pair<double, int64_t>> keyed_image, keyed_coarse;
    key_original_triangles(d, bounds, context, keyed_image, keyed_coarse);
    m.original_to_image = measure_original_to_image(d, bounds, keyed_image);
    m.original_to_coarse = measure_original_to_coarse(d, bounds, keyed_coarse);

    context.report(0.75, "distance: S to S0");
    std::vector<std::pair<double, int64_t>> keyed_coarse_triangles = key_coarse_triangles(d, piece_bound, m.node_bound);
    m.coarse_to_original = measure_coarse_to_original(d, keyed_coarse_triangles);

    report_distances(r, d, m, diagonal, options);
    context.report(1.0, "distance");
    return r;
}

}  // namespace bpm
