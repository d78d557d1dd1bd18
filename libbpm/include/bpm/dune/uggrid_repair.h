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
// tetrahedra, their corners that refinement created (any vertex but a level-0 one) go back
// to the midpoints of the edges they split, coarser levels first; when every such corner of
// an inverted tetrahedron is back, the ends of their edges follow, and so on (at most 16
// rounds). Flat refinement of a positive grid is positive, so resetting far enough gives a
// positive grid. The reset vertices then take part in the repair like the new ones; `reset`
// (if given) counts them. (Resetting only boundary vertices left 1-7 inverted tets at
// adaptive steps 3-4 on the femur with interior smoothing; bench/RESULTS.md.)

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
// \pre the grid was made by make_uggrid (or keep_uggrid_refinement_rules() was called)
// \throw AlgorithmError if a vertex of `added` or one of its edge ends is not a leaf
//        vertex; what repair_boundary throws.
inline BoundaryRepairResult repair_uggrid(UGGrid3& grid, const BoundaryParameterPoints& params,
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
    std::vector<int> vertex_level(n, 0);
    std::vector<BoundaryParameterPoints::IdType> id_of(n);
    std::map<BoundaryParameterPoints::IdType, size_t> by_id;
    for (const auto& vertex : vertices(view)) {
        const size_t i = index.index(vertex);
        vertex_level[i] = vertex.level();
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

    // Vertices of inverted tetrahedra back to the midpoints of their edges (see above). The
    // edge a vertex splits: the two corners of the father at whose midpoint the vertex is a
    // corner of a child (UG refines tetrahedra only at edge midpoints), on the level where
    // the vertex first appears.
    std::map<BoundaryParameterPoints::IdType, std::array<BoundaryParameterPoints::IdType, 2>> ends;
    for (int level = 1; level <= grid.maxLevel(); ++level) {
        for (const auto& element : elements(grid.levelGridView(level))) {
            const auto in_father = element.geometryInFather();
            const auto father = element.father();
            for (int c = 0; c < 4; ++c) {
                const auto id = ids.subId(element, c, 3);
                if (ends.count(id)) continue;
                const auto local = in_father.corner(c);
                const std::array<double, 4> w{1 - local[0] - local[1] - local[2], local[0], local[1], local[2]};
                int halves = 0, zeros = 0;
                std::array<int, 2> at{-1, -1};
                for (int k = 0; k < 4; ++k) {
                    if (std::abs(w[k] - 0.5) < 1e-9) {
                        if (halves < 2) at[static_cast<size_t>(halves)] = k;
                        ++halves;
                    } else if (std::abs(w[k]) < 1e-9) {
                        ++zeros;
                    }
                }
                if (halves == 2 && zeros == 2)
                    ends.emplace(id, std::array<BoundaryParameterPoints::IdType, 2>{ids.subId(father, at[0], 3),
                                                                                    ids.subId(father, at[1], 3)});
            }
        }
    }
    auto ends_in_leaf = [&](size_t i) -> const std::array<BoundaryParameterPoints::IdType, 2>* {
        const auto it = ends.find(id_of[i]);
        if (it == ends.end() || !by_id.count(it->second[0]) || !by_id.count(it->second[1])) return nullptr;
        return &it->second;
    };
    std::vector<char> is_reset(n, 0);
    std::vector<size_t> all_reset;  // the new vertices and those reset below
    for (const auto& v : added) {
        is_reset[leaf_index(v.vertex)] = 1;
        all_reset.push_back(leaf_index(v.vertex));
    }
    int64_t reset_count = 0;
    for (int round = 0; round < 16; ++round) {
        std::vector<size_t> to_reset;
        std::vector<char> queued(n, 0);
        auto queue = [&](size_t i) {
            if (!is_reset[i] && !queued[i] && ends_in_leaf(i)) {
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
            // Every corner is back already (or level 0): the ends of their edges follow.
            for (int32_t c : t) {
                const auto* e = ends_in_leaf(static_cast<size_t>(c));
                if (!e) continue;
                queue(by_id.at((*e)[0]));
                queue(by_id.at((*e)[1]));
            }
        }
        if (to_reset.empty()) break;
        for (size_t i : to_reset) is_reset[i] = 1;
        reset_count += static_cast<int64_t>(to_reset.size());
        // Every vertex back so far is placed again, coarser levels first (the ends of an edge
        // are on coarser levels than its midpoint): a vertex reset now may be the end of one
        // reset in an earlier round.
        all_reset.insert(all_reset.end(), to_reset.begin(), to_reset.end());
        std::stable_sort(all_reset.begin(), all_reset.end(),
                         [&](size_t a, size_t b) { return vertex_level[a] < vertex_level[b]; });
        for (size_t i : all_reset) {
            const auto* e = ends_in_leaf(i);
            if (e) x[i] = 0.5 * (x[by_id.at((*e)[0])] + x[by_id.at((*e)[1])]);
        }
    }
    if (reset) *reset = reset_count;

    const BoundaryRepairResult result = repair_boundary(phi, x, tetrahedra, points, options);

    for (const auto& vertex : vertices(view)) {
        const size_t i = index.index(vertex);
        if (x[i] != in_grid[i]) grid.setPosition(vertex, {x[i][0], x[i][1], x[i][2]});
    }
    return result;
}

}  // namespace bpm::dune
