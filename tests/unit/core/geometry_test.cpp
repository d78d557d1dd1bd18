#include <catch2/catch.hpp>

#include "bpm/geometry.h"

using namespace bpm;

TEST_CASE("aspect ratio of an equilateral triangle is 2", "[geometry]") {
    const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0.5, std::sqrt(3.0) / 2, 0};
    CHECK(aspect_ratio(a, b, c) == Approx(2.0));
}

TEST_CASE("aspect ratio of a degenerate triangle is infinite", "[geometry]") {
    CHECK(std::isinf(aspect_ratio({0, 0, 0}, {1, 0, 0}, {2, 0, 0})));
}

TEST_CASE("aspect ratio does not depend on units", "[geometry]") {
    const Vec3 a{0, 0, 0}, b{3, 0.2, 0}, c{0.4, 1.1, 0.3};
    const double r = aspect_ratio(a, b, c);
    CHECK(aspect_ratio(1e-3 * a, 1e-3 * b, 1e-3 * c) == Approx(r));
    CHECK(aspect_ratio(1e4 * a, 1e4 * b, 1e4 * c) == Approx(r));
}
