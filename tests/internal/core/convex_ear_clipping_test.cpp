// The shared clipper of convex overlay polygons (core/convex_ear_clipping.h), used by
// smoothing and by the refined parametrization: collinear boundary points are kept as
// corners without degenerate triangles, a flat polygon is refused, and the caller's
// emit can stop it.
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/geometry.h"
#include "bpm/predicates.h"
#include "core/convex_ear_clipping.h"

using namespace bpm;
using bpm::detail::clip_convex_ears;

namespace {

struct Clipped {
    bool ok = false;
    std::vector<std::array<int, 3>> ears;
    std::vector<int> left;
};

Clipped clip(const std::vector<Vec2>& p, int refuse_after = -1) {
    Clipped c;
    c.left.resize(p.size());
    for (size_t i = 0; i < p.size(); ++i) c.left[i] = int(i);
    const auto orient = [&](int a, int b, int x) { return orient2d(p[size_t(a)], p[size_t(b)], p[size_t(x)]); };
    c.ok = clip_convex_ears(c.left, orient, [&](int a, int b, int x) {
        if (refuse_after >= 0 && int(c.ears.size()) == refuse_after) return false;
        c.ears.push_back({a, b, x});
        return true;
    });
    return c;
}

}  // namespace

TEST_CASE("convex ear clipping: a square with midpoints on two sides gives only proper triangles",
          "[internal][core]") {
    // (0,0) (1,0) (2,0) (2,2) (1,2) (0,2): two collinear points.
    const std::vector<Vec2> p{{0, 0}, {1, 0}, {2, 0}, {2, 2}, {1, 2}, {0, 2}};
    const Clipped c = clip(p);
    REQUIRE(c.ok);
    REQUIRE(c.ears.size() == 3);
    REQUIRE(c.left.size() == 3);
    double area = 0;
    auto tri_area = [&](int a, int b, int x) {
        return 0.5 * cross(p[size_t(b)] - p[size_t(a)], p[size_t(x)] - p[size_t(a)]);
    };
    for (const auto& e : c.ears) {
        CHECK(orient2d(p[size_t(e[0])], p[size_t(e[1])], p[size_t(e[2])]) > 0);
        area += tri_area(e[0], e[1], e[2]);
    }
    CHECK(orient2d(p[size_t(c.left[0])], p[size_t(c.left[1])], p[size_t(c.left[2])]) > 0);
    area += tri_area(c.left[0], c.left[1], c.left[2]);
    CHECK(area == Approx(4.0));
}

TEST_CASE("convex ear clipping: a flat polygon and a refused ear both fail", "[internal][core]") {
    const std::vector<Vec2> flat{{0, 0}, {1, 0}, {2, 0}, {3, 0}};
    CHECK_FALSE(clip(flat).ok);
    const std::vector<Vec2> square{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    CHECK(clip(square).ok);
    const Clipped refused = clip(square, 0);
    CHECK_FALSE(refused.ok);
    CHECK(refused.ears.empty());
}
