#pragma once
// The sheet-order guard: a removal (or an edge flip) must not turn a sheet past another
// around a junction edge (an edge of three or more triangles). Two triangles that share
// an edge never intersect, so the intersection test lets such a turn pass, but the
// wedges between the sheets then face other materials and the regions of the volume
// change (bpm-check's junctions check; core/sheet_order.h decides exactly).
//
//   keeps_sheet_order       for every edge of a new triangle that exists already with
//                           two or more other triangles: the new apex lies strictly in
//                           the wedge between the neighbouring sheets that held the
//                           removed triangle's apex. Reads the current coarse surface, so
//                           the simplifier asks just before it commits (the sheets of the
//                           other side may have changed since the plan was made).
//   keeps_line_sheet_order  a removal along a feature line of three or more sheets: the
//                           sheets around the new edge a -- b come in the order they have
//                           around the two edges a -- v and v -- b it replaces. Where an
//                           order is not defined (two sheets on one half-plane, a sheet
//                           without area) it is not kept: refused.
//   line_sheets_of          which apexes keeps_line_sheet_order compares, from the plan's
//                           half-disks; false (the plan is refused) when a half-disk has no
//                           new triangle at a -- b.
// Internal to libbpm.

#include <array>
#include <cstdint>
#include <vector>

#include "bpm/geometry.h"
#include "simplify/coarse_mesh.h"
#include "simplify/star_fans.h"

namespace bpm::detail {

// The reason recorded for a refused removal (counted in the simplifier's "vertices kept").
inline constexpr const char* kSheetOrderReason = "would turn a sheet past another around a junction edge (sheet order)";

// `removed`: the triangles the change removes (alive in `mesh`); `added`: the new ones.
// `scratch` is a buffer.
bool keeps_sheet_order(const CoarseMesh& mesh, const std::vector<int32_t>& removed, const std::vector<Tri>& added,
                       std::vector<int32_t>& scratch);

// `sheets[i]`: the apexes of sheet i's triangles at a -- v and at v -- b, and of its new
// triangle at a -- b. All triangles at a -- v and v -- b are in the removed star, so the
// answer holds as long as the plan does.
bool keeps_line_sheet_order(const std::vector<Vec3>& x, int32_t a, int32_t v, int32_t b,
                            const std::vector<std::array<int32_t, 3>>& sheets);

// `sheets` for the removal of v along the feature line a -- v -- b, from its half-disks
// `fans` (each runs from a to b or back; link[1] and link[n - 2] are the apexes of its
// triangles at the line) and `added`, the fans' new triangles in fan order, n - 2 each.
// False when a half-disk has no new triangle at a -- b (the layout is not the expected
// one): no order can be compared, and the removal must be refused, not let pass.
bool line_sheets_of(int32_t a, int32_t b, const std::vector<Fan>& fans, const std::vector<Tri>& added,
                    std::vector<std::array<int32_t, 3>>& sheets);

}  // namespace bpm::detail
