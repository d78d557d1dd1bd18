#pragma once
// Local (red-green) refinement of a Dune::UGGrid<3> that Debian's UG 2.9 carries out
// correctly: the marks of one refinement step are applied in several adapt() calls, one per
// level of the elements UG actually refines, coarsest first.
//
// Why. UG refines a marked leaf only if it is regular; a mark on an irregular leaf (a child
// of a green closure) goes to its first regular ancestor (UG::D3::ELEMENT_TO_MARK), which
// is then refined red instead of its green closure. One adapt() can go wrong when it refines
// such an ancestor F (regular, already refined green) red while one of F's green children
// also gets a closure mark, because an element of the children's level that is refined red
// in the same adapt() shares an edge with it. Then, in dune-uggrid 2.9's gm/refine.cc:
//   - RestrictMarks (down the levels) sees a marked son of the green-refined F and calls
//     RestrictElementMark, which replaces F's red mark by F's old green rule (its test
//     `MARK(theElement) != RED` compares a rule number with the enumerator RED = 2);
//   - GridClosure (up the levels) computes the edge patterns, and so the green closure of
//     F's neighbours, from that old green rule, but SetElementRules gives every red-class
//     tetrahedron a full red rule (theFullRefRule, DUNE_UGGRID_TET_RULESET);
//   - where F's red refinement splits an edge that neither F's old rule nor any other
//     refinement of that adapt() splits, F's red children do not match the children of a
//     neighbour whose green rule did not change, and Connect_Sons_of_ElementSide pairs son
//     faces that do not match: the assertion `VCOUNT(Vector0)==1 && VCOUNT(Vector1)==1` in
//     DisposeDoubledSideVector aborts the process when a paired face is already shared,
//     and otherwise the neighbour relation is silently wrong.
// Measured with a wrapper around Connect_Sons_of_ElementSide comparing the son faces of
// both sides (random marks, 10 % of the leaves per step, on a cube of 48 tetrahedra, 20
// runs of 5 steps): one adapt() per step aborted 17 of the 20 runs and mismatched son
// faces in 43 adapts that did not abort (so trying an adapt() in a forked child and keeping
// it when the child survives is no remedy); grouped by level as here, no abort and no
// mismatch in 256 adapts of the same runs. examples/dune/uggrid_adapt_test.cpp pins the
// rule: on that cube after one tetrahedron was refined, one adapt() of an irregular leaf a
// and a regular leaf R of the next level next to a's siblings goes wrong for 100 of the
// 140 such pairs, a alone and R alone never do, and adapt_uggrid of the pair always works.
//
// Why grouping avoids it: when every element UG refines in one adapt() lies on the same
// level L, no element of level L + 1 or finer is refined red, so no child of a level-L
// element gets a closure mark and RestrictElementMark is not called for marked elements
// (RestrictMarks keeps the rules of red-refined elements as they are).
//
// The marks of later groups are kept by global id: an earlier group can replace a marked
// leaf (its father's green closure is rebuilt); such marks are dropped (`superseded`).

#include <cstdint>
#include <map>
#include <vector>

#include <dune/grid/uggrid.hh>

namespace bpm::dune {

using UGGrid3Element = Dune::UGGrid<3>::LeafGridView::Codim<0>::Entity;

// The level of the element UG refines when `leaf` is marked: that of its first regular
// ancestor (the leaf itself if it is regular).
inline int uggrid_refined_level(const UGGrid3Element& leaf) {
    auto e = leaf;
    while (!e.isRegular()) e = e.father();
    return e.level();
}

struct UGGridAdaptResult {
    int adapts = 0;          // adapt() calls made
    int64_t marked = 0;      // marks applied
    int64_t superseded = 0;  // marked leaves an earlier adapt() of this call had replaced
};

// Refines every leaf in `marks` once (red, with UG's green closure), in one adapt() per
// level of the elements UG refines (uggrid_refined_level), coarsest first; calls
// after_adapt() after each adapt() (for instance to track new boundary vertices and
// repair, which must run before the next adapt() moves on).
// \pre grid's refinement type is local with green closure (UGGrid's default)
template <class AfterAdapt>
UGGridAdaptResult adapt_uggrid(Dune::UGGrid<3>& grid, const std::vector<UGGrid3Element>& marks, AfterAdapt&& after_adapt) {
    using Id = Dune::UGGrid<3>::GlobalIdSet::IdType;
    const auto& ids = grid.globalIdSet();
    std::map<int, std::vector<Id>> by_level;
    for (const auto& leaf : marks) by_level[uggrid_refined_level(leaf)].push_back(ids.id(leaf));
    UGGridAdaptResult result;
    bool first = true;
    for (const auto& [level, group] : by_level) {
        std::vector<UGGrid3Element> leaves;
        if (first) {
            // Nothing has changed yet: the marks are the given leaves.
            for (const auto& leaf : marks)
                if (uggrid_refined_level(leaf) == level) leaves.push_back(leaf);
        } else {
            std::map<Id, UGGrid3Element> leaf_by_id;
            for (const auto& leaf : elements(grid.leafGridView())) leaf_by_id.emplace(ids.id(leaf), leaf);
            for (const Id& id : group) {
                const auto it = leaf_by_id.find(id);
                if (it == leaf_by_id.end()) {
                    ++result.superseded;
                    continue;
                }
                leaves.push_back(it->second);
            }
        }
        first = false;
        if (leaves.empty()) continue;
        for (const auto& leaf : leaves) grid.mark(1, leaf);
        grid.preAdapt();
        grid.adapt();
        grid.postAdapt();
        ++result.adapts;
        result.marked += static_cast<int64_t>(leaves.size());
        after_adapt();
    }
    return result;
}

}  // namespace bpm::dune
