#include "simplify/sheet_guard.h"

#include <algorithm>

#include "bpm/predicates.h"
#include "core/sheet_order.h"

namespace bpm::detail {

namespace {
int32_t third_corner(const Tri& t, int32_t x, int32_t y) {
    for (int32_t c : t)
        if (c != x && c != y) return c;
    return -1;
}

// The cyclic order of `apexes` around a -> b as the sequence of their indices starting
// at index 0; false if it is not defined (two on one half-plane).
bool cyclic_order(const Vec3& a, const Vec3& b, const std::vector<Vec3>& apexes, std::vector<int32_t>& order) {
    return sort_around_edge(a, b, apexes, order);  // starts at apexes[0]: comparable as is
}
}  // namespace

bool keeps_sheet_order(const CoarseMesh& mesh, const std::vector<int32_t>& removed, const std::vector<Tri>& added,
                       std::vector<int32_t>& tris) {
    const std::vector<Vec3>& x = mesh.positions();
    for (const Tri& t : added)
        for (int k = 0; k < 3; ++k) {
            const int32_t a = t[k], b = t[(k + 1) % 3], q = t[(k + 2) % 3];
            // Every edge of three or more triangles is a hard feature edge: most edges
            // stop at this lookup.
            if (!mesh.is_feature_edge(a, b)) continue;
            mesh.edge_triangles(a, b, tris);
            if (tris.size() < 3) continue;
            int32_t old_apex = -1, replaced = 0;
            int32_t before = -1, after = -1;  // the kept sheets next to the old apex
            for (int32_t u : tris)
                if (std::find(removed.begin(), removed.end(), u) != removed.end()) {
                    old_apex = third_corner(mesh.triangle(u), a, b);
                    ++replaced;
                }
            if (replaced != 1 || tris.size() - 1 < 2) continue;
            // An old triangle without area (apex on the edge's line) lies between no two
            // sheets, and the wedge test below would accept any new apex: refuse. (Input
            // that passed validate_surface has none; this keeps the guard sound anyway.)
            if (old_apex < 0 || collinear3d(x[size_t(a)], x[size_t(b)], x[size_t(old_apex)])) return false;
            const Vec3& p = x[size_t(old_apex)];
            for (int32_t u : tris) {
                if (std::find(removed.begin(), removed.end(), u) != removed.end()) continue;
                const int32_t c = third_corner(mesh.triangle(u), a, b);
                if (c < 0) return false;
                // after: the first kept sheet turning from p; before: the last.
                if (after < 0 || turns_before(x[a], x[b], p, x[c], x[after])) after = c;
                if (before < 0 || turns_before(x[a], x[b], p, x[before], x[c])) before = c;
            }
            if (!strictly_between(x[a], x[b], x[before], x[after], x[q])) return false;
        }
    return true;
}

bool keeps_line_sheet_order(const std::vector<Vec3>& x, int32_t a, int32_t v, int32_t b,
                            const std::vector<std::array<int32_t, 3>>& sheets) {
    if (sheets.size() < 3) return true;  // two sheets have one cyclic order
    std::vector<Vec3> apexes(sheets.size());
    std::vector<int32_t> order_new, order_old;
    for (size_t i = 0; i < sheets.size(); ++i) apexes[i] = x[size_t(sheets[i][2])];
    if (!cyclic_order(x[a], x[b], apexes, order_new)) return false;
    for (int k = 0; k < 2; ++k) {
        for (size_t i = 0; i < sheets.size(); ++i) apexes[i] = x[size_t(sheets[i][k])];
        // Both edges point along the line as a -> b does. An undefined old order (sheets
        // that overlap, or one without area) cannot be said to be kept.
        if (!cyclic_order(k == 0 ? x[a] : x[v], k == 0 ? x[v] : x[b], apexes, order_old)) return false;
        if (order_old != order_new) return false;
    }
    return true;
}

bool line_sheets_of(int32_t a, int32_t b, const std::vector<Fan>& fans, const std::vector<Tri>& added,
                    std::vector<std::array<int32_t, 3>>& sheets) {
    sheets.clear();
    size_t base = 0;
    for (const Fan& fan : fans) {
        const size_t n = fan.link.size();
        if (n < 3) return false;
        const bool from_a = fan.link.front() == a;  // else it runs from b to a
        int32_t found = -1;
        for (size_t i = base; i < base + (n - 2) && i < added.size(); ++i) {
            const Tri& t = added[i];
            const bool has_a = t[0] == a || t[1] == a || t[2] == a, has_b = t[0] == b || t[1] == b || t[2] == b;
            if (has_a && has_b) found = third_corner(t, a, b);
        }
        if (found < 0) return false;
        sheets.push_back({from_a ? fan.link[1] : fan.link[n - 2], from_a ? fan.link[n - 2] : fan.link[1], found});
        base += n - 2;
    }
    return true;
}

}  // namespace bpm::detail
