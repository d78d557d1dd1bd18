// The inline filters of bpm/predicates.h are compiled with the caller's flags, not libbpm's
// -ffp-contract=off. This file is a caller that contracts: it is compiled with
// -ffp-contract=fast (tests/CMakeLists.txt), and the functions marked BPM_FMA_TARGET are
// compiled for a CPU with fused multiply-add, as a solver built with -march=native would
// be. (A whole file with -mfma would also compile the out-of-line copies of the inline
// functions it uses for that CPU, and the linker may pick those copies for the whole test
// executable, which would then fail on a CPU without FMA.) The filters are compared with
// the exact predicates on inputs built to break them: exactly collinear, coplanar and
// cocircular points whose products cancel exactly but are not representable (so a fused
// evaluation leaves one product's rounding error where the plain one leaves zero), the
// same moved by one ulp, nearly degenerate points rounded onto a plane or circle, and all
// of these scaled by powers of two from the denormals to overflowing products.

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "bpm/predicates.h"

using namespace bpm;

namespace {

#if defined(__GNUC__) && defined(__x86_64__)
#define BPM_FMA_TARGET __attribute__((target("fma"), noinline))
bool cpu_has_fma() { return __builtin_cpu_supports("fma"); }
#elif defined(__GNUC__)
#define BPM_FMA_TARGET __attribute__((noinline))  // aarch64 always has FMA; elsewhere: as compiled
bool cpu_has_fma() { return true; }
#else
#define BPM_FMA_TARGET
bool cpu_has_fma() { return true; }
#endif

BPM_FMA_TARGET int orient2d_fma(const Vec2& a, const Vec2& b, const Vec2& c) { return orient2d(a, b, c); }
BPM_FMA_TARGET int orient3d_fma(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    return orient3d(a, b, c, d);
}
BPM_FMA_TARGET int in_circle_fma(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
    return in_circle(a, b, c, d);
}
// a * b - c, which this file's flags let the compiler fuse.
BPM_FMA_TARGET double product_minus(double a, double b, double c) { return a * b - c; }
BPM_FMA_TARGET double rounded_product_minus(double a, double b, double c) { return detail::rounded_product(a, b) - c; }

int orient2d_plain(const Vec2& a, const Vec2& b, const Vec2& c) { return orient2d(a, b, c); }
int orient3d_plain(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) { return orient3d(a, b, c, d); }
int in_circle_plain(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) { return in_circle(a, b, c, d); }

struct Rng {
    uint64_t state;
    uint64_t next() {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return state >> 11;
    }
    int64_t integer(int bits) { return int64_t(next() & ((1ULL << bits) - 1)) - (int64_t(1) << (bits - 1)); }
    double unit() { return double(next()) * 0x1.0p-53 - 0.5; }
};

struct Cases {
    std::vector<std::array<Vec2, 3>> orient2d;
    std::vector<std::array<Vec3, 4>> orient3d;
    std::vector<std::array<Vec2, 4>> in_circle;
};

Cases adversarial_cases(int rounds) {
    Cases cases;
    // Coordinates are integers below 2^41 times 2^e: exact, their differences exact, their
    // products (up to 2^62) and the determinants' terms rounded. e from denormal coordinates
    // (the integers lose bits there) to 2^1016, where the products overflow.
    const int kScales[] = {0, -20, 20, -500, 500, -540, -270, -900, -1000, -1060, 960, 975};
    // The 68 integer points of the circle of radius 5^8 about the origin:
    // (2 + i)^j (2 - i)^(16 - j) and its rotations by i.
    std::vector<std::array<int64_t, 2>> circle;
    for (int j = 0; j <= 16; ++j) {
        int64_t x = 1, y = 0;
        for (int k = 0; k < 16; ++k) {
            const int64_t v = k < j ? 1 : -1, nx = 2 * x - v * y, ny = v * x + 2 * y;
            x = nx;
            y = ny;
        }
        for (const auto& p : {std::array<int64_t, 2>{x, y}, {-y, x}, {-x, -y}, {y, -x}}) circle.push_back(p);
    }
    Rng rng{20261206};
    for (int i = 0; i < rounds; ++i) {
        const int e = i % 2 ? kScales[(i / 2) % 12] : int(rng.next() % 2075) - 1100;
        const auto scaled = [e](int64_t v) { return std::ldexp(double(v), e); };
        const int move = (i / 2) % 3;  // exactly degenerate, or one coordinate one ulp up or down
        const auto moved = [move](double v) { return move == 0 ? v : std::nextafter(v, move == 1 ? HUGE_VAL : -HUGE_VAL); };
        {  // collinear: x0 + k (p, q)
            const int64_t x0 = rng.integer(40), y0 = rng.integer(40), p = rng.integer(27), q = rng.integer(27);
            std::array<Vec2, 3> t;
            for (auto& v : t) {
                const int64_t k = rng.integer(6);
                v = {scaled(x0 + k * p), scaled(y0 + k * q)};
            }
            t[2][1] = moved(t[2][1]);
            cases.orient2d.push_back({t[0], t[1], t[2]});
            cases.orient2d.push_back({t[1], t[2], t[0]});
            cases.orient2d.push_back({t[2], t[0], t[1]});
        }
        {  // coplanar: base + s u + t v
            int64_t base[3], u[3], v[3];
            for (int k = 0; k < 3; ++k) base[k] = rng.integer(40), u[k] = rng.integer(25), v[k] = rng.integer(25);
            std::array<Vec3, 4> t;
            for (auto& point : t) {
                const int64_t s = rng.integer(5), r = rng.integer(5);
                for (int k = 0; k < 3; ++k) point[k] = scaled(base[k] + s * u[k] + r * v[k]);
            }
            t[3][2] = moved(t[3][2]);
            cases.orient3d.push_back({t[0], t[1], t[2], t[3]});
            cases.orient3d.push_back({t[3], t[0], t[1], t[2]});
            cases.orient3d.push_back({t[1], t[3], t[2], t[0]});
        }
        {  // cocircular: four of the integer points of the circle, about an integer centre
            const int64_t cx = rng.integer(30), cy = rng.integer(30);
            std::array<Vec2, 4> t;
            for (auto& v : t) {
                const auto& z = circle[rng.next() % circle.size()];
                v = {scaled(cx + z[0]), scaled(cy + z[1])};
            }
            t[3][0] = moved(t[3][0]);
            cases.in_circle.push_back({t[0], t[1], t[2], t[3]});
            cases.in_circle.push_back({t[1], t[2], t[3], t[0]});
        }
        {  // nearly degenerate: rounded onto a plane, a line, a circle
            const double s = std::ldexp(1.0, e / 2);
            std::array<Vec3, 4> t;
            for (auto& v : t) v = {s * rng.unit(), s * rng.unit(), s * rng.unit()};
            const double u = rng.unit(), w = rng.unit();
            for (int k = 0; k < 3; ++k) t[3][k] = t[0][k] + u * (t[1][k] - t[0][k]) + w * (t[2][k] - t[0][k]);
            cases.orient3d.push_back(t);
            const Vec2 a{t[0][0], t[0][1]}, b{t[1][0], t[1][1]};
            cases.orient2d.push_back({a, b, Vec2{a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1])}});
            std::array<Vec2, 4> c;
            for (auto& v : c) {
                const double angle = 7 * rng.unit();
                v = {s * std::cos(angle), s * std::sin(angle)};
            }
            cases.in_circle.push_back(c);
        }
    }
    // Products that underflow to zero: the plain filter once called these collinear.
    cases.orient2d.push_back({Vec2{1e-200, 2e-200}, Vec2{2e-200, 1e-200}, Vec2{0, 0}});
    // A product inf * 0 = NaN (the exact one is zero, the other is not): once "collinear".
    cases.orient2d.push_back({Vec2{1e308, 1}, Vec2{0, 0}, Vec2{-1e308, 0}});
    return cases;
}

const Cases& cases() {
    static const Cases all = adversarial_cases(6000);
    return all;
}

std::string describe(const double* x, int n) {
    std::string s;
    char buffer[40];
    for (int i = 0; i < n; ++i) {
        std::snprintf(buffer, sizeof buffer, "%a ", x[i]);
        s += buffer;
    }
    return s;
}

// Number of cases on which the filters disagree with the exact predicates; the first
// disagreement of each predicate is reported.
template <class Orient2d, class Orient3d, class InCircle>
void check_against_exact(Orient2d filtered2d, Orient3d filtered3d, InCircle filtered_circle) {
    int wrong = 0, zeros = 0;
    for (const auto& t : cases().orient2d) {
        const int exact = orient2d_exact(t[0], t[1], t[2]), filtered = filtered2d(t[0], t[1], t[2]);
        zeros += exact == 0;
        if (filtered != exact && wrong++ == 0)
            FAIL_CHECK("orient2d " << describe(t[0].data(), 6) << "filter " << filtered << " exact " << exact);
    }
    CHECK(wrong == 0);
    CHECK(zeros > 1000);
    wrong = zeros = 0;
    for (const auto& t : cases().orient3d) {
        const int exact = orient3d_exact(t[0], t[1], t[2], t[3]), filtered = filtered3d(t[0], t[1], t[2], t[3]);
        zeros += exact == 0;
        if (filtered != exact && wrong++ == 0)
            FAIL_CHECK("orient3d " << describe(t[0].data(), 12) << "filter " << filtered << " exact " << exact);
    }
    CHECK(wrong == 0);
    CHECK(zeros > 1000);
    wrong = zeros = 0;
    for (const auto& t : cases().in_circle) {
        const int exact = in_circle_exact(t[0], t[1], t[2], t[3]), filtered = filtered_circle(t[0], t[1], t[2], t[3]);
        zeros += exact == 0;
        if (filtered != exact && wrong++ == 0)
            FAIL_CHECK("in_circle " << describe(t[0].data(), 8) << "filter " << filtered << " exact " << exact);
    }
    CHECK(wrong == 0);
    CHECK(zeros > 1000);
}

}  // namespace

TEST_CASE("the predicate filters agree with the exact predicates on adversarial inputs", "[predicates]") {
    check_against_exact(orient2d_plain, orient3d_plain, in_circle_plain);
}

TEST_CASE("the predicate filters agree with the exact predicates when the caller fuses multiply-adds",
          "[predicates]") {
    if (!cpu_has_fma()) {
        WARN("this CPU has no fused multiply-add: nothing to check");
        return;
    }
    // 1 + 2^-30 and 1 - 2^-30: their product 1 - 2^-60 rounds to 1.
    volatile double a = 1 + 0x1p-30, b = 1 - 0x1p-30, one = 1;
#if defined(__OPTIMIZE__) && (defined(__GNUC__) || defined(__clang__))
    // The premise: in this file the compiler does fuse (-ffp-contract=fast, FMA target).
    CHECK(product_minus(a, b, one) == -0x1p-60);
#endif
    CHECK(rounded_product_minus(a, b, one) == 0.0);
    check_against_exact(orient2d_fma, orient3d_fma, in_circle_fma);
}
