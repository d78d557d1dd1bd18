#include "io/polygon_triangulation.h"

#include <algorithm>
#include <cmath>

#include "bpm/predicates.h"
#include "io/surface_readers.h"

namespace bpm::detail {

namespace {

// Beyond this many corners the best-ear search (quadratic per cut) gives way to the
// first ear found; beyond the hard limit a polygon is refused (ear clipping is
// quadratic in any case, and no surface format writes such faces on purpose).
constexpr size_t kBestEarLimit = 64;
constexpr size_t kMaxCorners = 100000;

// Point q in the closed triangle (a, b, c), counter-clockwise.
bool in_closed_triangle(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& q) {
    return orient2d(a, b, q) >= 0 && orient2d(b, c, q) >= 0 && orient2d(c, a, q) >= 0;
}

}  // namespace

bool triangulate_polygon(const std::vector<Vec3>& x, const std::vector<int32_t>& corners, std::vector<Tri>& out,
                         std::string& why) {
    const size_t n = corners.size();
    if (n < 3) {
        why = "a face needs at least 3 corners";
        return false;
    }
    if (n > kMaxCorners) {
        why = "a polygon with " + std::to_string(n) + " corners (at most " + std::to_string(kMaxCorners) +
              " can be triangulated)";
        return false;
    }
    {
        std::vector<int32_t> sorted(corners);
        std::sort(sorted.begin(), sorted.end());
        const auto twice = std::adjacent_find(sorted.begin(), sorted.end());
        if (twice != sorted.end()) {
            why = "vertex " + std::to_string(*twice) + " is a corner of the polygon twice";
            return false;
        }
    }
    if (n == 3) {
        out.push_back({corners[0], corners[1], corners[2]});
        return true;
    }
    // Newell's normal: robust for non-convex and slightly non-planar polygons.
    Vec3 normal{0, 0, 0};
    for (size_t i = 0; i < n; ++i) {
        const Vec3& a = x[corners[i]];
        const Vec3& b = x[corners[(i + 1) % n]];
        normal[0] += (a[1] - b[1]) * (a[2] + b[2]);
        normal[1] += (a[2] - b[2]) * (a[0] + b[0]);
        normal[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    int drop = 0;
    for (int k = 1; k < 3; ++k)
        if (std::abs(normal[k]) > std::abs(normal[drop])) drop = k;
    if (!(std::abs(normal[drop]) > 0)) {
        why = "the polygon has no area (its corners are collinear, or it folds back onto itself)";
        return false;
    }
    // The two kept coordinates in cyclic order (drop+1, drop+2) see the polygon
    // counter-clockwise when the normal points along +drop; swap them otherwise.
    int u = (drop + 1) % 3, v = (drop + 2) % 3;
    if (normal[drop] < 0) std::swap(u, v);
    std::vector<Vec2> p(n);
    for (size_t i = 0; i < n; ++i) p[i] = {x[corners[i]][u], x[corners[i]][v]};

    // The remaining ring as a doubly linked list over corner positions.
    std::vector<size_t> prev(n), next(n);
    for (size_t i = 0; i < n; ++i) {
        prev[i] = (i + n - 1) % n;
        next[i] = (i + 1) % n;
    }
    auto is_ear = [&](size_t i) {
        const size_t a = prev[i], c = next[i];
        if (orient2d(p[a], p[i], p[c]) <= 0) return false;
        for (size_t r = next[c]; r != a; r = next[r])
            if (in_closed_triangle(p[a], p[i], p[c], p[r])) return false;
        return true;
    };
    auto quality = [&](size_t i) { return aspect_ratio(x[corners[prev[i]]], x[corners[i]], x[corners[next[i]]]); };

    std::vector<Tri> cut;
    cut.reserve(n - 2);
    size_t remaining = n, start = 0;
    while (remaining > 3) {
        size_t best = n;
        double best_quality = 0.0;
        size_t i = start;
        for (size_t visited = 0; visited < remaining; ++visited, i = next[i]) {
            if (!is_ear(i)) continue;
            if (remaining > kBestEarLimit) {
                best = i;
                break;
            }
            const double q = quality(i);
            // Ties go to the corner that comes first in the face's order.
            if (best == n || q < best_quality || (q == best_quality && i < best)) {
                best = i;
                best_quality = q;
            }
        }
        if (best == n) {
            why = "the polygon is not simple seen along its normal (it crosses itself, or is far from planar)";
            return false;
        }
        cut.push_back({corners[prev[best]], corners[best], corners[next[best]]});
        next[prev[best]] = next[best];
        prev[next[best]] = prev[best];
        start = next[best];
        --remaining;
    }
    const size_t last = start;
    if (orient2d(p[prev[last]], p[last], p[next[last]]) <= 0) {
        why = "the polygon is not simple seen along its normal (it crosses itself, or is far from planar)";
        return false;
    }
    cut.push_back({corners[prev[last]], corners[last], corners[next[last]]});
    out.insert(out.end(), cut.begin(), cut.end());
    return true;
}

void insert_polygons(const InputCursor& in, bool binary, ReaderOutput& out) {
    if (out.polygons.empty()) return;
    Surface& s = out.surface;
    std::vector<Tri> triangles;
    std::vector<int32_t> patches;
    triangles.reserve(s.triangles.size() + 2 * out.polygons.size());
    patches.reserve(triangles.capacity());
    size_t copied = 0;
    size_t largest = 0;
    std::string why;
    for (const PolygonFace& polygon : out.polygons) {
        triangles.insert(triangles.end(), s.triangles.begin() + copied, s.triangles.begin() + polygon.position);
        patches.insert(patches.end(), s.patches.begin() + copied, s.patches.begin() + polygon.position);
        copied = polygon.position;
        if (!triangulate_polygon(s.vertices, polygon.corners, triangles, why)) {
            const std::string message = "face " + std::to_string(polygon.face) + " (" +
                                        std::to_string(polygon.corners.size()) + " corners) cannot be triangulated: " + why;
            if (binary) in.fail_offset(polygon.offset, message);
            in.fail_line(polygon.offset, message);
        }
        patches.resize(triangles.size(), polygon.patch);
        largest = std::max(largest, polygon.corners.size());
    }
    triangles.insert(triangles.end(), s.triangles.begin() + copied, s.triangles.end());
    patches.insert(patches.end(), s.patches.begin() + copied, s.patches.end());
    s.triangles = std::move(triangles);
    s.patches = std::move(patches);
    const PolygonFace& first = out.polygons.front();
    out.triangulated_polygons =
        (binary ? "byte offset " + std::to_string(first.offset) : "line " + std::to_string(in.line_of(first.offset))) +
        ": face " + std::to_string(first.face) + " has " + std::to_string(first.corners.size()) + " corners" +
        (out.polygons.size() > 1 ? " (and " + std::to_string(out.polygons.size() - 1) + " more polygon faces)" : "");
    out.notes.push_back("triangulated " + std::to_string(out.polygons.size()) + " polygon face" +
                        (out.polygons.size() == 1 ? "" : "s") + " (up to " + std::to_string(largest) + " corners)");
    out.polygons.clear();
}

}  // namespace bpm::detail
