#include "simplify/polar_map.h"

#include <algorithm>
#include <cmath>

#include "bpm/predicates.h"

namespace bpm::detail {

bool polar_map(const std::vector<Vec3>& x, int32_t v, const Fan& fan, double radius_scale, PolarMap& map,
               std::string& why) {
    const int32_t n = fan.corners();
    const int32_t ntri = static_cast<int32_t>(fan.triangles.size());
    auto& theta = map.theta;
    theta.resize(ntri);
    double total = 0.0;
    for (int32_t i = 0; i < ntri; ++i) {
        const Vec3 a = x[fan.link[i]] - x[v], b = x[fan.link[mod(i + 1, n)]] - x[v];
        theta[i] = angle_between(a, b);
        if (!(theta[i] > 0.0)) {
            why = "degenerate triangle in the star";
            return false;
        }
        total += theta[i];
    }
    const double alpha = (fan.closed ? 2.0 * M_PI : M_PI) / total;
    map.cocircular = false;
    map.q.assign(n, {0.0, 0.0});
    auto& phi = map.phi;
    phi.assign(n, 0.0);
    for (int32_t i = 1; i < n; ++i) phi[i] = phi[i - 1] + alpha * theta[i - 1];
    for (int32_t i = 0; i < ntri; ++i)
        if (!(alpha * theta[i] < M_PI)) {
            why = "flattened star angle too wide";
            return false;
        }
    auto& r = map.radius;
    r.resize(n);
    for (int32_t i = 0; i < n; ++i) r[i] = distance(x[fan.link[i]], x[v]) / radius_scale;
    // Closed: the polar map z -> z^alpha (conformal). Open: angles scaled, radii kept,
    // so that the position of v on the new edge is the same in every half-disk.
    // At a sharp cone tip (angles at v summing to a few degrees) alpha is in the hundreds
    // and r^alpha of the farther corners overflowed to inf (q inf or NaN). One factor on
    // every radius changes no shape: then, and only then, the radii are taken relative to
    // the largest (2^-largest_log), so that the usual case stays bit for bit as it was.
    double largest_log = 0.0;
    if (fan.closed)
        for (int32_t i = 0; i < n; ++i) largest_log = std::max(largest_log, alpha * std::log2(r[i]));
    const bool relative = largest_log > 1000.0;  // doubles overflow at 2^1024
    for (int32_t i = 0; i < n; ++i) {
        const double radius = !fan.closed ? r[i]
                              : relative  ? std::exp2(alpha * std::log2(r[i]) - largest_log)
                                          : std::pow(r[i], alpha);
        map.q[i] = {radius * std::cos(phi[i]), radius * std::sin(phi[i])};
    }
    if (!fan.closed) {
        map.q[0] = {r[0], 0.0};
        map.q[n - 1] = {-r[n - 1], 0.0};
    }
    auto convex = [&]() {
        for (int32_t i = 0; i < n; ++i)
            if (orient2d(map.q[mod(i - 1, n)], map.q[i], map.q[mod(i + 1, n)]) <= 0) return false;
        return true;
    };
    if (!convex()) {
        // A star-shaped but non-convex polygon cannot always carry the re-cut graph
        // (paper §2.2.4); move the corners outwards onto a circle (closed) or a
        // half-circle through the fixed ends (open), which is convex.
        map.cocircular = true;  // every ear is Delaunay-admissible on a circle
        map.q_polar = map.q;
        if (fan.closed) {
            for (int32_t i = 0; i < n; ++i) map.q[i] = {std::cos(phi[i]), std::sin(phi[i])};
        } else {
            const double c = 0.5 * (r[0] - r[n - 1]), R = 0.5 * (r[0] + r[n - 1]);
            for (int32_t i = 1; i < n - 1; ++i) map.q[i] = {c + R * std::cos(phi[i]), R * std::sin(phi[i])};
        }
        if (!convex()) {
            why = "cannot flatten the star to a convex polygon";
            return false;
        }
    }
    return true;
}

}  // namespace bpm::detail
