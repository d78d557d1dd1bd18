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
// Without interior smoothing: UG keeps, for every vertex it created, its father element
// and local coordinates there, and setPosition does not update them. Moving interior
// vertices (repair_boundary's smoothing) makes UG's next refinement leave elements out:
// femur at 10 %, level 2 after a smoothed level-1 repair had 130545 instead of 131072
// tetrahedra, 13 of them inverted before the repair. Boundary vertices moving along their
// segment disturb it much less (131072 tetrahedra, 0 inverted at level 2), so repair_uggrid
// refuses options with smooth = true; uggrid_repair_options() gives the defaults without it.
// Known limit (open): they still disturb it a little. Femur at 10 %, level 3 after
// repaired levels 1 and 2: 1048422 instead of 1048576 tetrahedra, and 3 inverted after the
// repair (8652 with UG's vertices at phi): although globalRefine marks every element red,
// UG refines 104 of the 131072 level-2 elements with irregular rules (678 children instead
// of 832), and 3 of those children are inverted with every new vertex at its edge
// midpoint, which the repair cannot undo (it never moves a vertex onto an inverting
// position, and does not untangle without smoothing). Without any setPosition all 131072
// are refined red.
//
// Call it after each adapt()/globalRefine(n = 1) and BoundaryParameterPoints::update, with
// what update returned.

#include <map>
#include <string>
#include <vector>

#include "bpm/boundary_repair.h"
#include "bpm/dune/uggrid_from_bpm.h"
#include "bpm/errors.h"
#include "bpm/phi_evaluation.h"

namespace bpm::dune {

// BoundaryRepairOptions' defaults with interior smoothing off (see the top of this file).
inline BoundaryRepairOptions uggrid_repair_options() {
    BoundaryRepairOptions options;
    options.smooth = false;
    return options;
}

// \pre `added` is what params.update(grid) returned after the last refinement, and no
//      vertex has been moved since.
// \throw OptionError if options.smooth (see the top of this file); AlgorithmError if a
//        vertex of `added` or one of its edge ends is not a leaf vertex; what
//        repair_boundary throws.
inline BoundaryRepairResult repair_uggrid(UGGrid3& grid, const BoundaryParameterPoints& params,
                                          const std::vector<BoundaryParameterPoints::NewVertex>& added,
                                          const PhiEvaluator& phi,
                                          const BoundaryRepairOptions& options = uggrid_repair_options()) {
    if (options.smooth)
        throw OptionError("bpm::dune::repair_uggrid: interior smoothing moves vertices UG keeps local coordinates "
                          "of, and UG's next refinement then leaves elements out; use uggrid_repair_options()");
    const auto view = grid.leafGridView();
    const auto& index = view.indexSet();
    const auto& ids = grid.globalIdSet();
    const size_t n = static_cast<size_t>(view.size(3));
    std::vector<Vec3> x(n);
    std::vector<SurfacePoint> points(n);
    std::map<BoundaryParameterPoints::IdType, size_t> by_id;
    for (const auto& vertex : vertices(view)) {
        const size_t i = index.index(vertex);
        const auto c = vertex.geometry().corner(0);
        x[i] = {c[0], c[1], c[2]};
        const auto id = ids.id(vertex);
        if (const SurfacePoint* p = params.find(id)) points[i] = *p;
        by_id.emplace(id, i);
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

    const BoundaryRepairResult result = repair_boundary(phi, x, tetrahedra, points, options);

    for (const auto& vertex : vertices(view)) {
        const size_t i = index.index(vertex);
        if (x[i] != in_grid[i]) grid.setPosition(vertex, {x[i][0], x[i][1], x[i][2]});
    }
    return result;
}

}  // namespace bpm::dune
