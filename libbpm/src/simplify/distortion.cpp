// Per-piece distortion of phi (simplify/distortion.h).
#include "simplify/distortion.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace bpm::detail {

namespace {

constexpr double kDegree = 180.0 / 3.14159265358979323846;

Vec3 unit(const Vec3& v) {
    const double n = norm(v);
    return n > 0 ? (1.0 / n) * v : Vec3{0, 0, 0};
}

double area(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * norm(cross(b - a, c - a)); }

}  // namespace

std::vector<Vec3> unit_normals(const Surface& s) {
    std::vector<Vec3> n(s.triangles.size());
    for (size_t t = 0; t < s.triangles.size(); ++t) {
        const Tri& x = s.triangles[t];
        n[t] = unit(cross(s.vertices[x[1]] - s.vertices[x[0]], s.vertices[x[2]] - s.vertices[x[0]]));
    }
    return n;
}

void triangle_distortion(const Parametrization& p, int32_t t, const std::vector<Vec3>& original_normals,
                         std::vector<PieceDistortion>& out) {
    const Tri& c = p.coarse.triangles[t];
    const Vec3 &c0 = p.coarse.vertices[c[0]], &c1 = p.coarse.vertices[c[1]], &c2 = p.coarse.vertices[c[2]];
    const Vec3 coarse_normal = unit(cross(c1 - c0, c2 - c0));
    const int64_t base = p.node_offsets[t], first = p.piece_offsets[t], last = p.piece_offsets[t + 1];
    auto at = [&](int32_t local) { return barycentric_point(c0, c1, c2, p.node_barycentric[base + local]); };
    out.assign(static_cast<size_t>(last - first), PieceDistortion{});
    double image_total = 0;
    for (int64_t q = first; q < last; ++q) {
        const Tri& pc = p.pieces[q];
        image_total += area(p.node_image[base + pc[0]], p.node_image[base + pc[1]], p.node_image[base + pc[2]]);
    }
    const double ratio = image_total > 0 ? area(c0, c1, c2) / image_total : 0;
    for (int64_t q = first; q < last; ++q) {
        const Tri& pc = p.pieces[q];
        PieceDistortion& d = out[size_t(q - first)];
        const double a = area(at(pc[0]), at(pc[1]), at(pc[2]));
        const double image = area(p.node_image[base + pc[0]], p.node_image[base + pc[1]], p.node_image[base + pc[2]]);
        const int32_t o = p.piece_original_triangle[q];
        const Vec3 n = original_normals.empty() ? [&] {
            const Tri& x = p.original.triangles[o];
            return unit(cross(p.original.vertices[x[1]] - p.original.vertices[x[0]],
                              p.original.vertices[x[2]] - p.original.vertices[x[0]]));
        }()
                                                : original_normals[size_t(o)];
        d.normal_deviation = std::acos(std::clamp(dot(n, coarse_normal), -1.0, 1.0)) * kDegree;
        if (!(a > 0) || !(image > 0) || !(ratio > 0)) {
            d.degenerate = true;
            d.squeeze = std::numeric_limits<double>::infinity();
            continue;
        }
        const double s = (a / image) / ratio;
        d.squeeze = std::max(s, 1.0 / s);
    }
}

double distortion_cost(double deviation, double weight, double fold_limit) {
    double cost = 0.0;
    if (weight > 0 && deviation > 45) {
        const double over = (deviation - 45) / 45;
        cost += weight * 1e-3 * over * over;
    }
    // Independent of the weight: a fold limit alone (weight 0) must still put folds last.
    if (fold_limit < 180 && deviation > fold_limit) cost += 1.0;
    return cost;
}

double fold_cost(double deviation, double weight) {
    if (!(weight > 0) || !(deviation > 90)) return 0.0;
    return weight * 1e-3 * (std::min(deviation, 180.0) - 90) / 90;
}

}  // namespace bpm::detail
