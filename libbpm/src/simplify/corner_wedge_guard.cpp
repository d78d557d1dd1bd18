// The corner-wedge guard of the simplifier (simplify/corner_wedge_guard.h).

#include "simplify/corner_wedge_guard.h"

#include <algorithm>
#include <cmath>

namespace bpm::detail {

namespace {

// The sine of the corner wedge of a and b (1 when there is none): comparing sines
// orders the angles (all in [0, 90] degrees) without an asin per pair.
double corner_wedge_sine(const std::vector<Vec3>& x, const Tri& a, const Tri& b) {
    int shared = 0, ia = -1, ib = -1;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (a[i] == b[j]) ++shared, ia = i, ib = j;
    if (shared != 1) return 1.0;
    const Vec3& s = x[size_t(a[ia])];
    const Vec3 u1 = x[size_t(a[(ia + 1) % 3])] - s, u2 = x[size_t(a[(ia + 2) % 3])] - s;
    const Vec3 w1 = x[size_t(b[(ib + 1) % 3])] - s, w2 = x[size_t(b[(ib + 2) % 3])] - s;
    const Vec3 na = cross(u1, u2), nb = cross(w1, w2);
    const double la = norm(na), lb = norm(nb);
    if (!(la > 0) || !(lb > 0)) return 1.0;
    double sine = 1.0;
    // r against the sector from p to q (counterclockwise about n = p x q, of length ln):
    // inside it when projected onto its plane iff (p x r) . n >= 0 and (r x q) . n >= 0.
    const auto ray = [&](const Vec3& r, const Vec3& p, const Vec3& q, const Vec3& n, double ln) {
        if (dot(cross(p, r), n) >= 0 && dot(cross(r, q), n) >= 0)
            sine = std::min(sine, std::abs(dot(r, n)) / (norm(r) * ln));
    };
    ray(w1, u1, u2, na, la);
    ray(w2, u1, u2, na, la);
    ray(u1, w1, w2, nb, lb);
    ray(u2, w1, w2, nb, lb);
    return sine;
}

}  // namespace

double corner_wedge_degrees(const std::vector<Vec3>& x, const Tri& a, const Tri& b) {
    return std::asin(std::min(1.0, corner_wedge_sine(x, a, b))) * (180.0 / M_PI);
}

bool keeps_corner_wedges(const CoarseMesh& mesh, const std::vector<int32_t>& removed, const std::vector<Tri>& added,
                         double floor_degrees) {
    if (!(floor_degrees > 0) || added.empty() || mesh.one_patch()) return true;
    const double floor = std::sin(floor_degrees * (M_PI / 180.0));
    const auto& x = mesh.positions();
    const auto is_removed = [&](int32_t t) { return std::find(removed.begin(), removed.end(), t) != removed.end(); };
    // A pair with one common corner s is met once, at s, among the triangles of s (the
    // mesh has this step's earlier commits: their new triangles are there).
    double after = 1.0;
    for (size_t i = 0; i < added.size(); ++i) {
        for (int32_t s : added[i])
            for (int32_t t : mesh.triangles_of(s))
                if (!is_removed(t)) after = std::min(after, corner_wedge_sine(x, added[i], mesh.triangle(t)));
        for (size_t j = 0; j < i; ++j) after = std::min(after, corner_wedge_sine(x, added[i], added[j]));
    }
    if (after >= floor) return true;
    double before = 1.0;
    for (int32_t r : removed)
        for (int32_t s : mesh.triangle(r))
            for (int32_t t : mesh.triangles_of(s))
                if (t != r) before = std::min(before, corner_wedge_sine(x, mesh.triangle(r), mesh.triangle(t)));
    return !(after < before);
}

}  // namespace bpm::detail
