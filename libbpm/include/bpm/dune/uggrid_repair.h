#pragma once
// bpm::repair_boundary (bpm/boundary_repair.h) applied to a refined UGGrid built by
// bpm/dune/uggrid_from_bpm.h, through UGGrid::setPosition.
//
// UG puts every new boundary vertex at phi of its parameter point (the PhiBoundarySegment),
// which can invert the thin tetrahedra next to the boundary (femur at 10 %: 163 of 16384 at
// level 1, 1859 of 131072 at level 2). The repair wants a positively oriented mesh on entry,
// as plain refinement gives, so the vertices UG just created on the boundary first go back
// to the midpoints of the edges they split (of the current, repaired positions of the
// edge ends); then repair_boundary moves each towards phi as far as no tetrahedron around
// it inverts or gets too flat; every vertex that moved is written back with setPosition
// (which moves it on all levels). Vertices held back stay on the segment between their
// midpoint and phi; the next call (after the next refinement) gives them another chance.
//
// Interior vertices are smoothed too (repair_boundary's default; options.smooth = false
// keeps them where UG put them). Moving vertices through setPosition is safe for UG's next
// refinement only with the hook of bpm/dune/uggrid_refinement_rules.h, which make_uggrid
// installs: without it UG re-chooses the octahedron diagonal of every refined element from
// the moved corners and rebuilds the elements where the choice changes, dropping the marks
// of their leaves (femur at 10 %: 1048422 instead of 1048576 tetrahedra at level 3 with
// boundary moves only, 3 of them inverted; 130545 instead of 131072 at level 2 with
// smoothing). UG's other per-vertex data that setPosition leaves alone (a vertex's local
// coordinates in its father element, LCVECT) only place nodes UG creates inside faces or
// elements (gm/ugm.cc), which its refinement of tetrahedra does not create.
//
// repair_boundary gets the plain positions too (where plain refinement of the grid as it
// now is puts each boundary vertex refinement created: the weighted corners it was made
// from, below), for its retreat (step 5, bpm/boundary_repair.h): a boundary vertex next to
// a tetrahedron below the angle bound may move back towards its plain position where that
// widens the worst tetrahedron around it. Four boundary vertices that reached phi in
// earlier calls can make a sliver that no interior vertex can widen (femur at 10 %,
// adaptive step 5: 2.02 degrees, cut by UG at an interior edge midpoint into two halves
// of 1.01 degrees each, the mesh's smallest angle; flat refinement has 2.37).
//
// The repair may also slide boundary vertices along S0 (step 6, bpm/boundary_repair.h:
// repair_boundary_sliding; options.slide), which changes their parameter points: they are
// written back into `params`, so the vertices refined later from their edges start from
// them. Four boundary vertices close together on a smooth S0 make a sliver that neither
// the retreat nor smoothing widens (femur at 10 %, adaptive step 5: 3.49 degrees, where a
// level-0 tetrahedron has faces on two neighbouring coarse triangles; all four corners at
// phi would invert it).
//
// Call it after each adapt()/globalRefine(n = 1) and BoundaryParameterPoints::update, with
// what update returned.
//
// Local (red-green) refinement: UG replaces a green closure by red refinement of its father
// when a neighbour is refined further, and the father's new children take the father's edge
// midpoints as corners: vertices an earlier call moved (boundary vertices towards phi,
// interior vertices by smoothing) while checking only the green children then present.
// Such a child can be inverted before any new vertex moves (femur at 10 %, adaptive
// bpm-torsion: 3-9 inverted tets after the repair at steps 3-4 with no reset, 0 when
// refined flat). So, while the grid with the new vertices at their midpoints has inverted
// tetrahedra, their corners that refinement created go back to where plain refinement puts
// them (the midpoints of the edges they split, or the centre of the father for the centre
// nodes of some green rules), coarser levels first, and level-0 corners that smoothing
// moved go back to where the grid was built (UGGridFromBpm::level0_positions); when every
// such corner of an inverted tetrahedron is back, the father corners they were made from
// follow, and so on, round after round until no tetrahedron is inverted or no corner of
// one is left to reset (each round resets at least one vertex not reset before, so there
// are at most #V rounds). Flat refinement of a positive grid is positive, so resetting
// far enough gives a positive grid. The reset vertices then take part in the repair like
// the new ones; `reset` (if given) counts them. (Resetting only boundary vertices left 1-7
// inverted tets at adaptive steps 3-4 on the femur with interior smoothing;
// bench/RESULTS.md. A cap of 16 rounds left 252 tets inverted at femur's adaptive step 6
// once the repair's angle guard compared the worst tetrahedron around a vertex, 34 of them
// still inverted after the repair: the reset had to reach further there.)

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "bpm/boundary_repair.h"
#include "bpm/dune/uggrid_from_bpm.h"
#include "bpm/errors.h"
#include "bpm/phi_evaluation.h"
#include "bpm/predicates.h"

namespace bpm::dune {

// \pre `added` is what params.update(grid) returned after the last refinement, and no
//      vertex has been moved since.
// `params` gets the new parameter points of the vertices the repair slid (step 6).
// \pre the grid was made by make_uggrid (or keep_uggrid_refinement_rules() was called)
// \throw AlgorithmError if a vertex of `added` or one of its edge ends is not a leaf
//        vertex; what repair_boundary throws.
inline BoundaryRepairResult repair_uggrid(UGGrid3& grid, BoundaryParameterPoints& params,
                                          const std::vector<BoundaryParameterPoints::NewVertex>& added,
                                          const PhiEvaluator& phi,
                                          const BoundaryRepairOptions& options = {},
                                          int64_t* reset = nullptr) {
    const auto view = grid.leafGridView();
    const auto& index = view.indexSet();
    const auto& ids = grid.globalIdSet();
    const size_t n = static_cast<size_t>(view.size(3));
    std::vector<Vec3> x(n);
    std::vector<SurfacePoint> points(n);
    std::vector<BoundaryParameterPoints::IdType> id_of(n);
    std::map<BoundaryParameterPoints::IdType, size_t> by_id;
    for (const auto& vertex : vertices(view)) {
        const size_t i = index.index(vertex);
        const auto c = vertex.geometry().corner(0);
        x[i] = {c[0], c[1], c[2]};
        const auto id = ids.id(vertex);
        if (const SurfacePoint* p = params.find(id)) points[i] = *p;
        by_id.emplace(id, i);
        id_of[i] = id;
    }
    auto leaf_index = [&](BoundaryParameterPoints::IdType id) {
        const auto it = by_id.find(id);
        if (it == by_id.end()) throw AlgorithmError("bpm::dune::repair_uggrid: a refined boundary vertex is not a leaf vertex");
        return it->second;
    };
    const std::vector<Vec3> in_grid = x;
    for (const auto& v : added)  // coarser levels first: ends are placed before their midpoints
        x[leaf_index(v.vertex)] = 0.5 * (x[leaf_index(v.ends[0])] + x[leaf_index(v.ends[1])]);

    std::vector<Tet> tetrahedra;
    tetrahedra.reserve(static_cast<size_t>(view.size(0)));
    for (const auto& element : elements(view))
        tetrahedra.push_back({static_cast<int32_t>(index.subIndex(element, 0, 3)),
                              static_cast<int32_t>(index.subIndex(element, 1, 3)),
                              static_cast<int32_t>(index.subIndex(element, 2, 3)),
                              static_cast<int32_t>(index.subIndex(element, 3, 3))});

    // Vertices of inverted tetrahedra back to where plain refinement puts them (see above):
    // for each vertex refinement created, the corners of the father it was made in and
    // their weights, read off geometryInFather on the level where the vertex first appears.
    // Mostly an edge midpoint (two corners at 1/2); some of UG's irregular (green) rules of
    // a tetrahedron add a centre node (four corners at 1/4: elephant at 5 %, adaptive step
    // 3), which smoothing moves like any interior vertex. (Taking only midpoints left those
    // where they were, and their moved fathers' children inverted.)
    // Also the level on which each vertex appears (0 for level-0 vertices): the order in
    // which reset vertices are placed again, the father's corners first. (Not vertex.level()
    // of the leaf view: that is the finest level the vertex is on, the same for a midpoint
    // and its ends wherever both are corners of the same leaf elements. Sorting by it placed
    // midpoints before their ends had moved back; at femur adaptive step 6 and elephant
    // step 5, tets stayed inverted after the reset and 10 and 2 after the repair.)
    using IdType = BoundaryParameterPoints::IdType;
    struct MadeFrom {
        std::array<IdType, 4> corner;
        std::array<double, 4> weight;
        int count = 0;
    };
    std::map<IdType, MadeFrom> made_from;
    std::vector<int> created_on(n, 0);
    for (int level = 1; level <= grid.maxLevel(); ++level) {
        for (const auto& element : elements(grid.levelGridView(level))) {
            const auto in_father = element.geometryInFather();
            const auto father = element.father();
            for (int c = 0; c < 4; ++c) {
                const auto id = ids.subId(element, c, 3);
                if (made_from.count(id) || params.level0_position(id)) continue;
                const auto local = in_father.corner(c);
                const std::array<double, 4> w{1 - local[0] - local[1] - local[2], local[0], local[1], local[2]};
                MadeFrom m;
                bool father_corner = false;
                for (int k = 0; k < 4; ++k) {
                    if (std::abs(w[k] - 1) < 1e-9) father_corner = true;
                    if (std::abs(w[k]) < 1e-9) continue;
                    m.corner[static_cast<size_t>(m.count)] = ids.subId(father, k, 3);
                    m.weight[static_cast<size_t>(m.count)] = w[static_cast<size_t>(k)];
                    ++m.count;
                }
                if (father_corner) continue;  // on an earlier level already
                made_from.emplace(id, m);
                if (const auto it = by_id.find(id); it != by_id.end()) created_on[it->second] = level;
            }
        }
    }
    // The father's corners a leaf vertex was made from, if they are all leaf vertices.
    auto made_in_leaf = [&](size_t i) -> const MadeFrom* {
        const auto it = made_from.find(id_of[i]);
        if (it == made_from.end()) return nullptr;
        for (int k = 0; k < it->second.count; ++k)
            if (!by_id.count(it->second.corner[static_cast<size_t>(k)])) return nullptr;
        return &it->second;
    };
    // A level-0 vertex that an earlier call moved (interior smoothing) and that can go back
    // to where the grid was built: its position then, else nullptr.
    auto moved_level0 = [&](size_t i) -> const Vec3* {
        const Vec3* built = params.level0_position(id_of[i]);
        return built && *built != x[i] ? built : nullptr;
    };
    std::vector<char> is_reset(n, 0);
    std::vector<size_t> all_reset;  // the new vertices and those reset below
    for (const auto& v : added) {
        is_reset[leaf_index(v.vertex)] = 1;
        all_reset.push_back(leaf_index(v.vertex));
    }
    int64_t reset_count = 0;
    for (;;) {  // rounds: see the top of this file
        std::vector<size_t> to_reset;
        std::vector<char> queued(n, 0);
        auto queue = [&](size_t i) {
            if (!is_reset[i] && !queued[i] && (made_in_leaf(i) || moved_level0(i))) {
                queued[i] = 1;
                to_reset.push_back(i);
            }
        };
        for (const Tet& t : tetrahedra) {
            const auto& a = x[static_cast<size_t>(t[0])];
            if (orient3d(a, x[static_cast<size_t>(t[1])], x[static_cast<size_t>(t[2])], x[static_cast<size_t>(t[3])]) == 1)
                continue;
            const size_t before = to_reset.size();
            for (int32_t c : t) queue(static_cast<size_t>(c));
            if (to_reset.size() > before) continue;
            // Every corner is back already (or level 0): the corners they were made from follow.
            for (int32_t c : t) {
                const MadeFrom* m = made_in_leaf(static_cast<size_t>(c));
                if (!m) continue;
                for (int k = 0; k < m->count; ++k) queue(by_id.at(m->corner[static_cast<size_t>(k)]));
            }
        }
        if (to_reset.empty()) break;
        for (size_t i : to_reset) is_reset[i] = 1;
        reset_count += static_cast<int64_t>(to_reset.size());
        // Every vertex back so far is placed again, coarser levels first (the corners a
        // vertex was made from are on coarser levels than the vertex): a vertex reset now
        // may be a corner of one reset in an earlier round.
        all_reset.insert(all_reset.end(), to_reset.begin(), to_reset.end());
        std::stable_sort(all_reset.begin(), all_reset.end(),
                         [&](size_t a, size_t b) { return created_on[a] < created_on[b]; });
        for (size_t i : all_reset) {
            if (const MadeFrom* m = made_in_leaf(i)) {
                Vec3 at{0, 0, 0};
                for (int k = 0; k < m->count; ++k) at = at + m->weight[static_cast<size_t>(k)] * x[by_id.at(m->corner[static_cast<size_t>(k)])];
                x[i] = at;
            } else if (const Vec3* built = params.level0_position(id_of[i])) {
                x[i] = *built;
            }
        }
    }
    if (reset) *reset = reset_count;

    // Where plain refinement puts each vertex refinement created (of the positions now),
    // for repair_boundary's retreat (step 5).
    std::vector<Vec3> plain = x;
    for (size_t i = 0; i < n; ++i)
        if (points[i].valid())
            if (const MadeFrom* m = made_in_leaf(i)) {
                Vec3 at{0, 0, 0};
                for (int k = 0; k < m->count; ++k) at = at + m->weight[static_cast<size_t>(k)] * x[by_id.at(m->corner[static_cast<size_t>(k)])];
                plain[i] = at;
            }
    const std::vector<SurfacePoint> points_before = points;
    const BoundaryRepairResult result = repair_boundary_sliding(phi, x, tetrahedra, points, plain, options);
    for (size_t i = 0; i < n; ++i)
        if (points[i] != points_before[i]) params.set(id_of[i], points[i]);

    for (const auto& vertex : vertices(view)) {
        const size_t i = index.index(vertex);
        if (x[i] != in_grid[i]) grid.setPosition(vertex, {x[i][0], x[i][1], x[i][2]});
    }
    return result;
}

}  // namespace bpm::dune
