// check_distortion: how far phi is from an isometry, per piece (spec/check-report.md,
// "distortion"; the measures are those of simplify/distortion.h). A report: it fails
// only on files it cannot read safely.
#include <algorithm>
#include <cmath>

#include "bpm/check.h"
#include "check/check_internal.h"
#include "simplify/distortion.h"

namespace bpm {

namespace {

// The q-quantile (nearest rank) of `values`, reordering them; 0 when empty.
double quantile(std::vector<double>& values, double q) {
    if (values.empty()) return 0;
    const size_t k = std::min(values.size() - 1, static_cast<size_t>(std::ceil(q * double(values.size()))) - (q > 0 ? 1 : 0));
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
    return values[k];
}

}  // namespace

CheckResult check_distortion(const Parametrization& param, const CheckOptions& options, const Context& context) {
    CheckResult r;
    r.name = "distortion";
    if (auto why = detail::parametrization_unsafe(param)) {
        detail::refuse(r, *why);
        return r;
    }
    (void)options;
    const std::vector<Vec3> normals = detail::unit_normals(param.original);
    std::vector<detail::PieceDistortion> piece;
    std::vector<double> squeezes, deviations;
    squeezes.reserve(param.pieces.size());
    deviations.reserve(param.pieces.size());
    int64_t degenerate = 0, over60 = 0, over90 = 0, triangles60 = 0, triangles90 = 0;
    WorstValue worst_squeeze{"area_squeeze_max", 1, {}}, worst_turn{"normal_deviation_degrees_max", 0, {}};
    const int32_t nt = param.num_coarse_triangles();
    for (int32_t t = 0; t < nt; ++t) {
        if ((t & 4095) == 0) context.report(double(t) / std::max(1, nt), "distortion of phi");
        detail::triangle_distortion(param, t, normals, piece);
        const int64_t over60_before = over60, over90_before = over90;
        for (size_t i = 0; i < piece.size(); ++i) {
            const detail::PieceDistortion& d = piece[i];
            const int64_t q = param.piece_offsets[t] + int64_t(i);
            deviations.push_back(d.normal_deviation);
            over60 += d.normal_deviation > 60;
            over90 += d.normal_deviation > 90;
            if (d.normal_deviation > worst_turn.value || worst_turn.ids.empty())
                worst_turn = {"normal_deviation_degrees_max", d.normal_deviation, {{"coarse_triangle", t}, {"piece", q}}};
            if (d.degenerate) {
                ++degenerate;
                continue;
            }
            squeezes.push_back(d.squeeze);
            if (d.squeeze > worst_squeeze.value || worst_squeeze.ids.empty())
                worst_squeeze = {"area_squeeze_max", d.squeeze, {{"coarse_triangle", t}, {"piece", q}}};
        }
        triangles60 += over60 > over60_before;
        triangles90 += over90 > over90_before;
    }
    r.add_count("pieces", param.num_pieces());
    r.add_count("degenerate_pieces", degenerate);
    r.add_count("pieces_turned_over_60_degrees", over60);
    r.add_count("pieces_turned_over_90_degrees", over90);
    r.add_count("coarse_triangles_with_pieces_over_60_degrees", triangles60);
    r.add_count("coarse_triangles_with_pieces_over_90_degrees", triangles90);
    const double s50 = quantile(squeezes, 0.5), s99 = quantile(squeezes, 0.99);
    const double n50 = quantile(deviations, 0.5), n99 = quantile(deviations, 0.99);
    r.measures = {{"area_squeeze_p50", s50, {}}, {"area_squeeze_p99", s99, {}}, worst_squeeze,
                  {"normal_deviation_degrees_p50", n50, {}}, {"normal_deviation_degrees_p99", n99, {}}, worst_turn};
    r.worst = worst_turn;
    using detail::format_number;
    r.summary = std::to_string(param.num_pieces()) + " pieces, area squeeze p50 " + format_number(s50) + " p99 " +
                format_number(s99) + " max " + format_number(worst_squeeze.value) + ", normal deviation p50 " +
                format_number(n50) + " p99 " + format_number(n99) + " max " + format_number(worst_turn.value) +
                " degrees, " + std::to_string(over60) + " pieces turned > 60 degrees, " + std::to_string(over90) +
                " > 90 (on " + std::to_string(triangles60) + " and " + std::to_string(triangles90) + " coarse triangles)";
    if (!worst_turn.ids.empty())
        r.summary += " (worst: coarse triangle " + std::to_string(worst_turn.ids[0].second) + ")";
    return r;
}

}  // namespace bpm
