#pragma once
// The cost of a vertex removal: the key of the simplifier's priority queue, and the
// limits of SimplifyOptions that refuse a removal. Internal to libbpm.
//
// cost = error + aspect_weight * 1e-3 * (log2(worst new R/r / 2) - 0.5 log2(worst removed R/r / 2)
//                                         - log2(max(worst removed, A) / max(worst new, A)))
// with error = max |phi(x) - x| over the new triangles / the bounding-box diagonal, so a
// cost is in units of the diagonal and the same for a model and its scaled copy, and
// A = max_aspect_ratio. The aspect term prefers removals that make better triangles than
// they remove (R/r = 2 is equilateral); its last part (0 unless a removed triangle is
// worse than A) puts removals that repair the input's slivers first. A new term (for example a distortion of phi) goes into removal_cost(),
// with what it needs carried by RemovalPlan.

#include <string>

#include "bpm/simplify.h"
#include "simplify/vertex_removal.h"

namespace bpm::detail {

// What a cost is computed from.
enum class CostBasis {
    Plan,      // a plan's final costs: max_deviation, and the normal limit applies
    Estimate,  // a full plan before (or without) its validation: estimated_deviation, and
               // no normal limit (max_normal_deviation is known only after validation);
               // a plan whose validation failed still has its estimate (plan.estimated)
};

// The queue key of the removal `plan` describes, rounded to 1e-10 so that rounding noise
// (a model and its scaled copy) does not reorder removals; +infinity if the plan is
// invalid (without an estimate, for CostBasis::Estimate) or a limit of `options` refuses
// it (max_error, max_aspect_ratio unless the removed triangles were worse,
// max_edge_length, min_ridge_angle_degrees (simplify/ridge_guard.h), max_normal_deviation_degrees). `why` gets the reason for +infinity
// and is cleared for a finite cost. `diagonal`: of the original's bounding box, > 0.
double removal_cost(const RemovalPlan& plan, const SimplifyOptions& options, double diagonal, CostBasis basis,
                    std::string& why);

}  // namespace bpm::detail
