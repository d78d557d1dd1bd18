#include "simplify/island_guard.h"

#include <algorithm>
#include <numeric>

#include "core/ray_crossing.h"
#include "core/vertex_components.h"

namespace bpm::detail {

namespace {

int32_t find_root(std::vector<int32_t>& parent, int32_t x) {
    while (parent[size_t(x)] != x) {
        parent[size_t(x)] = parent[size_t(parent[size_t(x)])];
        x = parent[size_t(x)];
    }
    return x;
}

bool has_corner(const Tri& t, int32_t x) { return t[0] == x || t[1] == x || t[2] == x; }

// The edges the sheets of a feature-line removal share: v -- a and v -- b (old), a -- b (new).
bool line_edge(int32_t x, int32_t y, int32_t v, int32_t a, int32_t b) {
    const auto is = [&](int32_t p, int32_t q) { return (x == p && y == q) || (x == q && y == p); };
    return a >= 0 && (is(v, a) || is(v, b) || is(a, b));
}

// Whether triangles s and t share an edge that is not a line edge.
bool glued(const Tri& s, const Tri& t, int32_t v, int32_t a, int32_t b) {
    for (int k = 0; k < 3; ++k) {
        const int32_t x = s[k], y = s[(k + 1) % 3];
        if (has_corner(t, x) && has_corner(t, y) && !line_edge(x, y, v, a, b)) return true;
    }
    return false;
}

}  // namespace

IslandGuard::IslandGuard(const CoarseMesh& mesh) {
    VertexComponents components(mesh.positions().size());
    for (int32_t t = 0; t < mesh.triangle_capacity(); ++t)
        if (mesh.alive(t)) components.add(mesh.triangle(t));
    std::vector<int32_t> id;
    components_ = components.number(id);
    if (components_ > 1) component_ = std::move(id);
}

bool IslandGuard::sweeps_island(const CoarseMesh& mesh, const TriangleGrid& grid, int32_t first_unindexed, int32_t v,
                                int32_t a, int32_t b, const std::vector<int32_t>& removed,
                                const std::vector<Tri>& added, Scratch& scratch) const {
    if (component_.empty() || removed.empty()) return false;
    const std::vector<Vec3>& x = mesh.positions();
    const int32_t home = component_[size_t(v)];
    // The box of the swept volume: of the old triangles (the new ones have their corners).
    Vec3 lo = x[size_t(v)], hi = x[size_t(v)];
    for (int32_t t : removed)
        for (int32_t c : mesh.triangle(t))
            for (int k = 0; k < 3; ++k) {
                lo[k] = std::min(lo[k], x[size_t(c)][k]);
                hi[k] = std::max(hi[k], x[size_t(c)][k]);
            }
    // Candidates: one vertex per other component with a triangle inside the box. Another
    // component shares no vertex with the old or the new triangles, so (the intersection
    // test passed, and the surface does not intersect itself) it meets neither: it lies
    // wholly inside the swept volume or wholly outside (the header says which volume along
    // a feature line), one vertex decides, and inside
    // means inside the box. A component that reaches out of the box (a triangle partly
    // outside) is outside, or it crosses a new triangle, which the intersection test
    // refuses: only components with a triangle wholly inside are tested (a triangle per
    // component suffices; every triangle of an enclosed one is inside).
    scratch.components.clear();
    scratch.points.clear();
    const auto consider = [&](int32_t t) {
        if (!mesh.alive(t)) return;
        const Tri& c = mesh.triangle(t);
        const int32_t k = component_[size_t(c[0])];
        if (k == home) return;
        for (int32_t corner : c)
            for (int d = 0; d < 3; ++d)
                if (x[size_t(corner)][d] < lo[d] || x[size_t(corner)][d] > hi[d]) return;
        if (std::find(scratch.components.begin(), scratch.components.end(), k) != scratch.components.end()) return;
        scratch.components.push_back(k);
        scratch.points.push_back(c[0]);
    };
    grid.query_within(lo, hi, scratch.entries);
    for (const TriangleGrid::Entry& e : scratch.entries) consider(e.id);
    for (int32_t t = first_unindexed; t < mesh.triangle_capacity(); ++t) consider(t);
    if (scratch.points.empty()) return false;

    // The sheets: old and new triangles glued along their edges but the line's, one group
    // per sheet (without a feature line one group). Sheets never share another edge: a
    // link vertex of two sheets would make its edge to v a feature edge.
    scratch.tris.clear();
    for (int32_t t : removed) scratch.tris.push_back(mesh.triangle(t));
    scratch.tris.insert(scratch.tris.end(), added.begin(), added.end());
    const size_t n = scratch.tris.size();
    std::vector<int32_t>& group = scratch.group;
    group.resize(n);
    std::iota(group.begin(), group.end(), 0);
    if (a >= 0)
        for (size_t i = 0; i < n; ++i)
            for (size_t j = 0; j < i; ++j)
                if (glued(scratch.tris[i], scratch.tris[j], v, a, b)) {
                    const int32_t r = find_root(group, int32_t(i)), s = find_root(group, int32_t(j));
                    if (r != s) group[size_t(std::max(r, s))] = std::min(r, s);
                }
    size_t sheets = 0;
    for (size_t i = 0; i < n; ++i) {
        group[i] = a >= 0 ? find_root(group, int32_t(i)) : 0;
        if (group[i] == int32_t(i)) ++sheets;
    }
    // One surface (no feature line, or a line with one sheet): closed (by (a, v, b) along
    // a line), and a point is swept when it lies inside. Two or more sheets along a line:
    // swept when the sheets' parities differ (see the header), which the closing triangle
    // flips for all sheets at once: left out.
    const bool closed = sheets == 1;
    for (int32_t q : scratch.points) {
        const Vec3& p = x[size_t(q)];
        // Parity per group; groups are named by their smallest member.
        int first = -1;  // the first sheet's parity
        for (size_t g = 0; g < n; ++g) {
            if (group[g] != int32_t(g)) continue;
            bool odd = false;
            for (size_t i = 0; i < n; ++i) {
                if (group[i] != int32_t(g)) continue;
                const Tri& t = scratch.tris[i];
                const RayHit h = ray_crosses(p, x[size_t(t[0])], x[size_t(t[1])], x[size_t(t[2])]);
                if (h == RayHit::Touches) return true;  // on the swept surface: refuse (not after a passed test)
                if (h == RayHit::Cross) odd = !odd;
            }
            if (closed) {
                if (a >= 0) {  // the sheet's closing triangle
                    const RayHit h = ray_crosses(p, x[size_t(a)], x[size_t(v)], x[size_t(b)]);
                    if (h == RayHit::Touches) return true;
                    if (h == RayHit::Cross) odd = !odd;
                }
                if (odd) return true;
            } else if (first < 0) {
                first = odd;
            } else if (int(odd) != first) {
                return true;
            }
        }
    }
    return false;
}

}  // namespace bpm::detail
