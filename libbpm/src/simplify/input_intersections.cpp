#include "simplify/input_intersections.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "bpm/predicates.h"
#include "check/check_internal.h"
#include "check/improper_pair.h"

namespace bpm::detail {

namespace {
// Beyond this many triangles outside the cells, each tested against every triangle,
// the walk is left to check_intersections (its box intersection has no such case).
constexpr size_t kMaxOversized = 64;

void box_of(const std::vector<Vec3>& V, const Tri& t, Vec3& lo, Vec3& hi) {
    for (int k = 0; k < 3; ++k) {
        lo[k] = std::min({V[t[0]][k], V[t[1]][k], V[t[2]][k]});
        hi[k] = std::max({V[t[0]][k], V[t[1]][k], V[t[2]][k]});
    }
}
}  // namespace

bool surely_passes_intersection_check(const Surface& surface, const TriangleGrid& grid) {
    if (surface_unsafe(surface)) return false;  // the check refuses it
    const auto& V = surface.vertices;
    const auto& T = surface.triangles;
    const size_t nt = T.size();
    if (grid.oversized_entries().size() > kMaxOversized) return false;
    // The check reports degenerate triangles; the grid walk below assumes there are none.
    for (const Tri& t : T)
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || collinear3d(V[t[0]], V[t[1]], V[t[2]])) return false;
    // The cell of each triangle's low corner, where the grid's placement of its box
    // begins (int32: 12 bytes per triangle; a surface with farther cells is left to the check).
    std::vector<std::array<int32_t, 3>> low(nt);
    for (size_t t = 0; t < nt; ++t) {
        Vec3 lo, hi;
        box_of(V, T[t], lo, hi);
        const std::array<int64_t, 3> c = grid.cell_of(lo);
        for (int k = 0; k < 3; ++k) {
            if (std::abs(c[size_t(k)]) > std::numeric_limits<int32_t>::max() / 2) return false;
            low[t][size_t(k)] = int32_t(c[size_t(k)]);
        }
    }
    // The check orders each pair by index before its decision: so does this walk.
    const auto meet = [&](int32_t a, int32_t b) {
        if (a > b) std::swap(a, b);
        return surface_triangles_meet_improperly(V, T[size_t(a)], T[size_t(b)]);
    };
    bool clean = true;
    std::vector<std::array<int32_t, 3>> list_low;  // low[] of a cell's entries, in its order
    grid.for_each_cell([&](uint64_t key, const std::vector<TriangleGrid::Entry>& list) {
        if (!clean) return;
        // Gathered first: the loads of low[] are scattered, and issued together they
        // overlap (in the pair loop they missed the cache one after another: 35 % of it).
        list_low.resize(list.size());
        for (size_t i = 0; i < list.size(); ++i) list_low[i] = low[size_t(list[i].id)];
        for (size_t i = 0; i < list.size() && clean; ++i) {
            const TriangleGrid::Entry& a = list[i];
            const TriangleGrid::LatticeBox box{a.lo, a.hi};
            const auto& la = list_low[i];
            for (size_t j = i + 1; j < list.size(); ++j) {
                const TriangleGrid::Entry& b = list[j];
                if (TriangleGrid::apart(box, b.lo, b.hi)) continue;
                // Decided in the cell of the low corner of the boxes' intersection only.
                const auto& lb = list_low[j];
                if (TriangleGrid::cell_key(std::max(la[0], lb[0]), std::max(la[1], lb[1]), std::max(la[2], lb[2])) != key)
                    continue;
                if (meet(a.id, b.id)) {
                    clean = false;
                    break;
                }
            }
        }
    });
    if (!clean) return false;
    // The oversized triangles are in no cell: each against every other triangle (a pair
    // of two of them once).
    std::vector<int32_t> oversized;
    for (const TriangleGrid::Entry& e : grid.oversized_entries()) oversized.push_back(e.id);
    std::sort(oversized.begin(), oversized.end());
    for (const TriangleGrid::Entry& e : grid.oversized_entries()) {
        const TriangleGrid::LatticeBox box{e.lo, e.hi};
        for (size_t t = 0; t < nt; ++t) {
            const int32_t id = int32_t(t);
            if (id == e.id) continue;
            if (id < e.id && std::binary_search(oversized.begin(), oversized.end(), id)) continue;
            Vec3 lo, hi;
            box_of(V, T[t], lo, hi);
            const TriangleGrid::LatticeBox other = grid.lattice_box(lo, hi);
            if (TriangleGrid::apart(box, other.lo, other.hi)) continue;
            if (meet(e.id, id)) return false;
        }
    }
    return true;
}

}  // namespace bpm::detail
