#include "core/sheet_order.h"

#include <algorithm>
#include <cstdint>
#include <numeric>

#include "bpm/predicates.h"

namespace bpm::detail {

int half_turn(const Vec3& a, const Vec3& b, const Vec3& r, const Vec3& q) {
    const int s = orient3d(a, b, r, q);
    if (s > 0) return 1;
    if (s < 0) return 3;
    // q in the plane of a, b, r: the same side of the line as r, or the other. A
    // projection on a coordinate plane that keeps (a, b, r) a triangle is an affine
    // bijection of that plane, so it keeps the sides of the line (exact).
    for (int drop = 0; drop < 3; ++drop) {
        const int i = drop == 0 ? 1 : 0, j = drop == 2 ? 1 : 2;
        const Vec2 a2{a[i], a[j]}, b2{b[i], b[j]};
        const int side_r = orient2d(a2, b2, Vec2{r[i], r[j]});
        if (side_r == 0) continue;
        const int side_q = orient2d(a2, b2, Vec2{q[i], q[j]});
        return side_q == side_r || side_q == 0 ? 0 : 2;
    }
    return 0;  // r on the line
}

bool turns_before(const Vec3& a, const Vec3& b, const Vec3& r, const Vec3& q, const Vec3& p) {
    const int hq = half_turn(a, b, r, q), hp = half_turn(a, b, r, p);
    if (hq != hp) return hq < hp;
    if (hq == 0 || hq == 2) return false;
    // Both within one half-turn: their angles differ by less than pi.
    return orient3d(a, b, q, p) > 0;
}

bool sort_around_edge(const Vec3& a, const Vec3& b, const std::vector<Vec3>& apexes, std::vector<int32_t>& order) {
    order.resize(apexes.size());
    std::iota(order.begin(), order.end(), 0);
    if (apexes.empty()) return true;
    const Vec3& r = apexes[0];
    // turns_before with each apex's half-turn found once (the sort compares each apex
    // several times).
    int8_t half[16];
    std::vector<int8_t> many;
    int8_t* h = half;
    if (apexes.size() > 16) {
        many.resize(apexes.size());
        h = many.data();
    }
    for (size_t i = 0; i < apexes.size(); ++i) h[i] = static_cast<int8_t>(i == 0 ? 0 : half_turn(a, b, r, apexes[i]));
    auto before = [&](int32_t x, int32_t y) {
        if (h[x] != h[y]) return h[x] < h[y];
        if (h[x] == 0 || h[x] == 2) return false;
        return orient3d(a, b, apexes[x], apexes[y]) > 0;
    };
    std::stable_sort(order.begin(), order.end(), before);
    bool distinct = true;
    for (const Vec3& c : apexes)
        if (collinear3d(a, b, c)) distinct = false;
    // Apexes on one half-plane compare equal (the half-plane of r: half-turn 0).
    for (size_t k = 1; k < order.size() && distinct; ++k)
        if (!before(order[k - 1], order[k])) distinct = false;
    return distinct;
}

bool strictly_between(const Vec3& a, const Vec3& b, const Vec3& u, const Vec3& w, const Vec3& q) {
    if (half_turn(a, b, u, q) == 0) return false;
    if (half_turn(a, b, u, w) == 0) return true;
    return turns_before(a, b, u, q, w);
}

}  // namespace bpm::detail
