// The cost of a vertex removal (simplify/removal_cost.h), tested on hand-made plans: the
// formula, the limits that refuse a removal with their reason, what an estimate may skip,
// and that a scaled model gets the same costs.
#include <cmath>
#include <string>

#include <catch2/catch.hpp>

#include "simplify/removal_cost.h"

using namespace bpm;
using namespace bpm::detail;

namespace {

RemovalPlan valid_plan(double deviation, double new_aspect, double old_aspect) {
    RemovalPlan plan;
    plan.valid = true;
    plan.estimated = true;
    plan.max_deviation = deviation;
    plan.estimated_deviation = deviation;
    plan.worst_new_aspect = new_aspect;
    plan.worst_old_aspect = old_aspect;
    plan.longest_new_edge = 1.0;
    return plan;
}

}  // namespace

TEST_CASE("removal cost: error over the diagonal plus the aspect term, reason cleared", "[internal][simplify]") {
    SimplifyOptions options;
    std::string why = "left from before";
    // error 0.01; aspect term log2(8 / 2) - 0.5 log2(8 / 2) = 1.
    const double cost = removal_cost(valid_plan(0.1, 8.0, 8.0), options, 10.0, CostBasis::Plan, why);
    CHECK(cost == Approx(0.01 + 1e-3).epsilon(1e-9));
    CHECK(why.empty());
    // Better triangles than the removed ones lower the cost; aspect_weight 0 removes the term.
    CHECK(removal_cost(valid_plan(0.1, 2.0, 8.0), options, 10.0, CostBasis::Plan, why) < 0.01);
    options.aspect_weight = 0.0;
    CHECK(removal_cost(valid_plan(0.1, 8.0, 2.0), options, 10.0, CostBasis::Plan, why) == Approx(0.01));
}

TEST_CASE("removal cost: removing a triangle worse than max_aspect_ratio gets credit for the excess it repairs",
          "[internal][simplify]") {
    SimplifyOptions options;  // max_aspect_ratio 30
    std::string why;
    // Femur's needle: the removed triangles' worst is 92.8, the new ones' 35.2 (allowed,
    // since the removed were worse). Credit log2(92.8 / 35.2) on top of the usual term.
    const double usual = std::log2(35.2 / 2.0) - 0.5 * std::log2(92.8 / 2.0);
    const double repaired = std::log2(92.8 / 35.2);
    CHECK(removal_cost(valid_plan(0.1, 35.2, 92.8), options, 10.0, CostBasis::Plan, why) ==
          Approx(0.01 + 1e-3 * (usual - repaired)).epsilon(1e-8));
    // New triangles within the limit: the credit counts from the limit, not from them.
    CHECK(removal_cost(valid_plan(0.1, 4.0, 92.8), options, 10.0, CostBasis::Plan, why) ==
          Approx(0.01 + 1e-3 * (std::log2(2.0) - 0.5 * std::log2(46.4) - std::log2(92.8 / 30.0))).epsilon(1e-8));
    // Nothing above the limit removed: no credit.
    CHECK(removal_cost(valid_plan(0.1, 8.0, 29.0), options, 10.0, CostBasis::Plan, why) ==
          Approx(0.01 + 1e-3 * (std::log2(4.0) - 0.5 * std::log2(14.5))).epsilon(1e-8));
}

TEST_CASE("removal cost: a scaled model gets exactly the same cost", "[internal][simplify]") {
    SimplifyOptions options;
    std::string why;
    const double diagonal = 1.7320508075688772;
    const double a = removal_cost(valid_plan(0.0123456789 * diagonal, 3.3, 2.5), options, diagonal, CostBasis::Plan, why);
    const double scale = 1000.0 / 3.0;
    const double b = removal_cost(valid_plan(0.0123456789 * diagonal * scale, 3.3, 2.5), options, diagonal * scale,
                                  CostBasis::Plan, why);
    CHECK(a == b);  // rounded to 1e-10: rounding noise does not reorder removals
}

TEST_CASE("removal cost: an invalid plan is refused with the planner's reason", "[internal][simplify]") {
    SimplifyOptions options;
    std::string why;
    RemovalPlan plan = valid_plan(0.1, 3.0, 3.0);
    plan.valid = false;
    plan.reason = "flattening failed";
    CHECK(std::isinf(removal_cost(plan, options, 10.0, CostBasis::Plan, why)));
    CHECK(why == "flattening failed");
    // An estimate ranks a plan whose validation is pending or failed by its estimate.
    CHECK(std::isfinite(removal_cost(plan, options, 10.0, CostBasis::Estimate, why)));
    plan.estimated = false;
    CHECK(std::isinf(removal_cost(plan, options, 10.0, CostBasis::Estimate, why)));
}

TEST_CASE("removal cost: each limit refuses with its own reason", "[internal][simplify]") {
    std::string why;
    SimplifyOptions options;
    options.max_error = 0.005;
    CHECK(std::isinf(removal_cost(valid_plan(0.1, 3.0, 3.0), options, 10.0, CostBasis::Plan, why)));
    CHECK(why.find("geometric error") != std::string::npos);
    // The estimate's deviation counts for an estimate, the final one for a plan.
    RemovalPlan plan = valid_plan(0.01, 3.0, 3.0);
    plan.estimated_deviation = 0.1;
    CHECK(std::isfinite(removal_cost(plan, options, 10.0, CostBasis::Plan, why)));
    CHECK(std::isinf(removal_cost(plan, options, 10.0, CostBasis::Estimate, why)));

    options = SimplifyOptions();
    options.max_aspect_ratio = 10.0;
    CHECK(std::isinf(removal_cost(valid_plan(0.1, 12.0, 3.0), options, 10.0, CostBasis::Plan, why)));
    CHECK(why.find("shape") != std::string::npos);
    // Not worse than what it removes: allowed.
    CHECK(std::isfinite(removal_cost(valid_plan(0.1, 12.0, 15.0), options, 10.0, CostBasis::Plan, why)));

    options = SimplifyOptions();
    options.max_edge_length = 0.05;  // of the diagonal: 0.5 here, the plan's edge is 1
    CHECK(std::isinf(removal_cost(valid_plan(0.1, 3.0, 3.0), options, 10.0, CostBasis::Plan, why)));
    CHECK(why.find("edge length") != std::string::npos);

    options = SimplifyOptions();
    options.max_normal_deviation_degrees = 45.0;
    plan = valid_plan(0.1, 3.0, 3.0);
    plan.max_normal_deviation = 60.0;
    CHECK(std::isinf(removal_cost(plan, options, 10.0, CostBasis::Plan, why)));
    CHECK(why.find("normal deviation") != std::string::npos);
    // Known only after validation: an estimate does not apply it.
    CHECK(std::isfinite(removal_cost(plan, options, 10.0, CostBasis::Estimate, why)));
    CHECK(why.empty());
}
