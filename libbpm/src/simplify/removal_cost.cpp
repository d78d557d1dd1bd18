#include "simplify/removal_cost.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "simplify/distortion.h"
#include "simplify/ridge_guard.h"

namespace bpm::detail {

double removal_cost(const RemovalPlan& plan, const SimplifyOptions& options, double diagonal, CostBasis basis,
                    std::string& why) {
    const bool estimate = basis == CostBasis::Estimate;
    // Reasons name the SimplifyOptions field that refused (bpm-simplify shows its flag).
    constexpr double kRefused = std::numeric_limits<double>::infinity();
    if (!plan.valid && !(estimate && plan.estimated)) {
        why = plan.reason;
        return kRefused;
    }
    const double error = (estimate ? plan.estimated_deviation : plan.max_deviation) / diagonal;
    if (error > options.max_error) {
        why = "geometric error limit (max_error)";
        return kRefused;
    }
    if (plan.worst_new_aspect > std::max(options.max_aspect_ratio, plan.worst_old_aspect)) {
        why = kShapeLimitReason;
        return kRefused;
    }
    if (plan.longest_new_edge > options.max_edge_length * diagonal) {
        why = "edge length limit (max_edge_length)";
        return kRefused;
    }
    if (ridge_too_sharp(plan.sharpest_new_ridge, plan.sharpest_original_ridge, options.min_ridge_angle_degrees)) {
        why = "ridge angle limit (min_ridge_angle_degrees)";
        return kRefused;
    }
    if (!estimate && plan.max_normal_deviation > options.max_normal_deviation_degrees) {
        why = "normal deviation limit (max_normal_deviation_degrees)";
        return kRefused;
    }
    why.clear();
    // A removal that takes out a triangle above max_aspect_ratio (an input sliver, which
    // no removal may create) and leaves better ones also gets full credit for the part of
    // the excess it repairs. With the half credit alone, a needle around an edge 1e-4 of
    // the diagonal long (femur) stayed to the end: removing its vertex cost more than its
    // neighbours' removals, and after those its removal made worse triangles still, so
    // bpm-mesh got a coarse triangle of R/r 92.8 and tets of 0.55 degrees.
    const double limit = options.max_aspect_ratio;
    const double repaired_excess =
        std::log2(std::max(plan.worst_old_aspect, limit) / std::max(plan.worst_new_aspect, limit));
    const double aspect_term = std::log2(std::max(plan.worst_new_aspect, 2.0) / 2.0) -
                               0.5 * std::log2(std::max(plan.worst_old_aspect, 2.0) / 2.0) - repaired_excess;
    // Costs are compared after rounding to 1e-10 (relative to the diagonal), so that
    // rounding noise, e.g. between a model and its scaled copy, does not reorder
    // removals (the queue breaks exact ties by the smaller vertex id).
    // The distortion term (simplify/distortion.h) is 0 unless SimplifyOptions::distortion_weight
    // or fold_limit_degrees ask for it: off by default (bench/RESULTS.md, issue 19 item 2).
    const double distortion =
        distortion_cost(plan.max_normal_deviation, options.distortion_weight, options.fold_limit_degrees) +
        fold_cost(plan.max_normal_deviation, options.fold_weight);
    return std::round((error + options.aspect_weight * 1e-3 * aspect_term + distortion) * 1e10) * 1e-10;
}

}  // namespace bpm::detail
