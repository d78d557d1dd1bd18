#include "simplify/fan_retriangulation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "bpm/predicates.h"

namespace bpm::detail {

namespace {

// Delaunay admissibility is a quality heuristic, not a validity decision: points within
// rounding distance of the circle count as on it, so that the choice does not depend on
// the model's units.
bool clearly_in_circle(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
    const double adx = a[0] - d[0], ady = a[1] - d[1];
    const double bdx = b[0] - d[0], bdy = b[1] - d[1];
    const double cdx = c[0] - d[0], cdy = c[1] - d[1];
    const double alift = adx * adx + ady * ady, blift = bdx * bdx + bdy * bdy, clift = cdx * cdx + cdy * cdy;
    const double det = alift * (bdx * cdy - cdx * bdy) + blift * (cdx * ady - adx * cdy) + clift * (adx * bdy - bdx * ady);
    // The bound below is >= 0 (or NaN): a det that is not positive fails it anyway, and
    // most corners are outside the circle, so the bound is only needed for det > 0.
    if (!(det > 0.0)) return false;
    const double permanent = (std::abs(bdx * cdy) + std::abs(cdx * bdy)) * alift +
                             (std::abs(cdx * ady) + std::abs(adx * cdy)) * blift +
                             (std::abs(adx * bdy) + std::abs(bdx * ady)) * clift;
    return det > 1e-9 * permanent;
}

// Whether the orientation of (a, b, c) is certainly negative by Shewchuk's filter (the
// one of bpm::orient2d), without the exact predicate.
inline bool clearly_clockwise(const Vec2& a, const Vec2& b, const Vec2& c) {
    const double left = (a[0] - c[0]) * (b[1] - c[1]);
    const double right = (a[1] - c[1]) * (b[0] - c[0]);
    // The 1e-250 as in orient2d: no claim where the products may have underflowed.
    return left - right < -(3.3306690738754716e-16 * (std::abs(left) + std::abs(right)) + 1e-250);
}

// Whether p is in the closed triangle (a, b, d), counter-clockwise: orient2d of p against
// each side >= 0. The same answer as the three exact tests in a row, but a side that
// certainly has p outside answers first: on a rim with collinear corners (a CAD face fanned
// from its centre) p is often exactly on the line of one side, and the exact predicate
// there cost a quarter of a run (bench/make_fan_box.py).
inline bool in_closed_triangle(const Vec2& a, const Vec2& b, const Vec2& d, const Vec2& p) {
    if (clearly_clockwise(a, b, p) || clearly_clockwise(b, d, p) || clearly_clockwise(d, a, p)) return false;
    return orient2d(a, b, p) >= 0 && orient2d(b, d, p) >= 0 && orient2d(d, a, p) >= 0;
}

bool is_forbidden(const std::vector<std::array<int32_t, 2>>& forbidden, int32_t a, int32_t d) {
    for (const auto& f : forbidden)
        if ((f[0] == a && f[1] == d) || (f[0] == d && f[1] == a)) return true;
    return false;
}

// The last triangle of an ear cutting, its corners in increasing order (as the plain
// scan leaves them).
bool close_last_triangle(const CoarseMesh& mesh, const Fan& fan, int32_t c0, int32_t c1, int32_t c2,
                         FanTriangulation& out, std::string& why) {
    const auto& x = mesh.positions();
    const double last_aspect = aspect_ratio(x[fan.link[c0]], x[fan.link[c1]], x[fan.link[c2]]);
    if (!std::isfinite(last_aspect)) {
        why = "retriangulation would create a degenerate triangle";
        return false;
    }
    if (mesh.find_triangle(fan.link[c0], fan.link[c1], fan.link[c2]) >= 0) {
        why = "new triangle already exists (topology condition)";
        return false;
    }
    out.triangles.push_back({c0, c1, c2});
    out.aspects.push_back(last_aspect);
    return true;
}

// retriangulate_fan() for a large polygon on a circle (map.cocircular), the same choices
// as its plain scan, O(n log n) on the fan box's rims where that is O(n^2) (on a round rim
// with one corner pulled in the greedy keeps fanning from one corner, the wedges widen and
// the polar tests visit O(n) corners each: O(n^2), ~10x fewer visits than the scan; found
// by review, 2026-12-07): the centre of a CAD face fanned to
// hundreds of collinear rim corners, planned again each time one of them goes
// (bench/make_fan_box.py). On a circle every ear is Delaunay-admissible, so the scan
// takes, among the non-degenerate ears whose diagonal may be cut, the ears of the polar
// map's polygon first, then the smallest aspect ratio, where an ear replaces the best so
// far only if it is better by a factor 1 - 1e-9, in corner order. Here the ears wait in an
// ordered set by (polar ear or not, aspect ratio, corner); the scan's choice is replayed
// on the best ears up to the first gap of that factor: an ear past the gap never replaces
// one before it, and each ear before it replaces any past it, so the scan over all ears
// ends where the scan over these ends. A cut changes the two ears beside it, and the
// polar-ear test of the ears that had the cut corner inside (their witness); everything
// else is kept, as the plain scan's caches keep it.
bool cut_indexed_ears(const CoarseMesh& mesh, const Fan& fan, const PolarMap& map,
                      const std::vector<std::array<int32_t, 2>>& forbidden, FanTriangulation& out, EarScratch& s,
                      std::string& why) {
    const auto& x = mesh.positions();
    const auto& q = map.q_polar;
    const int32_t n = fan.corners();
    int64_t& work = s.work;
    auto& ears = s.ears;
    ears.clear();
    s.queued.assign(n, 0);
    s.next.resize(n);
    s.prev.resize(n);
    for (int32_t i = 0; i < n; ++i) {
        s.next[i] = mod(i + 1, n);
        s.prev[i] = mod(i - 1, n);
    }
    s.aspect.assign(n, std::nan(""));
    s.blocked.assign(n, -1);
    s.polar.assign(n, -1);
    s.polar_witness.assign(n, -1);
    if (s.witnessed.size() < size_t(n)) s.witnessed.resize(n);
    for (int32_t i = 0; i < n; ++i) s.witnessed[i].clear();
    // The corners by their angle around v (the origin of the polar map), and a skip list
    // over that order past the corners cut off (union-find with path halving).
    s.angle.resize(n);
    for (int32_t i = 0; i < n; ++i) s.angle[i] = std::atan2(q[i][1], q[i][0]);
    s.by_angle.resize(n);
    std::iota(s.by_angle.begin(), s.by_angle.end(), 0);
    std::sort(s.by_angle.begin(), s.by_angle.end(), [&](int32_t i, int32_t j) {
        return s.angle[i] < s.angle[j] || (s.angle[i] == s.angle[j] && i < j);
    });
    s.sorted_angle.resize(n);
    s.angle_rank.resize(n);
    for (int32_t k = 0; k < n; ++k) {
        s.sorted_angle[k] = s.angle[s.by_angle[k]];
        s.angle_rank[s.by_angle[k]] = k;
    }
    s.skip.resize(n + 1);
    std::iota(s.skip.begin(), s.skip.end(), 0);
    const auto in_polygon_from = [&](int32_t k) {  // the first position >= k of a corner still in the polygon, or n
        while (s.skip[k] != k) {
            s.skip[k] = s.skip[s.skip[k]];
            k = s.skip[k];
        }
        return k;
    };

    // Whether (a, b, d) is an ear of the polar map's polygon: convex, and no other corner in
    // the closed triangle (the exact test of the plain scan, on fewer corners). When the
    // triangle lies in the wedge from v between a and d, narrower than pi (exact
    // orientations against v), every point of it is in that wedge, so a corner inside has
    // its angle between those of a and d; no corner outside that range (with a margin far
    // above the error of atan2, an ulp of pi) needs the test. Else all corners are tested.
    const auto polar_ear = [&](int32_t a, int32_t b, int32_t d) {
        s.polar[b] = 0;
        s.polar_witness[b] = -1;
        const Vec2 &pa = q[a], &pb = q[b], &pd = q[d];
        if (orient2d(pa, pb, pd) <= 0) return false;
        const auto inside = [&](int32_t p) {
            ++work;
            if (p == a || p == b || p == d || !in_closed_triangle(pa, pb, pd, q[p])) return false;
            s.polar_witness[b] = p;
            s.witnessed[p].push_back(b);
            return true;
        };
        const Vec2 v{0.0, 0.0};
        bool found = false;
        double span = s.angle[d] - s.angle[a];
        if (span < 0.0) span += 2.0 * M_PI;
        if (span < 3.0 && orient2d(v, pa, pd) > 0 && orient2d(v, pa, pb) >= 0 && orient2d(v, pb, pd) >= 0) {
            constexpr double kMargin = 1e-9;
            double from = s.angle[a] - kMargin, to = s.angle[a] + span + kMargin;
            if (from < -M_PI) {
                from += 2.0 * M_PI;
                to += 2.0 * M_PI;
            }
            const auto visit = [&](double lo, double hi) {
                const int32_t start = int32_t(std::lower_bound(s.sorted_angle.begin(), s.sorted_angle.end(), lo) -
                                              s.sorted_angle.begin());
                for (int32_t k = in_polygon_from(start); k < n && s.sorted_angle[k] <= hi; k = in_polygon_from(k + 1))
                    if (inside(s.by_angle[k])) return true;
                return false;
            };
            found = to <= M_PI ? visit(from, to) : visit(from, M_PI) || visit(-M_PI, to - 2.0 * M_PI);
        } else {
            for (int32_t p = s.next[d]; p != a && !found; p = s.next[p]) found = inside(p);
        }
        if (found) return false;
        s.polar[b] = 1;
        return true;
    };
    const auto rank_of = [&](int32_t b) { return int8_t(s.polar[b] == 1 ? 0 : 1); };
    const auto enqueue = [&](int32_t b) {
        const int32_t a = s.prev[b], d = s.next[b];
        ++work;
        s.aspect[b] = aspect_ratio(x[fan.link[a]], x[fan.link[b]], x[fan.link[d]]);
        s.blocked[b] = -1;
        s.polar[b] = -1;
        if (!std::isfinite(s.aspect[b])) return;  // degenerate: never cut
        polar_ear(a, b, d);
        ears.insert({rank_of(b), s.aspect[b], b});
        s.queued[b] = 1;
    };
    const auto dequeue = [&](int32_t b) {
        if (!s.queued[b]) return;
        ears.erase({rank_of(b), s.aspect[b], b});
        s.queued[b] = 0;
    };
    for (int32_t b = 0; b < n; ++b) enqueue(b);

    constexpr double kTie = 1.0 - 1e-9;  // as in the plain scan
    auto& ties = s.ties;
    int32_t m = n, any = 0;
    while (m > 3) {
        // The best ears up to the first gap; those whose diagonal exists or is forbidden
        // leave the set (until a cut beside them changes them).
        ties.clear();
        int8_t rank = 0;
        double last = 0.0;
        for (auto it = ears.begin(); it != ears.end();) {
            if (!ties.empty() && (it->rank != rank || last < it->aspect * kTie)) break;
            const int32_t b = it->corner;
            const int32_t a = s.prev[b], d = s.next[b];
            if (s.blocked[b] < 0) s.blocked[b] = mesh.has_edge(fan.link[a], fan.link[d]) || is_forbidden(forbidden, a, d);
            if (s.blocked[b]) {
                it = ears.erase(it);
                s.queued[b] = 0;
                continue;
            }
            rank = it->rank;
            last = it->aspect;
            ties.push_back(b);
            ++it;
        }
        if (ties.empty()) {
            why = "no admissible retriangulation (topology condition)";
            return false;
        }
        // The plain scan over them, in corner order.
        std::sort(ties.begin(), ties.end());
        work += int64_t(ties.size());
        int32_t best = -1;
        double best_aspect = std::numeric_limits<double>::infinity();
        for (int32_t b : ties)
            if (s.aspect[b] < best_aspect * kTie) {
                best = b;
                best_aspect = s.aspect[b];
            }
        const int32_t a = s.prev[best], d = s.next[best];
        out.triangles.push_back({a, best, d});
        out.aspects.push_back(s.aspect[best]);
        out.diagonals.push_back({a, d});
        dequeue(best);
        dequeue(a);
        dequeue(d);
        s.next[a] = d;
        s.prev[d] = a;
        s.skip[s.angle_rank[best]] = s.angle_rank[best] + 1;
        --m;
        any = a;
        if (m > 3) {
            enqueue(a);
            enqueue(d);
            for (int32_t e : s.witnessed[best]) {
                ++work;
                if (s.queued[e] && s.polar[e] == 0 && s.polar_witness[e] == best) {
                    dequeue(e);
                    enqueue(e);
                }
            }
        }
        s.witnessed[best].clear();
    }
    std::array<int32_t, 3> last{any, s.next[any], s.next[s.next[any]]};
    std::sort(last.begin(), last.end());
    return close_last_triangle(mesh, fan, last[0], last[1], last[2], out, why);
}

// The fallback of retriangulate_fan(): over all triangulations of the polygon (corners
// 0..n-1, counter-clockwise) whose diagonals may be cut (`allowed`) and whose triangles
// are not degenerate, the one with the smallest worst 3D aspect ratio (near-ties to the
// smaller apex). Fills `out` and returns true, or false when there is none.
template <class Allowed>
bool min_max_aspect_triangulation(const std::vector<Vec3>& x, const Fan& fan, const Allowed& allowed,
                                  FanTriangulation& out, EarScratch& scratch) {
    const int32_t n = fan.corners();
    constexpr double kNone = std::numeric_limits<double>::infinity();
    auto& worst = scratch.worst;
    auto& apex = scratch.apex;
    worst.assign(size_t(n) * size_t(n), kNone);
    apex.assign(size_t(n) * size_t(n), -1);
    auto at = [n](int32_t i, int32_t k) { return size_t(i) * size_t(n) + size_t(k); };
    for (int32_t i = 0; i + 1 < n; ++i) worst[at(i, i + 1)] = 0.0;  // a polygon side: nothing to triangulate
    for (int32_t len = 2; len < n; ++len)
        for (int32_t i = 0; i + len < n; ++i) {
            const int32_t k = i + len;
            // i -- k closes the sub-polygon: a diagonal, except the side n-1 -- 0.
            if (!(i == 0 && k == n - 1) && !allowed(i, k)) continue;
            double best = kNone;
            int32_t best_j = -1;
            for (int32_t j = i + 1; j < k; ++j) {
                const double left = worst[at(i, j)], right = worst[at(j, k)];
                if (!(left < kNone) || !(right < kNone)) continue;
                const double aspect = aspect_ratio(x[fan.link[i]], x[fan.link[j]], x[fan.link[k]]);
                if (!std::isfinite(aspect)) continue;  // degenerate
                const double w = std::max({aspect, left, right});
                if (w < best * (1.0 - 1e-9)) {
                    best = w;
                    best_j = j;
                }
            }
            worst[at(i, k)] = best;
            apex[at(i, k)] = best_j;
        }
    if (apex[at(0, n - 1)] < 0) return false;
    out.triangles.clear();
    out.aspects.clear();
    out.diagonals.clear();
    auto& stack = scratch.stack;
    stack.assign(1, {0, n - 1});
    while (!stack.empty()) {
        const auto [i, k] = stack.back();
        stack.pop_back();
        if (k - i < 2) continue;
        const int32_t j = apex[at(i, k)];
        out.triangles.push_back({i, j, k});
        out.aspects.push_back(aspect_ratio(x[fan.link[i]], x[fan.link[j]], x[fan.link[k]]));
        if (j - i >= 2) out.diagonals.push_back({i, j});
        if (k - j >= 2) out.diagonals.push_back({j, k});
        stack.push_back({j, k});
        stack.push_back({i, j});
    }
    return true;
}

}  // namespace

bool retriangulate_fan(const CoarseMesh& mesh, const Fan& fan, const PolarMap& map,
                       const std::vector<std::array<int32_t, 2>>& forbidden, FanTriangulation& out,
                       EarScratch& scratch, std::string& why) {
    const auto& x = mesh.positions();
    const int32_t n = fan.corners();
    int64_t& work = scratch.work;
    work = 0;
    if (map.cocircular && n > kIndexedEarCorners && scratch.indexed) {
        out.triangles.clear();
        out.aspects.clear();
        out.diagonals.clear();
        return cut_indexed_ears(mesh, fan, map, forbidden, out, scratch, why);
    }
    auto& poly = scratch.polygon;
    poly.resize(n);
    for (int32_t i = 0; i < n; ++i) poly[i] = i;
    auto& new_tris = out.triangles;
    auto& new_aspects = out.aspects;
    auto& diagonals = out.diagonals;
    new_tris.clear();
    new_aspects.clear();
    diagonals.clear();
    // The ear at a corner only changes when a neighbouring ear is cut, so its aspect
    // ratio and whether its diagonal already exists are cached per corner.
    auto& ear_aspect = scratch.aspect;
    auto& ear_blocked = scratch.blocked;
    // Whether an ear is Delaunay-admissible: a cut only removes a test point, so an
    // admissible ear stays admissible unless it is one of the two ears next to the cut.
    auto& ear_delaunay = scratch.delaunay;
    // A corner found clearly inside the circle of a non-admissible ear: the ear stays
    // non-admissible until that corner is cut off (or the ear itself changes).
    auto& ear_witness = scratch.witness;
    ear_witness.assign(n, -1);
    ear_aspect.assign(n, std::nan(""));
    ear_blocked.assign(n, -1);
    ear_delaunay.assign(n, map.cocircular ? 1 : -1);
    // On a circle (a star the polar map made non-convex) every ear is valid in 2D, but an
    // ear at a reflex corner of the polar map's polygon folds over the rest of the star
    // in space (on a flat face it overlaps it: a self-intersection). Ears of the polar
    // map's polygon, convex and holding no other corner, come first.
    // Cached per corner like the Delaunay test, and for the same reason: a cut only
    // removes a corner, so an ear of the polar map's polygon stays one, and an ear with
    // a corner inside (its witness) stays none until that corner is cut off, unless it is
    // one of the two ears next to the cut.
    auto& ear_polar = scratch.polar;
    auto& ear_polar_witness = scratch.polar_witness;
    ear_polar.assign(n, map.cocircular ? -1 : 1);
    ear_polar_witness.assign(n, -1);
    auto polar_ear = [&](int32_t a, int32_t b, int32_t d) {
        if (ear_polar[b] >= 0) return ear_polar[b] != 0;
        ear_polar[b] = 0;
        ear_polar_witness[b] = -1;
        const Vec2 &pa = map.q_polar[a], &pb = map.q_polar[b], &pd = map.q_polar[d];
        if (orient2d(pa, pb, pd) <= 0) return false;
        for (int32_t p : poly) {
            ++work;
            if (p == a || p == b || p == d) continue;
            const Vec2& pp = map.q_polar[p];
            if (in_closed_triangle(pa, pb, pd, pp)) {
                ear_polar_witness[b] = p;
                return false;
            }
        }
        ear_polar[b] = 1;
        return true;
    };
    while (poly.size() > 3) {
        const int32_t m = static_cast<int32_t>(poly.size());
        int32_t best = -1;
        bool best_delaunay = false, best_polar = false;
        double best_aspect = std::numeric_limits<double>::infinity();
        work += m;
        for (int32_t c = 0; c < m; ++c) {
            const int32_t a = poly[mod(c - 1, m)], b = poly[c], d = poly[mod(c + 1, m)];
            if (std::isnan(ear_aspect[b]))
                ear_aspect[b] = aspect_ratio(x[fan.link[a]], x[fan.link[b]], x[fan.link[d]]);
            const double aspect = ear_aspect[b];
            if (!std::isfinite(aspect)) continue;  // degenerate
            const bool polar = polar_ear(a, b, d);
            if (best_polar && !polar) continue;
            // Once the best is Delaunay-admissible, an ear that is not better shaped
            // cannot win whether it is admissible or not: its test is left for when it
            // matters (the answer is the same then: see ear_delaunay and ear_witness).
            if (best_delaunay && !(polar && !best_polar) && !(aspect < best_aspect * (1.0 - 1e-9))) continue;
            if (ear_delaunay[b] < 0) {
                bool admissible = true;
                for (int32_t o = 0; o < m && admissible; ++o) {
                    ++work;
                    const int32_t p = poly[o];
                    if (p == a || p == b || p == d) continue;
                    if (clearly_in_circle(map.q[a], map.q[b], map.q[d], map.q[p])) {
                        admissible = false;
                        ear_witness[b] = p;
                    }
                }
                ear_delaunay[b] = admissible;
            }
            const bool delaunay = ear_delaunay[b] != 0;
            // Prefer Delaunay-admissible ears; among them the best 3D aspect ratio.
            // Near-ties count as ties (first ear wins), so that rounding differences, e.g.
            // between a model and its scaled copy, do not change the triangulation.
            if ((polar && !best_polar) || (delaunay && !best_delaunay) ||
                (delaunay == best_delaunay && aspect < best_aspect * (1.0 - 1e-9))) {
                // Topology condition (Conjecture 2.1): the new edge must not exist yet.
                // Asked only of ears that would become the best: an ear that would not
                // leaves the choice the same whether it is blocked or not.
                if (ear_blocked[b] < 0)
                    ear_blocked[b] = mesh.has_edge(fan.link[a], fan.link[d]) || is_forbidden(forbidden, a, d);
                if (ear_blocked[b]) continue;
                best = c;
                best_polar = polar;
                best_delaunay = delaunay;
                best_aspect = aspect;
            }
        }
        if (best < 0) {
            // The greedy choice may have left a polygon whose diagonals all exist or are
            // forbidden while another triangulation of the whole polygon avoids them.
            auto allowed = [&](int32_t a, int32_t d) { return !mesh.has_edge(fan.link[a], fan.link[d]) && !is_forbidden(forbidden, a, d); };
            if (!map.cocircular && min_max_aspect_triangulation(x, fan, allowed, out, scratch)) return true;
            why = "no admissible retriangulation (topology condition)";
            return false;
        }
        const int32_t a = poly[mod(best - 1, m)], b = poly[best], d = poly[mod(best + 1, m)];
        new_tris.push_back({a, b, d});
        new_aspects.push_back(ear_aspect[b]);  // ear_aspect[b] is that of (a, b, d) now
        diagonals.push_back({a, d});
        poly.erase(poly.begin() + best);
        ear_blocked[a] = ear_blocked[d] = -1;
        ear_aspect[a] = ear_aspect[d] = std::nan("");
        ear_delaunay[a] = ear_delaunay[d] = map.cocircular ? 1 : -1;
        ear_polar[a] = ear_polar[d] = map.cocircular ? -1 : 1;
        work += m - 1;
        for (int32_t p : poly) {
            if (ear_delaunay[p] == 0 && ear_witness[p] == b) ear_delaunay[p] = -1;
            if (ear_polar[p] == 0 && ear_polar_witness[p] == b) ear_polar[p] = -1;
        }
    }
    return close_last_triangle(mesh, fan, poly[0], poly[1], poly[2], out, why);
}

double triangulation_aspect_lower_bound(const std::vector<Vec3>& x, const Fan& fan) {
    const int32_t n = fan.corners();
    constexpr double kInfinite = std::numeric_limits<double>::infinity();
    const auto corner = [&](int32_t i) -> const Vec3& { return x[fan.link[mod(i, n)]]; };
    // The two best ears, and the shortest side (side i runs from corner i to i + 1).
    double best = kInfinite, second = kInfinite;
    int32_t shortest = 0;
    double shortest_length = kInfinite;
    for (int32_t i = 0; i < n; ++i) {
        const double length = distance(corner(i), corner(i + 1));
        if (length < shortest_length) {
            shortest_length = length;
            shortest = i;
        }
        const double a = aspect_ratio(corner(i - 1), corner(i), corner(i + 1));
        if (!(a < second)) continue;  // also NaN
        if (a < best) {
            second = best;
            best = a;
        } else {
            second = a;
        }
    }
    double side_best = kInfinite;
    for (int32_t j = 0; j < n; ++j) {
        if (j == shortest || j == mod(shortest + 1, n)) continue;
        const double a = aspect_ratio(corner(shortest), corner(shortest + 1), corner(j));
        if (a < side_best) side_best = a;
    }
    return std::max(second, side_best);
}

}  // namespace bpm::detail
