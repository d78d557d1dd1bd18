#include "simplify/intersection_test.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "bpm/predicates.h"

namespace bpm::detail {

namespace {

// Triangles pa and pb share exactly their corners pa[ia] == pb[ib] and are coplanar:
// whether a line through the shared corner has the rest of one strictly on one side and
// the rest of the other strictly on the other (then they meet only in that corner), with
// exact predicates in a coordinate plane onto which pa projects non-degenerately. False
// when that is not shown (a degenerate triangle, a projection that flattens pa, wedges
// that overlap or touch along a ray): the full test decides then.
// The fans of CAD discs make such pairs by the thousand: every new triangle at the
// centre against the slivers around it, which CGAL's coplanar segment-triangle tests
// took a quarter of a cylinder's run for (tests/cli/lib/fan_cylinder.py, 3000 segments).
bool apart_in_their_plane(const Vec3 pa[3], const Vec3 pb[3], int ia, int ib) {
    const Vec3 normal = cross(pa[1] - pa[0], pa[2] - pa[0]);
    int k = 0;
    for (int j = 1; j < 3; ++j)
        if (std::abs(normal[j]) > std::abs(normal[k])) k = j;
    const auto flat = [k](const Vec3& p) { return Vec2{p[(k + 1) % 3], p[(k + 2) % 3]}; };
    const Vec2 c = flat(pa[ia]);
    const Vec2 a1 = flat(pa[(ia + 1) % 3]), a2 = flat(pa[(ia + 2) % 3]);
    const Vec2 b1 = flat(pb[(ib + 1) % 3]), b2 = flat(pb[(ib + 2) % 3]);
    // Exact: a projection (dropping coordinate k) keeps the orientations of points in one
    // plane, with one sign for all, unless it flattens the plane (then pa's is 0 too).
    const int sa = orient2d(c, a1, a2), sb = orient2d(c, b1, b2);
    if (sa == 0 || sb == 0) return false;
    // The line through c and p (a corner of a triangle whose third corner is q): the other
    // triangle's two corners strictly on the side opposite q.
    const auto separates = [&c](const Vec2& p, const Vec2& q, const Vec2& u, const Vec2& w) {
        const int side = orient2d(c, p, q);
        return orient2d(c, p, u) == -side && orient2d(c, p, w) == -side;
    };
    return separates(a1, a2, b1, b2) || separates(a2, a1, b1, b2) || separates(b1, b2, a1, a2) ||
           separates(b2, b1, a1, a2);
}

}  // namespace

bool meet_improperly(const std::vector<Vec3>& x, const Tri& a, const Tri& b) {
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
        // One shared corner, b in a's plane: apart on either side of a line through it?
        if (count == 1) {
            int ia = 0;
            while (shared[ia] < 0) ++ia;
            const int ib = shared[ia];
            if (orient3d(pa[0], pa[1], pa[2], pb[(ib + 1) % 3]) == 0 &&
                orient3d(pa[0], pa[1], pa[2], pb[(ib + 2) % 3]) == 0 && apart_in_their_plane(pa, pb, ia, ib))
                return false;
        }
    }
    return triangles_intersect_improperly(pa, pb, shared);
}

bool meet_improperly(const std::vector<Vec3>& x, const std::vector<Tri>& ours, const std::vector<Tri>& others) {
    for (const Tri& a : ours)
        for (const Tri& b : others)
            if (meet_improperly(x, a, b)) return true;
    return false;
}

IntersectionTest::IntersectionTest(const CoarseMesh& mesh) : mesh_(mesh), grid_(1.0) { rebuild(); }

void IntersectionTest::rebuild() {
    // Cell size: twice the mean edge length of the current triangles.
    const auto& x = mesh_.positions();
    double extent = 0.0;
    int64_t count = 0;
    for (int32_t t = 0; t < mesh_.triangle_capacity(); ++t) {
        if (!mesh_.alive(t)) continue;
        const Tri& c = mesh_.triangle(t);
        for (int k = 0; k < 3; ++k) extent += distance(x[c[k]], x[c[(k + 1) % 3]]);
        count += 3;
    }
    const double cell = count ? 2.0 * extent / double(count) : 1.0;
    // The lattice of the grid's boxes spans every position (new triangles use only those).
    Vec3 lo{}, hi{};
    for (size_t v = 0; v < x.size(); ++v)
        for (int k = 0; k < 3; ++k) {
            lo[k] = v == 0 ? x[v][k] : std::min(lo[k], x[v][k]);
            hi[k] = v == 0 ? x[v][k] : std::max(hi[k], x[v][k]);
        }
    grid_ = TriangleGrid(cell > 0 ? cell : 1.0, TriangleGrid::Frame::of_box(lo, hi));
    std::vector<int32_t> ids;
    std::vector<Tri> corners;
    ids.reserve(size_t(mesh_.num_alive_triangles()));
    corners.reserve(size_t(mesh_.num_alive_triangles()));
    for (int32_t t = 0; t < mesh_.triangle_capacity(); ++t) {
        if (!mesh_.alive(t)) continue;
        ids.push_back(t);
        corners.push_back(mesh_.triangle(t));
    }
    grid_.insert_all(ids, corners, x);
    built_at_ = mesh_.num_alive_triangles();
}

void IntersectionTest::rebuild_if_sparse() {
    if (mesh_.num_alive_triangles() * 4 < built_at_) rebuild();
}

void IntersectionTest::update(const std::vector<std::pair<int32_t, Tri>>& removed, int32_t first_new) {
    const auto& x = mesh_.positions();
    for (const auto& [t, c] : removed) grid_.remove(t, x[c[0]], x[c[1]], x[c[2]]);
    for (int32_t t = first_new; t < mesh_.triangle_capacity(); ++t) {
        const Tri& c = mesh_.triangle(t);
        grid_.insert(t, x[c[0]], x[c[1]], x[c[2]]);
    }
}

bool IntersectionTest::intersects_rest(const std::vector<Tri>& new_triangles,
                                       const std::vector<int32_t>& removed_triangles,
                                       std::vector<TriangleGrid::Entry>& scratch) const {
    const auto& x = mesh_.positions();
    const size_t count_new = new_triangles.size();
    // Boxes of the new triangles, and the box around all of them: one grid query for
    // the whole star (the new triangles overlap the same few cells) instead of one per
    // new triangle. Every triangle whose box meets a new triangle's box is in a cell
    // that box meets, so the pairs tested below are exactly those of a query per
    // triangle; the answer does not depend on the order of the tests.
    static thread_local std::vector<TriangleGrid::LatticeBox> boxes;
    boxes.resize(count_new);
    Vec3 all_lo{}, all_hi{};
    for (size_t i = 0; i < count_new; ++i) {
        const Tri& a = new_triangles[i];
        Vec3 lo, hi;
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min({x[a[0]][k], x[a[1]][k], x[a[2]][k]});
            hi[k] = std::max({x[a[0]][k], x[a[1]][k], x[a[2]][k]});
            all_lo[k] = i == 0 ? lo[k] : std::min(all_lo[k], lo[k]);
            all_hi[k] = i == 0 ? hi[k] : std::max(all_hi[k], hi[k]);
        }
        boxes[i] = grid_.lattice_box(lo, hi);
    }
    if (count_new == 0) return false;
    // Only triangles whose box meets the box of all new triangles (the grid tests the
    // boxes it stores), then the cheap box rejection per new triangle before the exact test.
    grid_.query_boxes(all_lo, all_hi, scratch);
    for (const TriangleGrid::Entry& candidate : scratch) {
        const int32_t t = candidate.id;
        if (!mesh_.alive(t)) continue;
        if (std::find(removed_triangles.begin(), removed_triangles.end(), t) != removed_triangles.end()) continue;
        for (size_t i = 0; i < count_new; ++i)  // the lattice boxes: only a filter
            if (!TriangleGrid::apart(boxes[i], candidate.lo, candidate.hi) &&
                meet_improperly(x, new_triangles[i], mesh_.triangle(t)))
                return true;
    }
    for (size_t i = 0; i < count_new; ++i)
        for (size_t j = 0; j < i; ++j)
            if (meet_improperly(x, new_triangles[i], new_triangles[j])) return true;
    return false;
}

}  // namespace bpm::detail
