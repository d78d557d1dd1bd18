#pragma once
// Makes UG keep the red refinement rule of every tetrahedron it has already refined, so
// that moving vertices (UGGrid::setPosition: bpm's repair, interior smoothing) does not
// make UG's next refinement throw away and rebuild part of the hierarchy.
//
// Why: a red tetrahedron splits into 4 corner children and an octahedron that UG cuts along
// one of its three diagonals. UG picks the diagonal with a function of the element's
// *current* corner positions (UG::D3::theFullRefRule, by default ShortestInteriorEdge in
// dune-uggrid's gm/rm.cc). It calls that function not only when an element is first
// refined but, in every AdaptMultiGrid, for every red tetrahedron of every level
// (gm/refine.cc, SetElementRules: "choose best tet_red rule"). If a vertex has moved since
// the element was refined, the shortest diagonal can be another one; then the element's
// new rule differs from the one it was refined with (REFINEMENT_CHANGES), and UG unrefines
// it and refines it again with the other diagonal: its old children and all their
// descendants are deleted, together with the refinement marks of the leaves among them,
// and the new children are only refined as far as the green closure of their neighbours
// asks (irregular rules, fewer and worse-shaped elements). Measured on femur at 10 %
// without this hook: level 3 after repaired levels 1-2 had 1048422 instead of 1048576
// tetrahedra (3 inverted), and with interior smoothing level 2 had 130545 instead of 131072.
//
// The hook: UG's choice for a tetrahedron that is already refined red is the rule it was
// refined with (REFINE); for any other element (a leaf, or one refined green) it is UG's
// own choice, which is what UG does when nothing has moved. Nothing else in UG's
// refinement looks at coordinates (gm/refine.cc: the closure works on edge patterns).
//
// theFullRefRule is a process-wide UG variable: the hook then applies to every UGGrid<3>
// of the process, with no change of behaviour for grids whose vertices never move. UG sets
// the variable back to its default whenever it is initialised again (the first UGGrid after
// all were destroyed), so call keep_uggrid_refinement_rules() after creating a grid
// (bpm::dune::make_uggrid does). Not thread-safe (neither is UG).
//
// Needs Debian's dune-uggrid 2.9 (built with DUNE_UGGRID_TET_RULESET, its default: the
// three full rules are Pattern2Rule[TETRAHEDRON][0x3F] + 0, 1, 2); compile as
// bpm/dune/uggrid_from_bpm.h says.

#include <cstdint>

#include <dune/grid/uggrid.hh>

namespace bpm::dune {

namespace detail {

struct UGRefinementRuleHook {
    UG::D3::FULLREFRULEPTR original = nullptr;  // UG's choice (ShortestInteriorEdge)
    int64_t kept = 0;  // calls where the kept rule differs from what UG would have chosen
};

inline UGRefinementRuleHook& ug_refinement_rule_hook() {
    static UGRefinementRuleHook hook;
    return hook;
}

inline UG::INT kept_full_refinement_rule(UG::D3::ELEMENT* element) {
    UGRefinementRuleHook& hook = ug_refinement_rule_hook();
    const UG::INT chosen = hook.original(element);
    if (UG::D3::ReadCW(element, UG::D3::TAG_CE) != UG::D3::TETRAHEDRON) return chosen;
    if (UG::D3::ReadCW(element, UG::D3::NSONS_CE) == 0) return chosen;  // not refined yet
    if (UG::D3::ReadCW(element, UG::D3::REFINECLASS_CE) != UG::D3::RED_CLASS) return chosen;
    const auto refined_with = static_cast<UG::INT>(UG::D3::ReadCW(element, UG::D3::REFINE_CE));
    const UG::INT first = UG::D3::Pattern2Rule[UG::D3::TETRAHEDRON][0x3F];
    if (refined_with < first || refined_with > first + 2) return chosen;  // not a full red rule
    if (refined_with != chosen) ++hook.kept;
    return refined_with;
}

}  // namespace detail

// Installs the hook (see the top of this file); calling it again is harmless.
// \pre a UGGrid<3> exists (UG is initialised)
inline void keep_uggrid_refinement_rules() {
    detail::UGRefinementRuleHook& hook = detail::ug_refinement_rule_hook();
    if (UG::D3::theFullRefRule == &detail::kept_full_refinement_rule) return;
    hook.original = UG::D3::theFullRefRule;
    UG::D3::theFullRefRule = &detail::kept_full_refinement_rule;
}

// How often, since the process started, UG asked for the rule of a refined tetrahedron
// and the hook answered with its old rule where UG's own choice (by the moved corners)
// would have been another: each such answer saved a subtree from being rebuilt. UG asks
// more than once per element and adapt, so this counts questions, not elements.
inline int64_t uggrid_refinement_rules_kept() { return detail::ug_refinement_rule_hook().kept; }

}  // namespace bpm::dune
