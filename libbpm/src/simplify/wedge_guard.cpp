// The wedge guard of the simplifier (simplify/wedge_guard.h).

#include "simplify/wedge_guard.h"

#include <algorithm>
#include <cmath>

namespace bpm::detail {

double smallest_wedge_degrees(const Vec3& a, const Vec3& b, const std::vector<Vec3>& apexes) {
    if (apexes.size() < 2) return 360.0;
    const Vec3 e = b - a;
    const double ee = dot(e, e);
    if (!(ee > 0)) return 0.0;
    // A frame across the edge: u towards the first apex, w = e x u.
    const auto across = [&](const Vec3& p) {
        const Vec3 d = p - a;
        return d - (dot(d, e) / ee) * e;
    };
    const Vec3 u = across(apexes[0]);
    const Vec3 w = cross(e, u);
    if (!(dot(u, u) > 0)) return 0.0;
    double angles[16];
    std::vector<double> more;
    double* angle = angles;
    if (apexes.size() > 16) {
        more.resize(apexes.size());
        angle = more.data();
    }
    constexpr double kTwoPi = 2 * M_PI;
    for (size_t i = 0; i < apexes.size(); ++i) {
        const Vec3 d = across(apexes[i]);
        double t = std::atan2(dot(d, w), dot(d, u) * std::sqrt(ee));
        if (t < 0) t += kTwoPi;
        angle[i] = t;
    }
    std::sort(angle, angle + apexes.size());
    double smallest = kTwoPi - (angle[apexes.size() - 1] - angle[0]);
    for (size_t i = 1; i < apexes.size(); ++i) smallest = std::min(smallest, angle[i] - angle[i - 1]);
    return std::max(smallest, 0.0) * (180.0 / M_PI);
}

namespace {

int32_t third_corner(const Tri& t, int32_t x, int32_t y) {
    for (int32_t c : t)
        if (c != x && c != y) return c;
    return -1;
}

bool has_edge(const Tri& t, int32_t u, int32_t w) {
    return (t[0] == u || t[1] == u || t[2] == u) && (t[0] == w || t[1] == w || t[2] == w);
}

// The smallest wedge at a -- b of the mesh as it is (all its triangles there).
double wedge_now(const CoarseMesh& mesh, int32_t a, int32_t b, WedgeScratch& s) {
    const auto& x = mesh.positions();
    mesh.edge_triangles(a, b, s.tris);
    s.apexes.clear();
    for (int32_t t : s.tris) s.apexes.push_back(x[size_t(third_corner(mesh.triangle(t), a, b))]);
    return smallest_wedge_degrees(x[size_t(a)], x[size_t(b)], s.apexes);
}

}  // namespace

bool keeps_feature_wedges(const CoarseMesh& mesh, const std::vector<int32_t>& removed, const std::vector<Tri>& added,
                           int32_t line_a, int32_t line_v, int32_t line_b, WedgeScratch& s,
                           double junction_floor_degrees, double crease_floor_degrees) {
    const auto& x = mesh.positions();
    const auto is_removed = [&](int32_t t) { return std::find(removed.begin(), removed.end(), t) != removed.end(); };
    for (size_t i = 0; i < added.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            const int32_t a = added[i][k], b = added[i][(k + 1) % 3];
            const bool line_edge = line_v >= 0 && ((a == line_a && b == line_b) || (a == line_b && b == line_a));
            // Every edge of three or more triangles is a hard feature edge, and so is a new
            // edge along a junction line: most edges stop at this lookup.
            if (!line_edge && !mesh.is_feature_edge(a, b)) continue;
            // Judged once, by the first added triangle on it.
            bool earlier = false;
            for (size_t j = 0; j < i && !earlier; ++j) earlier = has_edge(added[j], a, b);
            if (earlier) continue;
            // The sheets after the change: the kept ones and the added ones.
            s.apexes.clear();
            if (!line_edge) {
                mesh.edge_triangles(a, b, s.tris);
                for (int32_t t : s.tris)
                    if (!is_removed(t)) s.apexes.push_back(x[size_t(third_corner(mesh.triangle(t), a, b))]);
            }
            for (const Tri& t : added)
                if (has_edge(t, a, b)) s.apexes.push_back(x[size_t(third_corner(t, a, b))]);
            if (s.apexes.size() < 2) continue;
            const double floor_degrees = s.apexes.size() >= 3 ? junction_floor_degrees : crease_floor_degrees;
            const double after = smallest_wedge_degrees(x[size_t(a)], x[size_t(b)], s.apexes);
            if (after >= floor_degrees) continue;
            const double before = line_edge ? std::min(wedge_now(mesh, line_a, line_v, s), wedge_now(mesh, line_v, line_b, s))
                                            : wedge_now(mesh, a, b, s);
            if (after < before) return false;
        }
    return true;
}

}  // namespace bpm::detail
