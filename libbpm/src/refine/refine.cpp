// Refinement of the coarse surface through phi (Krause & Sander §1, §2.2.3): subdivide
// in parameter space, place every new vertex at phi of its parameter position.
//
// Uniform refinement is red refinement (1 -> 4 at edge midpoints) of every triangle,
// `levels` times. Adaptive refinement follows the classic red-green scheme (Bank,
// Sherman & Weiser 1983): red-refine triangles whose deviation from phi (exact, over the
// overlay with the pieces of phi: Refiner::error) exceeds the
// tolerance, red-refine further triangles until the mesh is 1-irregular (no triangle
// with two split edges, no split edge whose halves are split again), then close it
// with green bisections of the triangles that have exactly one split edge.
//
// All parameter positions are averages of parameter positions, i.e. dyadic fractions of
// the coarse corners: exact in double precision for any practical level, so a vertex on
// a coarse edge has an exactly zero barycentric coordinate, and the same vertex seen
// from the two coarse triangles of an edge has the same (permuted) coordinates.

#include "bpm/refine.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <unordered_map>

#include "bpm/check.h"
#include "bpm/errors.h"
#include "bpm/phi_evaluation.h"
#include "bpm/predicates.h"
#include "core/triangle_grid.h"
#include "core/barycentric_orientation.h"
#include "core/edge_key.h"
#include "core/number_text.h"
#include "phi/phi_layout.h"
#include "refine/planar_regions.h"

namespace bpm {

namespace {

using detail::edge_key;

struct RTri {
    int32_t coarse;
    std::array<int32_t, 3> v;
    std::array<Vec3, 3> b;
    int32_t level;
    double error = -1;  // max |flat - phi| over the triangle (Refiner::error), -1 = not yet computed
    // What adaptive refinement splits by (Refiner::need): error, or less on a planar
    // region; -1 = not yet computed, +infinity = split in any case.
    double need = -1;
};

inline Vec3 mid(const Vec3& a, const Vec3& b) { return {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])}; }

// The adaptive passes ("refine, hold back, measure"): which one is the best so far, and
// when to stop. A pass is better when its bound is below every earlier pass's, or equal to
// the best one's with fewer triangles above the tolerance: where phi folds at max_level the
// same triangles set the bound in every pass, and the passes still free the rest of the
// surface from held-back vertices (femur 1000 V at T = 0.0003: bound 0.006754 in passes
// 1-3 from triangles at level 8; 707, 295, 289 triangles above T, held back up to 0.0036,
// 0.0004, 0.0004; pass 1 was returned and the sampled distance was 0.0016). The passes
// stop after kMaxPasses, at the second pass in a row that is not better when it does not
// lower the number of triangles above the tolerance either, or when that number passes 8x
// the first pass's (at least 64): refining is then not helping. Why: femur 10 % at
// T = 0.001 had 813, 2247, 6059 above T in passes 1-3, the bound rising; at T = 0.0003 a
// pass took minutes, 238 remedy rounds in the first. (With the input needle bpm-simplify
// now removes, femur at T = 0.003 went 1, 1, 1, 1, 2, 2, 4, 2 above T with bounds barely
// moving and met T after 9 passes; stopping at the first pass that was not better stopped
// it after the second. Stopping after two passes without a smaller bound instead stopped
// it at 0.00313.) Why the second pass in a row, not the first: a pass refines around the
// held-back vertices and the remedy may then hold back more, which the next pass undoes
// (femur 10 %, Morton-ordered coarse surface, T = 0.003: bound 0.00374, 0.00376, then
// 0.003 met, with 4, 7, 0 triangles above T; stopping at the second pass returned the
// first, unproved). Over the 30 runs of bench/adaptive.py only that one changed.
class PassHistory {
public:
    // Records the next pass's bound and number of triangles above the tolerance; returns
    // whether it is the best pass so far.
    bool record(double bound, int64_t above) {
        ++passes_;
        const bool better = passes_ == 1 || bound < best_bound_ || (bound == best_bound_ && above < best_above_);
        if (better) best_bound_ = bound, best_above_ = above;
        worse_ = better ? 0 : worse_ + 1;
        if (passes_ == 1) first_above_ = above;
        diverging_ = worse_ >= 2 && above >= previous_above_;  // two passes not better in a row
        previous_above_ = above;
        exploding_ = above > 8 * std::max<int64_t>(first_above_, 8);
        return better;
    }
    // No further pass after the one recorded last.
    bool stop() const { return passes_ >= kMaxPasses || diverging_ || exploding_; }
    // The best pass is an earlier one than the last (then that one is returned).
    bool best_is_earlier() const { return passes_ > 1 && worse_ > 0; }
    int32_t passes() const { return passes_; }

    // Each pass splits at least one triangle one level deeper; the cap only bounds the
    // time on a pathological input.
    static constexpr int32_t kMaxPasses = 12;

private:
    int32_t passes_ = 0;
    int32_t worse_ = 0;  // passes since the best one
    double best_bound_ = 0;
    int64_t best_above_ = 0, first_above_ = 0, previous_above_ = 0;
    bool diverging_ = false, exploding_ = false;
};

// The refined surface's triangles in a grid (core/triangle_grid.h) for the release step:
// cells of the triangles' mean box extent, the lattice over the box of the vertices now
// and at phi (a held-back vertex only moves between its place and phi; the grid clamps
// what lies outside, so any box is safe to ask for).
detail::TriangleGrid triangle_grid_of(const Surface& s, const std::vector<Vec3>& at_phi) {
    Vec3 lo = s.vertices.empty() ? Vec3{0, 0, 0} : s.vertices[0], hi = lo;
    for (const std::vector<Vec3>* points : {&s.vertices, &at_phi})
        for (const Vec3& p : *points)
            for (size_t k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
    double extents = 0;
    for (const Tri& c : s.triangles) {
        double extent = 0;
        for (size_t k = 0; k < 3; ++k) {
            const double a = s.vertices[size_t(c[0])][k], b = s.vertices[size_t(c[1])][k], e = s.vertices[size_t(c[2])][k];
            extent = std::max(extent, std::max({a, b, e}) - std::min({a, b, e}));
        }
        extents += extent;
    }
    const double cell = s.triangles.empty() ? 0.0 : extents / double(s.triangles.size());
    detail::TriangleGrid grid(cell > 0 ? cell : 1.0, detail::TriangleGrid::Frame::of_box(lo, hi));
    std::vector<int32_t> ids(s.triangles.size());
    std::iota(ids.begin(), ids.end(), 0);
    grid.insert_all(ids, s.triangles, s.vertices);
    return grid;
}

// Takes triangle t out of `grid`, filed with its corners where they were when it went in:
// those in `moving` at `before` (same order), the others where they are.
void grid_remove(detail::TriangleGrid& grid, const Surface& s, int32_t t, const std::vector<int32_t>& moving,
                 const std::vector<Vec3>& before) {
    Vec3 x[3];
    for (size_t k = 0; k < 3; ++k) {
        const int32_t v = s.triangles[size_t(t)][k];
        const auto it = std::lower_bound(moving.begin(), moving.end(), v);
        x[k] = it != moving.end() && *it == v ? before[size_t(it - moving.begin())] : s.vertices[size_t(v)];
    }
    grid.remove(t, x[0], x[1], x[2]);
}

class Refiner {
public:
    Refiner(const Parametrization& p, const PhiEvaluator& phi, RefinedSurface& out)
        : p_(p), phi_(phi), out_(out) {
        diagonal_ = bounding_box_diagonal(p.original);
        if (!(diagonal_ > 0)) diagonal_ = 1;
        planar_ = detail::planar_regions(p, diagonal_);
    }

    // Progress, monotone over the whole call: within a pass, refining takes the first half
    // and the intersection remedy (any number of rounds) the second; the adaptive passes
    // (pass_ >= 1, at most PassHistory::kMaxPasses) share the whole range. Before, every
    // pass restarted "refining" at 0 % and the remedy's rounds (minutes on polyhedral
    // inputs, whose refined vertices fold in the faces' planes) reported nothing.
    void progress(const Context& context, double within_pass, const std::string& what) const {
        if (pass_ < 1) {
            context.report(within_pass, what);
            return;
        }
        context.report((pass_ - 1 + within_pass) / PassHistory::kMaxPasses, "pass " + std::to_string(pass_) + ": " + what);
    }

    void init() {
        const Surface& c = p_.coarse;
        out_.surface.vertices = c.vertices;  // coarse vertices keep their positions exactly
        const size_t nv = c.vertices.size();
        out_.vertex_coarse_triangle.assign(nv, -1);
        out_.vertex_barycentric.assign(nv, Vec3{0, 0, 0});
        for (int32_t t = 0; t < c.num_triangles(); ++t) {
            RTri r;
            r.coarse = t;
            r.level = 0;
            for (int k = 0; k < 3; ++k) {
                r.v[size_t(k)] = c.triangles[size_t(t)][size_t(k)];
                Vec3 e{0, 0, 0};
                e[size_t(k)] = 1;
                r.b[size_t(k)] = e;
                if (out_.vertex_coarse_triangle[size_t(r.v[size_t(k)])] < 0) {
                    out_.vertex_coarse_triangle[size_t(r.v[size_t(k)])] = t;
                    out_.vertex_barycentric[size_t(r.v[size_t(k)])] = e;
                }
            }
            tris_.push_back(r);
        }
    }

    int32_t midpoint(const RTri& r, int k, bool create) {
        const int32_t a = r.v[size_t(k)], b = r.v[size_t((k + 1) % 3)];
        auto it = mids_.find(edge_key(a, b));
        if (it != mids_.end()) return it->second;
        if (!create) return -1;
        const Vec3 bm = mid(r.b[size_t(k)], r.b[size_t((k + 1) % 3)]);
        const int32_t id = int32_t(out_.surface.vertices.size());
        out_.surface.vertices.push_back(phi_.evaluate(r.coarse, bm).position);
        out_.vertex_coarse_triangle.push_back(r.coarse);
        out_.vertex_barycentric.push_back(bm);
        mids_.emplace(edge_key(a, b), id);
        parents_.emplace_back(a, b);
        return id;
    }

    // Replaces tris_[i] by its first red child and appends the other three.
    void red(size_t i) {
        const RTri r = tris_[i];
        std::array<int32_t, 3> m;
        std::array<Vec3, 3> bm;
        for (int k = 0; k < 3; ++k) {
            m[size_t(k)] = midpoint(r, k, true);
            bm[size_t(k)] = mid(r.b[size_t(k)], r.b[size_t((k + 1) % 3)]);
        }
        auto child = [&](int32_t a, int32_t b, int32_t c, const Vec3& ba, const Vec3& bb, const Vec3& bc) {
            RTri x;
            x.coarse = r.coarse;
            x.v = {a, b, c};
            x.b = {ba, bb, bc};
            x.level = r.level + 1;
            return x;
        };
        tris_[i] = child(r.v[0], m[0], m[2], r.b[0], bm[0], bm[2]);
        tris_.push_back(child(m[0], r.v[1], m[1], bm[0], r.b[1], bm[1]));
        tris_.push_back(child(m[2], m[1], r.v[2], bm[2], bm[1], r.b[2]));
        tris_.push_back(child(m[0], m[1], m[2], bm[0], bm[1], bm[2]));
    }

    // Number of split edges of a triangle; sets `deep` if a half of a split edge is split again.
    int split_edges(const RTri& r, bool& deep, int& which) const {
        int count = 0;
        deep = false;
        for (int k = 0; k < 3; ++k) {
            const int32_t a = r.v[size_t(k)], b = r.v[size_t((k + 1) % 3)];
            auto it = mids_.find(edge_key(a, b));
            if (it == mids_.end()) continue;
            ++count;
            which = k;
            if (mids_.count(edge_key(a, it->second)) || mids_.count(edge_key(it->second, b))) deep = true;
        }
        return count;
    }

    // Red-refines until 1-irregular.
    void close_red() {
        for (bool changed = true; changed;) {
            changed = false;
            const size_t n = tris_.size();
            for (size_t i = 0; i < n; ++i) {
                bool deep;
                int which;
                const int count = split_edges(tris_[i], deep, which);
                if (count >= 2 || deep) {
                    red(i);
                    changed = true;
                }
            }
        }
    }

    // `origin` (if given, one entry per triangle) gets the origin of each new green half.
    void close_green(std::vector<size_t>* origin = nullptr) {
        const size_t n = tris_.size();
        for (size_t i = 0; i < n; ++i) {
            bool deep;
            int k = -1;
            if (split_edges(tris_[i], deep, k) != 1) continue;
            const RTri r = tris_[i];
            RTri a, b;
            green_halves(r, k, midpoint(r, k, false), a, b);
            a.error = b.error = a.need = b.need = -1;
            tris_[i] = a;
            tris_.push_back(b);
            if (origin) origin->push_back((*origin)[i]);
        }
    }

    // Largest need (what adaptive refinement splits by) of the two green halves of r
    // split at edge k.
    double green_error(const RTri& r, int k) const {
        RTri a, b;
        green_halves(r, k, mids_.at(edge_key(r.v[size_t(k)], r.v[size_t((k + 1) % 3)])), a, b);
        a.error = b.error = a.need = b.need = -1;
        return std::max(need(a), need(b));
    }

    // The two halves of r split at the midpoint m (vertex id) of its local edge k.
    static void green_halves(const RTri& r, int k, int32_t m, RTri& a, RTri& b) {
        const Vec3 bm = mid(r.b[size_t(k)], r.b[size_t((k + 1) % 3)]);
        const size_t k0 = size_t(k), k1 = size_t((k + 1) % 3), k2 = size_t((k + 2) % 3);
        a = r;
        b = r;
        a.v = {r.v[k0], m, r.v[k2]};
        a.b = {r.b[k0], bm, r.b[k2]};
        b.v = {m, r.v[k1], r.v[k2]};
        b.b = {bm, r.b[k1], r.b[k2]};
    }

    // Largest distance between the flat triangle r and phi over r, relative to the
    // diagonal: an upper bound of the two-sided Hausdorff distance between r and its image
    // on S0 (x -> phi(x) pairs every point of r with one of phi(r)). Both maps are affine
    // on every cell of the overlay of r with the pieces of phi, so the largest distance is
    // at a corner of a cell: a corner of r, a node of phi in r, or a point where a piece
    // edge crosses an edge of r. All of them are visited (nodes and crossings within
    // rounding of r too, which can only raise the value). Not sampled: no feature of S0
    // between sample points is missed.
    // With `only_edge` (0..2, an edge of r on an edge of its coarse triangle): the same
    // maximum over that edge alone. Along a coarse edge phi's breakpoints are its nodes
    // on the edge (exactly 0 at the opposite coarse corner), so its two corners and those
    // nodes are visited.
    double error(const RTri& r, int only_edge = -1) const {
        const auto& x = out_.surface.vertices;
        const Vec3 X[3] = {x[size_t(r.v[0])], x[size_t(r.v[1])], x[size_t(r.v[2])]};
        // Barycentric coordinates in r of a point given in the coarse triangle, in the (b1, b2) plane.
        const double u1 = r.b[1][1] - r.b[0][1], u2 = r.b[1][2] - r.b[0][2];
        const double v1 = r.b[2][1] - r.b[0][1], v2 = r.b[2][2] - r.b[0][2];
        const double det = u1 * v2 - u2 * v1;
        auto in_r = [&](const Vec3& b) {
            const double w1 = b[1] - r.b[0][1], w2 = b[2] - r.b[0][2];
            const double l1 = (w1 * v2 - w2 * v1) / det, l2 = (u1 * w2 - u2 * w1) / det;
            return Vec3{1.0 - l1 - l2, l1, l2};
        };
        double worst = 0;
        auto visit = [&](const Vec3& b, const Vec3& image) {
            const Vec3 l = in_r(b);
            worst = std::max(worst, distance(l[0] * X[0] + l[1] * X[1] + l[2] * X[2], image));
        };
        constexpr double kSlack = 1e-12;  // barycentric units: rounding of stored node positions
        if (only_edge >= 0) {
            const size_t k0 = size_t(only_edge), k1 = size_t((only_edge + 1) % 3);
            const int z = coarse_zero(r, only_edge);
            visit(r.b[k0], phi_.evaluate(r.coarse, r.b[k0]).position);
            visit(r.b[k1], phi_.evaluate(r.coarse, r.b[k1]).position);
            const size_t t = size_t(r.coarse);
            for (int64_t g = p_.node_offsets[t]; g < p_.node_offsets[t + 1]; ++g) {
                const Vec3& b = p_.node_barycentric[size_t(g)];
                if (b[size_t(z)] != 0) continue;
                const Vec3 l = in_r(b);
                if (l[0] >= -kSlack && l[1] >= -kSlack && l[2] >= -kSlack) visit(b, p_.node_image[size_t(g)]);
            }
            return worst / diagonal_;
        }
        for (int k = 0; k < 3; ++k) visit(r.b[size_t(k)], phi_.evaluate(r.coarse, r.b[size_t(k)]).position);
        const double lo1 = std::min({r.b[0][1], r.b[1][1], r.b[2][1]}) - kSlack;
        const double hi1 = std::max({r.b[0][1], r.b[1][1], r.b[2][1]}) + kSlack;
        const double lo2 = std::min({r.b[0][2], r.b[1][2], r.b[2][2]}) - kSlack;
        const double hi2 = std::max({r.b[0][2], r.b[1][2], r.b[2][2]}) + kSlack;
        const size_t t = size_t(r.coarse);
        const int64_t n0 = p_.node_offsets[t], n1 = p_.node_offsets[t + 1];
        for (int64_t g = n0; g < n1; ++g) {
            const Vec3& b = p_.node_barycentric[size_t(g)];
            if (b[1] < lo1 || b[1] > hi1 || b[2] < lo2 || b[2] > hi2) continue;
            const Vec3 l = in_r(b);
            if (l[0] >= -kSlack && l[1] >= -kSlack && l[2] >= -kSlack) visit(b, p_.node_image[size_t(g)]);
        }
        for (int64_t q = p_.piece_offsets[t]; q < p_.piece_offsets[t + 1]; ++q) {
            const Tri& pc = p_.pieces[size_t(q)];
            const Vec3* N[3];
            for (int k = 0; k < 3; ++k) N[k] = &p_.node_barycentric[size_t(n0 + pc[size_t(k)])];
            if (std::max({(*N[0])[1], (*N[1])[1], (*N[2])[1]}) < lo1 || std::min({(*N[0])[1], (*N[1])[1], (*N[2])[1]}) > hi1 ||
                std::max({(*N[0])[2], (*N[1])[2], (*N[2])[2]}) < lo2 || std::min({(*N[0])[2], (*N[1])[2], (*N[2])[2]}) > hi2)
                continue;
            for (int k = 0; k < 3; ++k) {
                const Vec3& A = *N[k];
                const Vec3& B = *N[(k + 1) % 3];
                const double d1 = B[1] - A[1], d2 = B[2] - A[2];
                for (int j = 0; j < 3; ++j) {
                    const Vec3& C = r.b[size_t(j)];
                    const Vec3& D = r.b[size_t((j + 1) % 3)];
                    const double e1 = D[1] - C[1], e2 = D[2] - C[2];
                    const double den = d1 * e2 - d2 * e1;
                    if (den == 0) continue;  // parallel: its ends are nodes or corners, visited
                    const double c1 = C[1] - A[1], c2 = C[2] - A[2];
                    const double s = (c1 * e2 - c2 * e1) / den;  // along the piece edge
                    const double w = (c1 * d2 - c2 * d1) / den;  // along the edge of r
                    if (s < -kSlack || s > 1 + kSlack || w < -kSlack || w > 1 + kSlack) continue;
                    const double sc = std::min(1.0, std::max(0.0, s));
                    const Vec3 b = A + sc * (B - A);
                    // A piece edge on the same line as the edge of r (both on a coarse
                    // edge) is parallel, but `den` rounds to ~1e-17 instead of 0 and s is
                    // then noise: b may lie anywhere on the piece edge, outside r, where the
                    // flat map extrapolates far off (elephant 10 % after bpm-smooth: a bound
                    // of 5.74e-3 where the largest distance is 1.16e-3). Points outside r
                    // are not corners of its cells; on such a shared line the cells' corners
                    // are nodes and corners of r, visited above.
                    const Vec3 lb = in_r(b);
                    if (lb[0] < -kSlack || lb[1] < -kSlack || lb[2] < -kSlack) continue;
                    const Vec3& IA = p_.node_image[size_t(n0 + pc[size_t(k)])];
                    const Vec3& IB = p_.node_image[size_t(n0 + pc[size_t((k + 1) % 3)])];
                    visit(b, IA + sc * (IB - IA));
                }
            }
        }
        return worst / diagonal_;
    }

    // error(r) with every vertex at phi, cached in r.error (vertices are at phi until
    // hold_back moves them).
    double phi_error(RTri& r) const {
        if (r.error < 0) r.error = error(r);
        return r.error;
    }

    // The barycentric coordinate of the coarse triangle that is 0 at both corners of edge
    // i of r (the edge then lies on the coarse edge opposite that corner), or -1. Exact:
    // parameter positions are dyadic fractions, 0 on a coarse edge.
    static int coarse_zero(const RTri& r, int i) {
        const Vec3& a = r.b[size_t(i)];
        const Vec3& b = r.b[size_t((i + 1) % 3)];
        for (int z = 0; z < 3; ++z)
            if (a[size_t(z)] == 0 && b[size_t(z)] == 0) return z;
        return -1;
    }
    // The local edge of the coarse triangle (corners k, k + 1) that edge i of r lies on, or -1.
    static int coarse_edge(const RTri& r, int i) {
        const int z = coarse_zero(r, i);
        return z < 0 ? -1 : (z + 1) % 3;
    }

    // PLANAR REGIONS. On a planar region M (detail::planar_regions: coarse triangles that
    // lie, with phi's image of them, in one plane P) phi may move points within P, and
    // max |flat - phi| counts that drift although the refined surface and S0 coincide
    // there. What the Hausdorff distance needs is less: R = union of the refined triangles
    // f(rho), S0 = union of phi(rho) (phi is onto), so H(R, S0) <= max over parts of the
    // parameter surface of max(sup d(f(x), S0), sup d(phi(x), R)), and M may be one part.
    // Its value, beta_M (region_bounds), relative to the diagonal:
    //   beta_M = e_f + e_phi + max(e_f, e_phi) + max over boundary edges e of M of c_e,
    // e_f / e_phi the largest offset (along the dropped axis, vertical_offset) of the
    // refined vertices / phi's node images from P, c_e as below. Proof. Project along the
    // axis P is least steep in (psi drops a coordinate: exact); F = psi o f and G = psi o
    // phi are piecewise linear maps of M into the plane. If every refined triangle of M
    // projects with one sign s (exact orient2d) and every piece of phi with one sign t,
    // then for u off the images of edges deg(F, u) = s * #(triangles covering u), nonzero
    // exactly on F(M), and deg(G, u) = t * #(pieces covering u), nonzero exactly on G(M).
    // Both degrees are winding numbers of the images of the boundary chain of M (the sum
    // of the coarse triangles' boundaries: an edge shared by two consistently oriented
    // triangles of M cancels; the refinement is conforming and phi continuous, so the
    // maps agree on each edge from both sides). (a) A point a of f(M) whose projection u
    // is in G(M) has a point b of phi(M) above or below it: |a - b| <= e_f + e_phi.
    // Otherwise deg(F, u) != 0 = deg(G, u), so the straight homotopy (1 - l) F + l G of
    // the boundary chain passes through u: u = psi(q), q = (1 - l) f(x) + l phi(x) for a
    // boundary point x, and |a - q| <= e_f + max(e_f, e_phi) (the offset is affine), so
    // d(a, S0) <= e_f + max(e_f, e_phi) + d(q, S0). (b) Symmetrically for b in phi(M)
    // with d(q, R). d(q, S0) and d(q, R) are at most c_e, the smaller of: max |f - phi|
    // over e (q lies between f(x) and phi(x)); and 2 eta + o, eta the largest distance of
    // phi's nodes and the refined vertices on e from the line through e's corners, o how
    // far they overshoot the segment (phi(e) and f(e), paths between the same corners,
    // pass within eta of every point of the segment, and q is within eta and o of it).
    // Non-generic points follow by continuity. So no tangential drift counts, only the
    // offsets from P and the boundary; on a box face (straight edges on the box's edges)
    // beta is rounding. If a sign condition fails, M gets no bound (plain error(r)).
    // The bound of a triangle of M is min(error(r), beta_M): both are proven.

    // What adaptive refinement splits by: error(r) with every vertex at phi, or on a
    // planar region the part of beta_M that r can lower (its offsets from the plane and
    // c_e on its edges on the region's boundary), whichever is smaller. Cached in r.need.
    double need(RTri& r) const {
        if (r.need >= 0) return r.need;
        double e = phi_error(r);
        const int32_t g = planar_.region[size_t(r.coarse)];
        if (g >= 0) {
            double planar = 3 * planar_.regions[size_t(g)].phi_offset / diagonal_;
            for (int i = 0; i < 3; ++i) {
                const int k = coarse_edge(r, i);
                if (k < 0 || !planar_.boundary[size_t(r.coarse)][size_t(k)]) continue;
                const detail::LineDeviation& line = planar_.phi_line[size_t(r.coarse)][size_t(k)];
                planar = std::max(planar, std::min(error(r, i), (2 * line.off + line.overshoot) / diagonal_));
            }
            e = std::min(e, planar);
        }
        return r.need = e;
    }

    // beta_M of every planar region with the vertices where they are (see PLANAR
    // REGIONS), relative to the diagonal; +infinity where a sign condition fails.
    std::vector<double> region_bounds() const {
        const size_t nr = planar_.regions.size();
        std::vector<double> beta(nr, std::numeric_limits<double>::infinity());
        if (nr == 0) return beta;
        const auto& x = out_.surface.vertices;
        const auto& cv = p_.coarse.vertices;
        std::vector<double> offset(nr, 0.0);
        std::vector<int> sign(nr, 0);
        std::vector<uint8_t> failed(nr, 0);
        struct EdgeBound {
            double flat_phi = 0;  // max |f - phi| over the edge (absolute)
            detail::LineDeviation line;  // the refined vertices on it
        };
        std::vector<std::array<EdgeBound, 3>> edges(p_.coarse.triangles.size());
        for (const RTri& r : tris_) {
            const int32_t g = planar_.region[size_t(r.coarse)];
            if (g < 0 || failed[size_t(g)]) continue;
            const detail::PlanarRegion& region = planar_.regions[size_t(g)];
            using Regions = detail::PlanarRegions;
            const Vec3 X[3] = {x[size_t(r.v[0])], x[size_t(r.v[1])], x[size_t(r.v[2])]};
            for (const Vec3& v : X)
                offset[size_t(g)] = std::max(offset[size_t(g)], std::abs(Regions::vertical_offset(region, v)));
            const int s = orient2d(Regions::project(region, X[0]), Regions::project(region, X[1]),
                                   Regions::project(region, X[2])) *
                          detail::orient_barycentric(r.b[0], r.b[1], r.b[2]);
            if (s == 0 || (sign[size_t(g)] != 0 && s != sign[size_t(g)])) {
                failed[size_t(g)] = 1;
                continue;
            }
            sign[size_t(g)] = s;
            for (int i = 0; i < 3; ++i) {
                const int k = coarse_edge(r, i);
                if (k < 0 || !planar_.boundary[size_t(r.coarse)][size_t(k)]) continue;
                EdgeBound& e = edges[size_t(r.coarse)][size_t(k)];
                e.flat_phi = std::max(e.flat_phi, error(r, i) * diagonal_);
                const Tri& c = p_.coarse.triangles[size_t(r.coarse)];
                const Vec3& a = cv[size_t(c[size_t(k)])];
                const Vec3& b = cv[size_t(c[size_t((k + 1) % 3)])];
                e.line.add(a, b, X[i]);
                e.line.add(a, b, X[(i + 1) % 3]);
            }
        }
        std::vector<double> chain(nr, 0.0);  // max c_e over the boundary edges
        for (size_t t = 0; t < p_.coarse.triangles.size(); ++t) {
            const int32_t g = planar_.region[t];
            if (g < 0) continue;
            for (size_t k = 0; k < 3; ++k) {
                if (!planar_.boundary[t][k]) continue;
                const EdgeBound& e = edges[t][k];
                const detail::LineDeviation& phi_line = planar_.phi_line[t][k];
                const double eta = std::max(e.line.off, phi_line.off);
                const double along = 2 * eta + std::max(e.line.overshoot, phi_line.overshoot);
                chain[size_t(g)] = std::max(chain[size_t(g)], std::min(e.flat_phi, along));
            }
        }
        for (size_t g = 0; g < nr; ++g) {
            if (failed[g]) continue;
            const double ef = offset[g], ep = planar_.regions[g].phi_offset;
            beta[g] = (ef + ep + std::max(ef, ep) + chain[g]) / diagonal_;
        }
        return beta;
    }

    // Uniform: every triangle below `max_level` is red-refined, level by level.
    void refine_uniform(int max_level, const Context& context) {
        for (int round = 0; round < max_level; ++round) {
            progress(context, 0.5 * double(round) / std::max(1, max_level), "refining");
            std::vector<size_t> marked;
            for (size_t i = 0; i < tris_.size(); ++i)
                if (tris_[i].level < max_level) marked.push_back(i);
            if (marked.empty()) break;
            for (size_t i : marked) red(i);
            context.debug("level " + std::to_string(round + 1) + ": " + std::to_string(marked.size()) +
                          " triangles split, " + std::to_string(tris_.size()) + " triangles");
        }
    }

    // The triangles below max_level whose need (error at phi, less on planar regions)
    // exceeds the tolerance.
    std::vector<size_t> above_tolerance(const RefineOptions& options) {
        std::vector<size_t> marked;
        for (size_t i = 0; i < tris_.size(); ++i)
            if (tris_[i].level < options.max_level && !(need(tris_[i]) <= options.tolerance)) marked.push_back(i);
        return marked;
    }

    // Adaptive, up to the green closure: red-refines every triangle below max_level whose
    // deviation (cached in RTri::error; +infinity = split in any case) exceeds the
    // tolerance, keeps the mesh 1-irregular, and red-refines the parent of a green half
    // that would exceed it.
    void refine_adaptive(const RefineOptions& options, const Context& context) {
        const int max_level = options.max_level;
        for (int round = 0; round < max_level; ++round) {
            progress(context, 0.5 * double(round) / std::max(1, max_level), "refining");
            const std::vector<size_t> marked = above_tolerance(options);
            if (marked.empty()) break;
            for (size_t i : marked) red(i);
            close_red();
            context.debug("level " + std::to_string(round + 1) + ": " + std::to_string(marked.size()) +
                          " triangles split, " + std::to_string(tris_.size()) + " triangles");
        }
        // A green half may still deviate more than the tolerance: then its parent is
        // red-refined instead, and the loop continues until every green half is fine.
        for (bool again = true; again;) {
            again = false;
            const size_t n = tris_.size();
            for (size_t i = 0; i < n; ++i) {
                RTri& r = tris_[i];
                if (r.level >= max_level) continue;
                bool deep;
                int k = -1;
                if (split_edges(r, deep, k) != 1) continue;
                if (green_error(r, k) <= options.tolerance) continue;
                red(i);
                again = true;
            }
            if (!again) break;
            close_red();
            // New red triangles may need splitting themselves.
            for (std::vector<size_t> marked = above_tolerance(options); !marked.empty();
                 marked = above_tolerance(options)) {
                for (size_t i : marked) red(i);
                close_red();
            }
        }
    }

    // The refined surface of tris_ (vertex positions as they are), per-triangle data,
    // and the original triangle of every vertex.
    void emit(RefineResult& result) {
        Surface& s = out_.surface;
        s.triangles.clear();
        s.patches.clear();
        out_.triangle_coarse.clear();
        out_.triangle_barycentric.clear();
        out_.triangle_level.clear();
        result.max_level = 0;
        for (const RTri& r : tris_) {
            s.triangles.push_back(Tri{r.v[0], r.v[1], r.v[2]});
            s.patches.push_back(p_.coarse.patches[size_t(r.coarse)]);
            out_.triangle_coarse.push_back(r.coarse);
            out_.triangle_barycentric.push_back(r.b);
            out_.triangle_level.push_back(r.level);
            result.max_level = std::max(result.max_level, r.level);
        }
        const size_t nv = s.vertices.size();
        out_.vertex_original_triangle.resize(nv);
        out_.vertex_original_barycentric.resize(nv);
        for (size_t v = 0; v < nv; ++v) {
            const PhiSample sample = phi_.evaluate(out_.vertex_coarse_triangle[v], out_.vertex_barycentric[v]);
            out_.vertex_original_triangle[v] = sample.original_triangle;
            out_.vertex_original_barycentric[v] = sample.original_barycentric;
        }
        result.vertices = int64_t(nv);
        result.triangles = int64_t(s.triangles.size());
        out_.vertex_phi_fraction.assign(nv, 1.0);
        moved_.assign(nv, 0);
    }

    RefineResult run(const RefineOptions& options, const Context& context) {
        init();
        RefineResult result;
        result.coarse_triangles = int64_t(tris_.size());
        if (options.levels >= 0) {
            refine_uniform(options.levels, context);
            emit(result);
            for (RTri& r : tris_) result.max_estimated_error = std::max(result.max_estimated_error, phi_error(r));
            if (options.prevent_intersections) hold_back(result, context);
            bound(result, nullptr);
            return result;
        }
        // Adaptive. Held-back vertices move the flat triangles around them away from phi,
        // so the deviation is measured again with the vertices where they end up; a
        // triangle that then exceeds the tolerance is refined further (its pieces of S0
        // are resolved by smaller triangles, whose new vertices at phi need less holding
        // back or none), and the remedy runs again on the finer surface, until every
        // triangle is within the tolerance or at max_level.
        // A pass can also make it worse (the new vertices at phi intersect too, as near a
        // fold of phi, a sharp fold of S0 or where S0 nearly touches itself): the best pass
        // is returned; PassHistory says which and when to stop.
        RefinedSurface best_out;
        RefineResult best;
        PassHistory history;
        for (;;) {
            pass_ = history.passes() + 1;
            refine_adaptive(options, context);
            // Green closure, remembering which triangle of the 1-irregular mesh each comes from.
            const std::vector<RTri> irregular = tris_;
            std::vector<size_t> origin(tris_.size());
            for (size_t i = 0; i < origin.size(); ++i) origin[i] = i;
            close_green(&origin);
            emit(result);
            result.max_estimated_error = 0;
            for (RTri& r : tris_) result.max_estimated_error = std::max(result.max_estimated_error, phi_error(r));
            const std::vector<Vec3> at_phi = out_.surface.vertices;
            result.held_back_vertices = 0;
            result.max_held_back = 0;
            result.remedy_rounds = 0;
            if (options.prevent_intersections) hold_back(result, context);
            std::vector<size_t> split;
            bound(result, &split, &options, &origin);
            // The next pass splits what the remedy left above the tolerance (`split`, as
            // before release): releasing first and splitting less made femur 10 % at
            // T = 0.0003 worse in pass 2 (bound 2.3e-3 -> 3.3e-3) and stopped the passes.
            if (options.prevent_intersections && release(options.tolerance * diagonal_, context) > 0) {
                count_held_back(result);
                bound(result, nullptr, &options, &origin);
            }
            context.debug("refine: pass " + std::to_string(history.passes() + 1) + ": bound " +
                          detail::three_digit_text(result.hausdorff_bound) + ", " +
                          std::to_string(result.triangles_above_tolerance) + " triangles above the tolerance (" +
                          std::to_string(result.triangles_at_max_level_above_tolerance) + " at max_level), " +
                          std::to_string(result.held_back_vertices) + " vertices held back up to " +
                          detail::three_digit_text(result.max_held_back) + ", " + std::to_string(result.triangles) + " triangles");
            const bool better = history.record(result.hausdorff_bound, result.triangles_above_tolerance);
            if (split.empty() || history.stop()) break;
            if (better) best_out = out_, best = result;
            context.debug("refine: pass " + std::to_string(history.passes()) + ": " + std::to_string(split.size()) +
                          " triangles above the tolerance next to held-back vertices (bound " +
                          detail::three_digit_text(result.hausdorff_bound) + "), refined further");
            tris_ = irregular;
            out_.surface.vertices = at_phi;
            for (size_t i : split) tris_[i].need = std::numeric_limits<double>::infinity();
        }
        if (history.best_is_earlier()) {
            out_ = std::move(best_out);
            result = best;
        }
        result.adaptive_passes = history.passes();
        return result;
    }

    // Per-triangle proven bound with the vertices where they are (held back or not),
    // RefineResult::hausdorff_bound and the counts above the tolerance. With `split`,
    // the triangles of the 1-irregular mesh (origin: final triangle -> its index there)
    // that exceed the tolerance below max_level.
    void bound(RefineResult& result, std::vector<size_t>* split, const RefineOptions* options = nullptr,
               const std::vector<size_t>* origin = nullptr) {
        out_.triangle_bound.resize(tris_.size());
        result.hausdorff_bound = 0;
        result.triangles_above_tolerance = 0;
        result.triangles_at_max_level_above_tolerance = 0;
        const std::vector<double> beta = region_bounds();
        for (size_t i = 0; i < tris_.size(); ++i) {
            const RTri& r = tris_[i];
            // Unchanged vertices: the error at phi (cached for red triangles) is the bound.
            bool moved = false;
            for (int32_t v : r.v) moved = moved || moved_[size_t(v)];
            double e = moved ? error(r) : r.error;
            const int32_t g = planar_.region[size_t(r.coarse)];
            if (g >= 0) e = std::min(e, beta[size_t(g)]);
            out_.triangle_bound[i] = e;
            result.hausdorff_bound = std::max(result.hausdorff_bound, e);
            if (!options || e <= options->tolerance) continue;
            ++result.triangles_above_tolerance;
            if (r.level >= options->max_level) ++result.triangles_at_max_level_above_tolerance;
            else if (split) split->push_back((*origin)[i]);
        }
        if (split) {
            std::sort(split->begin(), split->end());
            split->erase(std::unique(split->begin(), split->end()), split->end());
        }
    }
    // HELD-BACK VERTICES (RefineOptions::prevent_intersections). A new vertex v is the
    // midpoint of its parent edge (a, b) in parameter space. Held back, it lies between its
    // parents' CURRENT midpoint m = (x_a + x_b) / 2 and phi: x_v = m + f (phi_v - m), f its
    // fraction (RefinedSurface::vertex_phi_fraction; f = 1 is phi exactly, so a vertex that
    // is not held back is where it was). A vertex that still intersects at f = 0 does not
    // move on towards its point on the coarse surface: its parents are held back instead
    // (recursively, up to the coarse vertices, which never move), and it follows them.
    // Why: at a sharp fold of S0 (femur: 497 edges turn by more than 90 deg, up to 155) the
    // chords across the fold cross their neighbours at every level, and moving such a
    // vertex on to the coarse surface moved it by about its coarse triangle's deviation:
    // femur 10 % at T = 0.0003 held back 2530 vertices up to 4.0e-3 of the diagonal, and
    // they set the bound, 4.0e-3, in 405 remedy rounds. Holding back the parents instead
    // moves a branch of the hierarchy together by its chords' deviations: 326 vertices up
    // to 5.0e-4 in 4 rounds, and the bound, 1.37e-3, is that of the triangles at
    // max_level at phi (the fold itself). At level 1 the parents are coarse vertices, m is
    // the flat point, and this is the one-stage flat + f (phi - flat) it replaces.
    // How far: with d the distance from phi and c_v = |mid(phi_a, phi_b) - phi_v| (the
    // deviation of v's parent chord), d_v <= (1 - f_v) (c_v + (d_a + d_b) / 2), so a
    // held-back vertex is bounded by its ancestors' chord deviations, halved per level.
    // It ends: a round of the remedy only lowers fractions, each reaches 0 after 11 moves,
    // and with every fraction 0 every new vertex is at its flat point (by induction in
    // creation order: the flat map is affine on the coarse triangle holding v and both
    // parents, so the midpoint of their flat points is v's), where the refined triangles
    // lie in their coarse triangles, which do not intersect. (The flat point is taken as
    // computed from the coarse corners once both parents are on it, so that end state is
    // the coarse surface exactly as before.)
    struct Placement {
        std::vector<Vec3> at_phi, flat;
        std::vector<uint8_t> on_coarse;  // at its flat point: coarse vertices, and f = 0 with both parents on it
    };

    // Places every new vertex by its fraction, parents before children (a midpoint is
    // created after the ends of its edge, so it has the larger id).
    void place(Placement& pl) {
        Surface& s = out_.surface;
        const std::vector<double>& f = out_.vertex_phi_fraction;
        for (size_t v = p_.coarse.vertices.size(); v < s.vertices.size(); ++v) {
            if (f[v] >= 1.0) {
                s.vertices[v] = pl.at_phi[v];
                pl.on_coarse[v] = 0;
                continue;
            }
            const auto [a, b] = parents_[v - p_.coarse.vertices.size()];
            const bool parents_flat = pl.on_coarse[size_t(a)] && pl.on_coarse[size_t(b)];
            const Vec3 m = parents_flat ? pl.flat[v] : mid(s.vertices[size_t(a)], s.vertices[size_t(b)]);
            s.vertices[v] = f[v] > 0 ? m + f[v] * (pl.at_phi[v] - m) : m;
            pl.on_coarse[v] = parents_flat && f[v] == 0;
        }
    }

    // The vertices a remedy round moves for vertex v of an intersecting pair (appended to
    // `moving`): v itself while it is above its parents' midpoint (f > 0), else what its
    // parents would move; none once v and its ancestors are on the coarse surface. `seen`
    // marks the vertices visited in this round (each moves once per round).
    void to_move(int32_t v, std::vector<uint8_t>& seen, std::vector<int32_t>& moving) const {
        if (size_t(v) < p_.coarse.vertices.size() || seen[size_t(v)]) return;
        seen[size_t(v)] = 1;
        if (out_.vertex_phi_fraction[size_t(v)] > 0) {
            moving.push_back(v);
            return;
        }
        const auto [a, b] = parents_[size_t(v) - p_.coarse.vertices.size()];
        to_move(a, seen, moving);
        to_move(b, seen, moving);
    }

    // The fraction after `halvings` moves of the remedy: 2^-h, 0 (the parents' midpoint)
    // after 10.
    static double fraction_after(int32_t halvings) { return halvings > 10 ? 0.0 : std::ldexp(1.0, -halvings); }

    // Intersecting pairs of the refined surface (every one: CheckResult::problems), with
    // triangle ids of the whole surface. With `reference` (positions of every vertex in
    // an earlier state), only the pairs with a triangle that moved since then are looked
    // for: the check runs on the triangles with a vertex not at its reference position and
    // the triangles whose bounding boxes overlap theirs. A pair of unmoved triangles is
    // missed, so callers use it where those did not intersect, or check everything once
    // more at the end. The remedy moves few vertices per round, so this is most of its
    // time saved on a large surface.
    CheckResult intersections(const std::vector<Vec3>* reference) const {
        const Surface& s = out_.surface;
        CheckOptions all;
        all.max_problems = std::numeric_limits<size_t>::max();
        if (!reference) return check_intersections(s, all, Context{}, "refined intersections");
        const size_t nt = s.triangles.size();
        auto box = [&](size_t t, Vec3& lo, Vec3& hi) {
            lo = hi = s.vertices[size_t(s.triangles[t][0])];
            for (int32_t v : s.triangles[t])
                for (size_t k = 0; k < 3; ++k) {
                    lo[k] = std::min(lo[k], s.vertices[size_t(v)][k]);
                    hi[k] = std::max(hi[k], s.vertices[size_t(v)][k]);
                }
        };
        std::vector<uint8_t> vertex_moved(s.vertices.size());
        for (size_t v = 0; v < s.vertices.size(); ++v) vertex_moved[v] = s.vertices[v] != (*reference)[v];
        std::vector<int32_t> changed;
        Vec3 origin{0, 0, 0}, far{0, 0, 0};  // the bounding box of the changed triangles
        double h = 0;
        for (size_t t = 0; t < nt; ++t) {
            const Tri& c = s.triangles[t];
            if (!vertex_moved[size_t(c[0])] && !vertex_moved[size_t(c[1])] && !vertex_moved[size_t(c[2])]) continue;
            Vec3 lo, hi;
            box(t, lo, hi);
            if (changed.empty()) origin = lo, far = hi;
            for (size_t k = 0; k < 3; ++k)
                origin[k] = std::min(origin[k], lo[k]), far[k] = std::max(far[k], hi[k]), h = std::max(h, hi[k] - lo[k]);
            changed.push_back(int32_t(t));
        }
        CheckResult none;
        none.name = "refined intersections";
        if (changed.empty()) return none;
        if (!(h > 0)) h = diagonal_ * 1e-9;
        // Coarse occupancy of the changed boxes, G^3 cells over their bounding box: the scan
        // below visits every triangle each round, and most are far from every moved one, so
        // they are rejected here with a few comparisons instead of hash lookups. Exact: the
        // cell index is monotone in x, so overlapping boxes cover a common cell.
        constexpr int64_t G = 32;
        double coarse_size[3];
        for (size_t k = 0; k < 3; ++k) coarse_size[k] = std::max((far[k] - origin[k]) / double(G), diagonal_ * 1e-12);
        auto coarse = [&](double x, size_t k) {
            return std::min(G - 1, std::max<int64_t>(0, int64_t(std::floor((x - origin[k]) / coarse_size[k]))));
        };
        std::vector<uint8_t> occupied(size_t(G * G * G), 0);
        for (int32_t t : changed) {
            Vec3 lo, hi;
            box(size_t(t), lo, hi);
            for (int64_t i = coarse(lo[0], 0); i <= coarse(hi[0], 0); ++i)
                for (int64_t j = coarse(lo[1], 1); j <= coarse(hi[1], 1); ++j)
                    for (int64_t k = coarse(lo[2], 2); k <= coarse(hi[2], 2); ++k) occupied[size_t((i * G + j) * G + k)] = 1;
        }
        auto maybe_near = [&](const Vec3& lo, const Vec3& hi) {
            for (size_t k = 0; k < 3; ++k)
                if (hi[k] < origin[k] || lo[k] > far[k]) return false;
            const int64_t i1 = coarse(hi[0], 0), j1 = coarse(hi[1], 1), k1 = coarse(hi[2], 2);
            for (int64_t i = coarse(lo[0], 0); i <= i1; ++i)
                for (int64_t j = coarse(lo[1], 1); j <= j1; ++j)
                    for (int64_t k = coarse(lo[2], 2); k <= k1; ++k)
                        if (occupied[size_t((i * G + j) * G + k)]) return true;
            return false;
        };
        // A hash grid of cell size h: each changed box covers at most 2 cells per axis.
        auto cell = [&](double x, size_t k) { return int64_t(std::floor((x - origin[k]) / h)); };
        auto key = [](int64_t i, int64_t j, int64_t k) {
            return uint64_t(i) * 73856093u ^ uint64_t(j) * 19349663u ^ uint64_t(k) * 83492791u;
        };
        std::unordered_map<uint64_t, std::vector<int32_t>> grid;
        for (int32_t t : changed) {
            Vec3 lo, hi;
            box(size_t(t), lo, hi);
            for (int64_t i = cell(lo[0], 0); i <= cell(hi[0], 0); ++i)
                for (int64_t j = cell(lo[1], 1); j <= cell(hi[1], 1); ++j)
                    for (int64_t k = cell(lo[2], 2); k <= cell(hi[2], 2); ++k) grid[key(i, j, k)].push_back(t);
        }
        Surface sub;
        sub.vertices = s.vertices;
        std::vector<int64_t> whole;
        for (size_t t = 0; t < nt; ++t) {
            Vec3 lo, hi;
            box(t, lo, hi);
            if (!maybe_near(lo, hi)) continue;
            const int64_t i0 = cell(lo[0], 0), i1 = cell(hi[0], 0), j0 = cell(lo[1], 1), j1 = cell(hi[1], 1),
                          k0 = cell(lo[2], 2), k1 = cell(hi[2], 2);
            bool near = (i1 - i0 + 1) * (j1 - j0 + 1) * (k1 - k0 + 1) > 64;  // large: take it
            for (int64_t i = i0; i <= i1 && !near; ++i)
                for (int64_t j = j0; j <= j1 && !near; ++j)
                    for (int64_t k = k0; k <= k1 && !near; ++k) {
                        const auto it = grid.find(key(i, j, k));
                        if (it == grid.end()) continue;
                        for (int32_t c : it->second) {
                            Vec3 clo, chi;
                            box(size_t(c), clo, chi);
                            if (clo[0] <= hi[0] && lo[0] <= chi[0] && clo[1] <= hi[1] && lo[1] <= chi[1] &&
                                clo[2] <= hi[2] && lo[2] <= chi[2]) {
                                near = true;
                                break;
                            }
                        }
                    }
            if (!near) continue;
            whole.push_back(int64_t(t));
            sub.triangles.push_back(s.triangles[t]);
            if (!s.patches.empty()) sub.patches.push_back(s.patches[t]);
        }
        CheckResult r = check_intersections(sub, all, Context{}, "refined intersections");
        for (CheckProblem& problem : r.problems)
            for (auto& [kind, id] : problem.ids)
                if ((kind == "triangle" || kind == "other_triangle") && id >= 0) id = whole[size_t(id)];
        return r;
    }

    // After hold_back's halvings every held-back vertex has a fraction f that is free of
    // intersections and one (its value before the last move) that was not: bisect between
    // them, all vertices at once, five times. A trial that makes a pair intersect is undone
    // (undo_nearest) for the vertices of that pair, or where they have none, for the
    // nearest trials they follow (a held-back vertex moves with its parents); the others
    // keep theirs, until the surface is free of intersections again, so every step ends in
    // a valid state.
    void grow_back(const std::vector<int32_t>& halvings, Placement& pl, const Context& context) {
        std::vector<double>& f = out_.vertex_phi_fraction;
        const size_t nv = out_.surface.vertices.size();
        std::vector<double> lo(nv, 1.0), hi(nv, 1.0);
        std::vector<int32_t> held;
        for (size_t v = 0; v < nv; ++v) {
            if (f[v] >= 1.0) continue;
            held.push_back(int32_t(v));
            lo[v] = f[v];
            hi[v] = fraction_after(halvings[v] - 1);
        }
        if (held.empty()) return;
        for (int step = 0; step < 5; ++step) {
            std::vector<uint8_t> trying(nv, 0);
            const std::vector<Vec3> valid = out_.surface.vertices;  // free of intersections
            for (int32_t v : held) {
                f[size_t(v)] = 0.5 * (lo[size_t(v)] + hi[size_t(v)]);
                trying[size_t(v)] = 1;
            }
            place(pl);
            int64_t undone = 0;
            while (true) {
                // Only the pairs of moved triangles: the state before was valid.
                const CheckResult r = intersections(&valid);
                if (r.passed) break;
                std::vector<uint8_t> seen(nv, 0);
                int64_t undone_now = 0;
                auto undo_nearest = [&](auto&& self, int32_t v) -> void {
                    if (size_t(v) < p_.coarse.vertices.size() || seen[size_t(v)]) return;
                    seen[size_t(v)] = 1;
                    if (trying[size_t(v)]) {
                        trying[size_t(v)] = 0;
                        hi[size_t(v)] = f[size_t(v)];
                        f[size_t(v)] = lo[size_t(v)];
                        ++undone_now;
                        return;
                    }
                    if (f[size_t(v)] >= 1.0) return;  // at phi: follows no one
                    const auto [a, b] = parents_[size_t(v) - p_.coarse.vertices.size()];
                    self(self, a);
                    self(self, b);
                };
                for (const CheckProblem& problem : r.problems)
                    for (const char* kind : {"triangle", "other_triangle"}) {
                        const int64_t t = problem.id(kind);
                        if (t >= 0)
                            for (int32_t v : out_.surface.triangles[size_t(t)]) undo_nearest(undo_nearest, v);
                    }
                // Only trials moved since the last valid state: undoing them all is that state.
                if (undone_now == 0) throw std::logic_error("refine: intersections after undoing every trial");
                undone += undone_now;
                place(pl);
            }
            for (int32_t v : held)
                if (trying[size_t(v)]) lo[size_t(v)] = f[size_t(v)];
            context.debug("refine: intersection remedy, bisection step " + std::to_string(step + 1) + ": " +
                          std::to_string(int64_t(held.size()) - undone) + " of " + std::to_string(held.size()) +
                          " vertices moved closer to phi");
        }
    }

    // After grow_back, each vertex held back farther than `above` (absolute) from phi,
    // farthest first, is tried alone at phi and, where that intersects, bisected alone four
    // times between its fraction and 1; a trial that intersects is undone. Why: grow_back
    // moves all vertices at once and only within the last halving (f to 2 f), so a vertex
    // whose intersections were resolved by later moves of others (its parents, its
    // neighbours) stays held back: femur 10 % at T = 0.001, pass 1, the farthest one (1.04e-3
    // from phi, f = 0.625) intersected nothing when put back at phi alone. Only the
    // vertices that put their triangles above the tolerance are tried (each trial checks
    // the triangles around it), and every kept state is free of intersections.
    int64_t release(double above, const Context& context) {
        Placement& pl = placement_;
        Surface& s = out_.surface;
        std::vector<double>& f = out_.vertex_phi_fraction;
        const size_t nv = s.vertices.size(), nc = p_.coarse.vertices.size(), nt = s.triangles.size();
        std::vector<std::pair<double, int32_t>> far;
        for (size_t v = nc; v < nv; ++v) {
            if (f[v] >= 1.0) continue;
            const double d = distance(s.vertices[v], pl.at_phi[v]);
            if (d > above) far.emplace_back(d, int32_t(v));
        }
        if (far.empty()) return 0;
        std::sort(far.begin(), far.end(), [](const auto& a, const auto& b) {
            return a.first > b.first || (a.first == b.first && a.second < b.second);
        });
        // Held-back children of every vertex (they follow their parents), incident triangles.
        std::vector<std::vector<int32_t>> followers(nv), incident(nv);
        for (size_t w = nc; w < nv; ++w) {
            if (f[w] >= 1.0) continue;
            const auto [a, b] = parents_[w - nc];
            followers[size_t(a)].push_back(int32_t(w));
            followers[size_t(b)].push_back(int32_t(w));
        }
        for (size_t t = 0; t < nt; ++t)
            for (int32_t v : s.triangles[t]) incident[size_t(v)].push_back(int32_t(t));
        // Places the vertices of `moving` (ascending ids: parents first) as place() does.
        auto place_moving = [&](const std::vector<int32_t>& moving) {
            for (int32_t w : moving) {
                const auto [a, b] = parents_[size_t(w) - nc];
                const bool parents_flat = pl.on_coarse[size_t(a)] && pl.on_coarse[size_t(b)];
                const Vec3 m = parents_flat ? pl.flat[size_t(w)] : mid(s.vertices[size_t(a)], s.vertices[size_t(b)]);
                const double fw = f[size_t(w)];
                s.vertices[size_t(w)] = fw >= 1.0 ? pl.at_phi[size_t(w)] : fw > 0 ? m + fw * (pl.at_phi[size_t(w)] - m) : m;
                pl.on_coarse[size_t(w)] = fw < 1.0 && parents_flat && fw == 0;
            }
        };
        CheckOptions all;
        all.max_problems = 1;
        int64_t moved = 0;
        std::vector<uint8_t> in_moving(nv, 0);
        // The triangles' boxes, kept current below (core/triangle_grid.h, the simplifier's
        // grid): each trial's sub-surface is found among the triangles near its box instead
        // of by a scan of all, which made a call (vertices x triangles): femur 10 % at
        // T = 0.0003, pass 1, 397 x 323k = 128M box tests. A build costs about as much as
        // 30-60 scans (femur 10 % at T = 0.001, 1-12 vertices per call on 55k triangles,
        // spent 4-10 ms more per call with a grid), so few vertices are scanned for.
        constexpr size_t kGridFrom = 32;
        std::optional<detail::TriangleGrid> grid;
        if (far.size() >= kGridFrom) grid = triangle_grid_of(s, pl.at_phi);
        std::vector<detail::TriangleGrid::Entry> near;
        std::vector<int32_t> candidates;  // of a trial's sub-surface
        int64_t box_tests = 0, queries = 0;
        for (const auto& [d, v] : far) {
            if (f[size_t(v)] >= 1.0) continue;
            // v and the held-back vertices that follow it: their positions are affine in f_v.
            std::vector<int32_t> moving{v};
            in_moving[size_t(v)] = 1;
            for (size_t k = 0; k < moving.size(); ++k)
                for (int32_t w : followers[size_t(moving[k])])
                    if (!in_moving[size_t(w)] && f[size_t(w)] < 1.0) in_moving[size_t(w)] = 1, moving.push_back(w);
            std::sort(moving.begin(), moving.end());
            // Every triangle a trial can meet: the box of the moving triangles at f_v and at
            // f_v = 1 holds them at every fraction between (positions affine in f_v).
            std::vector<int32_t> moving_tris;
            for (int32_t w : moving)
                for (int32_t t : incident[size_t(w)]) moving_tris.push_back(t);
            std::sort(moving_tris.begin(), moving_tris.end());
            moving_tris.erase(std::unique(moving_tris.begin(), moving_tris.end()), moving_tris.end());
            const double start = f[size_t(v)];
            const std::vector<Vec3> before = [&] {
                std::vector<Vec3> x;
                for (int32_t w : moving) x.push_back(s.vertices[size_t(w)]);
                return x;
            }();
            Vec3 lo = s.vertices[size_t(v)], hi = lo;
            auto grow = [&]() {
                for (int32_t t : moving_tris)
                    for (int32_t w : s.triangles[size_t(t)])
                        for (size_t k = 0; k < 3; ++k)
                            lo[k] = std::min(lo[k], s.vertices[size_t(w)][k]), hi[k] = std::max(hi[k], s.vertices[size_t(w)][k]);
            };
            grow();
            f[size_t(v)] = 1.0;
            place_moving(moving);
            grow();
            // Slack for rounding: at f_v = 0 a follower may sit at its flat point, computed
            // from the coarse corners instead of as its parents' midpoint.
            for (size_t k = 0; k < 3; ++k) lo[k] -= 1e-9 * diagonal_, hi[k] += 1e-9 * diagonal_;
            // The sub-surface: every triangle whose box meets that box (the others cannot
            // meet a moving triangle), with its own vertex numbering, in ascending order. The
            // grid's candidates hold them all: the others' boxes are as filed, and each
            // moving triangle is filed under its box at f_v, which lies in [lo, hi].
            Surface sub;
            std::unordered_map<int32_t, int32_t> local;
            std::vector<int32_t> global;
            if (grid) {
                // The moving triangles are out of the grid until they have moved (below):
                // their boxes change with every trial, and they all meet [lo, hi].
                for (int32_t t : moving_tris) grid_remove(*grid, s, t, moving, before);
                grid->query_boxes(lo, hi, near);
                candidates = moving_tris;
                for (const auto& e : near) candidates.push_back(e.id);
                std::sort(candidates.begin(), candidates.end());
                candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
            } else {
                candidates.resize(nt);
                std::iota(candidates.begin(), candidates.end(), 0);
            }
            box_tests += int64_t(candidates.size());
            ++queries;
            for (int32_t t : candidates) {
                const Tri& c = s.triangles[size_t(t)];
                bool out = false;
                for (size_t k = 0; k < 3 && !out; ++k) {
                    const double a = s.vertices[size_t(c[0])][k], b = s.vertices[size_t(c[1])][k], e = s.vertices[size_t(c[2])][k];
                    out = std::max({a, b, e}) < lo[k] || std::min({a, b, e}) > hi[k];
                }
                if (out) continue;
                Tri l;
                for (size_t k = 0; k < 3; ++k) {
                    const auto [it, added] = local.emplace(c[k], int32_t(global.size()));
                    if (added) global.push_back(c[k]);
                    l[k] = it->second;
                }
                sub.triangles.push_back(l);
                if (!s.patches.empty()) sub.patches.push_back(s.patches[size_t(t)]);
            }
            auto free_of_intersections = [&]() {
                sub.vertices.resize(global.size());
                for (size_t i = 0; i < global.size(); ++i) sub.vertices[i] = s.vertices[size_t(global[i])];
                return check_intersections(sub, all, Context{}, "refined intersections").passed;
            };
            double lo_f = start, hi_f = 1.0;
            for (int step = 0; step < 5; ++step) {
                const double trial = step == 0 ? 1.0 : 0.5 * (lo_f + hi_f);
                f[size_t(v)] = trial;
                place_moving(moving);
                if (free_of_intersections()) {
                    lo_f = trial;
                    if (step == 0) break;
                    continue;
                }
                hi_f = trial;
            }
            f[size_t(v)] = lo_f;
            if (lo_f == start) {
                for (size_t i = 0; i < moving.size(); ++i) s.vertices[size_t(moving[i])] = before[i];
                place_moving(moving);  // on_coarse as before
            } else {
                place_moving(moving);
                ++moved;
            }
            for (int32_t w : moving) in_moving[size_t(w)] = 0;
            if (grid)
                for (int32_t t : moving_tris) {
                    const Tri& c = s.triangles[size_t(t)];
                    grid->insert(t, s.vertices[size_t(c[0])], s.vertices[size_t(c[1])], s.vertices[size_t(c[2])]);
                }
        }
        context.debug("refine: intersection remedy: " + std::to_string(moved) + " of " + std::to_string(far.size()) +
                      " vertices held back farther than the tolerance moved closer to phi alone (" +
                      std::to_string(box_tests) + " triangle boxes tested for their sub-surfaces" +
                      (grid ? "; a scan tests " + std::to_string(queries * int64_t(nt)) : std::string(", a scan")) +
                      ")");
        return moved;
    }

    // RefineOptions::prevent_intersections: holds back the vertices of intersecting pairs
    // (see HELD-BACK VERTICES), then grows them back towards phi as far as they stay free.
    void hold_back(RefineResult& result, const Context& context) {
        Surface& s = out_.surface;
        const size_t nv = s.vertices.size(), coarse_vertices = p_.coarse.vertices.size();
        placement_ = Placement{};
        Placement& pl = placement_;
        pl.at_phi = s.vertices;
        pl.flat.resize(nv);
        pl.on_coarse.assign(nv, 0);
        std::fill(pl.on_coarse.begin(), pl.on_coarse.begin() + ptrdiff_t(coarse_vertices), uint8_t(1));
        for (size_t v = coarse_vertices; v < nv; ++v) {
            const Tri& c = p_.coarse.triangles[size_t(out_.vertex_coarse_triangle[v])];
            const auto& x = p_.coarse.vertices;
            pl.flat[v] = barycentric_point(x[size_t(c[0])], x[size_t(c[1])], x[size_t(c[2])], out_.vertex_barycentric[v]);
        }
        std::vector<int32_t> halvings(nv, 0);
        std::vector<double>& f = out_.vertex_phi_fraction;
        constexpr int32_t kMoves = 11;  // after this many a vertex is at its parents' midpoint
        // The first and the last check see every pair; the rounds between look only at the
        // pairs with a triangle moved in the round before (`last_checked`). That misses
        // none: a pair that intersected in the round before had a vertex moved in it (a
        // pair with no vertex left to move is the bug thrown below, at the latest after the
        // full check), and a pair of triangles that did not move is as it was, free of
        // intersections. Each round then checks the few thousand triangles around
        // the vertices it moved, not every triangle ever held back (femur 10 % at
        // T = 0.0003: ~250 rounds per adaptive pass).
        std::vector<Vec3> last_checked;
        for (int32_t round = 0;; ++round) {
            progress(context, 1.0 - 0.5 / (round + 1),
                     round == 0 ? std::string("checking the refined surface for intersections")
                                : "holding back intersecting vertices, round " + std::to_string(round));
            CheckResult r = intersections(round > 0 ? &last_checked : nullptr);
            if (r.passed && round > 0) r = intersections(nullptr);
            if (r.passed) break;
            last_checked = s.vertices;
            // Every round lowers at least one fraction and a fraction is 0 after kMoves
            // moves, so this ends after at most that many rounds per vertex.
            if (round > kMoves * int32_t(nv)) throw std::logic_error("refine: the intersection remedy does not end");
            result.remedy_rounds = round + 1;
            std::vector<uint8_t> seen(nv, 0), in_pair(nv, 0);
            std::vector<int32_t> moving;
            for (const CheckProblem& problem : r.problems)
                for (const char* kind : {"triangle", "other_triangle"}) {
                    const int64_t t = problem.id(kind);
                    if (t < 0) continue;
                    for (int32_t v : s.triangles[size_t(t)]) {
                        in_pair[size_t(v)] = 1;
                        to_move(v, seen, moving);
                    }
                }
            // Triangles with all their new vertices on the coarse surface lie in their coarse
            // triangles, which do not intersect: a pair of them is a bug, not the input.
            if (moving.empty())
                throw std::logic_error("refine: refined triangles on the coarse surface intersect (" +
                                       (r.problems.empty() ? std::string("?") : r.problems[0].describe()) + ")");
            int64_t ancestors = 0;  // moved for a descendant at its parents' midpoint only
            for (int32_t v : moving) {
                f[size_t(v)] = fraction_after(++halvings[size_t(v)]);
                ancestors += !in_pair[size_t(v)];
            }
            place(pl);
            context.debug("refine: intersection remedy round " + std::to_string(round + 1) + ": " +
                          std::to_string(r.problem_count) + " intersecting pairs, " + std::to_string(moving.size()) +
                          " vertices moved towards their parents' midpoints (" + std::to_string(ancestors) +
                          " of them in no intersecting pair: ancestors of a vertex at its parents' midpoint)");
        }
        grow_back(halvings, pl, context);
        count_held_back(result);
    }

    // RefineResult::held_back_vertices and max_held_back, and moved_, from the fractions.
    void count_held_back(RefineResult& result) {
        const Surface& s = out_.surface;
        const std::vector<double>& f = out_.vertex_phi_fraction;
        result.held_back_vertices = 0;
        result.max_held_back = 0;
        for (size_t v = p_.coarse.vertices.size(); v < s.vertices.size(); ++v) {
            moved_[v] = f[v] < 1.0;
            if (f[v] >= 1.0) continue;
            ++result.held_back_vertices;
            result.max_held_back = std::max(result.max_held_back, distance(s.vertices[v], placement_.at_phi[v]) / diagonal_);
        }
    }

private:
    const Parametrization& p_;
    const PhiEvaluator& phi_;
    RefinedSurface& out_;
    double diagonal_ = 1;
    std::vector<RTri> tris_;
    std::unordered_map<uint64_t, int32_t> mids_;
    // Per new vertex (index - #coarse vertices): the edge it is the midpoint of.
    std::vector<std::pair<int32_t, int32_t>> parents_;
    std::vector<uint8_t> moved_;  // per vertex: not at phi (hold_back)
    Placement placement_;         // of the last hold_back (release continues it)
    detail::PlanarRegions planar_;  // see PLANAR REGIONS
    int32_t pass_ = 0;            // the adaptive pass running (1, 2, ...); 0 = uniform
};

}  // namespace

RefineResult refine(const Parametrization& param, const RefineOptions& options, const Context& context,
                    RefinedSurface& out) {
    const auto start = std::chrono::steady_clock::now();
    if (options.levels > 10) throw OptionError("refine: levels must be at most 10 (4^10 triangles per coarse triangle)");
    if (options.levels < 0 && !(options.tolerance > 0))
        throw OptionError("refine: give levels >= 0 (uniform) or a tolerance > 0 (adaptive)");
    // Both given: the tolerance was dropped without a word (uniform refinement won).
    if (options.levels >= 0 && options.tolerance != 0)
        throw OptionError("refine: give levels (uniform) or tolerance (adaptive), not both; got levels " +
                          std::to_string(options.levels) + " and tolerance " +
                          detail::significant_text(options.tolerance, 6));
    if (options.levels < 0 && (options.max_level < 0 || options.max_level > 10))
        throw OptionError("refine: max_level must be in 0..10");
    detail::require_coordinates_in_range(param);
    const PhiEvaluator phi(param);
    out = RefinedSurface{};
    Refiner refiner(param, phi, out);
    RefineResult result = refiner.run(options, context);
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    context.report(1.0, "refining");
    return result;
}

std::vector<Vec3> vertex_normals(const Surface& surface) {
    std::vector<Vec3> n(surface.vertices.size(), Vec3{0, 0, 0});
    for (const Tri& t : surface.triangles) {
        const Vec3& a = surface.vertices[size_t(t[0])];
        const Vec3& b = surface.vertices[size_t(t[1])];
        const Vec3& c = surface.vertices[size_t(t[2])];
        const Vec3 w = cross(b - a, c - a);  // length = 2 * area: area weighting
        for (int32_t v : t) n[size_t(v)] = n[size_t(v)] + w;
    }
    for (Vec3& x : n) {
        const double l = norm(x);
        if (l > 0) x = (1.0 / l) * x;
    }
    return n;
}

std::vector<double> transfer_vertex_data(const RefinedSurface& refined, const Surface& original,
                                         const std::vector<double>& data, int components) {
    if (components < 1 || data.size() != original.vertices.size() * size_t(components))
        throw std::invalid_argument("transfer_vertex_data: data must have #V0 * components values");
    const size_t nv = refined.surface.vertices.size();
    std::vector<double> out(nv * size_t(components), 0.0);
    for (size_t v = 0; v < nv; ++v) {
        const Tri& t = original.triangles[size_t(refined.vertex_original_triangle[v])];
        const Vec3& beta = refined.vertex_original_barycentric[v];
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < components; ++c)
                out[v * size_t(components) + size_t(c)] +=
                    beta[size_t(k)] * data[size_t(t[size_t(k)]) * size_t(components) + size_t(c)];
    }
    return out;
}

}  // namespace bpm
