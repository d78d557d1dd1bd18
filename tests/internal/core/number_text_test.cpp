// core/number_text.h: libbpm's number text is printf's "%.<n>g" and strtod's reading in
// the "C" locale, whatever C locale the program has set.

#include "core/number_text.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "comma_locale.h"

using namespace bpm::detail;

namespace {

// Values of every kind printf's %g distinguishes: integers, fractions, both notations and
// the switch between them, subnormals, the largest double, zeros of both signs, inf, NaN.
std::vector<double> sample_values() {
    std::vector<double> v = {0.0, -0.0, 0.5, 0.1, 1.0 / 3, -2.5, 1e-5, 1e-4, 9.9995e-5, 0.00099950000000000001,
                             999.5, 9995, 1e16, 1e17, 123456789012345678.0, 0.18987, 1.7976931348623157e308,
                             std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::min(),
                             std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                             std::nan(""), -std::nan("")};
    uint64_t bits = 0x9E3779B97F4A7C15ull;
    for (int i = 0; i < 3000; ++i) {
        bits = bits * 6364136223846793005ull + 1442695040888963407ull;
        double x = 0;
        std::memcpy(&x, &bits, sizeof x);  // any bit pattern: every exponent
        v.push_back(x);
        v.push_back(std::ldexp(double(bits >> 40) / 997, int(bits % 80) - 40));  // around 1
    }
    return v;
}

std::string printf_text(double v, int digits) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, v);
    return buffer;
}

double parsed(const std::string& text) {
    double v = -7;
    const auto r = parse_double(text.data(), text.data() + text.size(), v);
    REQUIRE(r.ec == std::errc());
    REQUIRE(r.ptr == text.data() + text.size());
    return v;
}

}  // namespace

TEST_CASE("number_text: significant_text writes what printf's %g writes in the C locale", "[core][locale]") {
    for (double v : sample_values())
        for (int digits : {3, 6, 12, 17}) {
            INFO(printf_text(v, 17) << " with " << digits << " digits");
            CHECK(significant_text(v, digits) == printf_text(v, digits));
        }
    CHECK(round_trip_text(0.1) == "0.10000000000000001");
    CHECK(three_digit_text(1.0 / 3) == "0.333");
    std::string out = "x ";
    append_round_trip_text(out, -2.5);
    CHECK(out == "x -2.5");
}

TEST_CASE("number_text: parse_double reads like strtod in the C locale, out-of-range values included",
          "[core][locale]") {
    for (double v : sample_values()) {
        const std::string text = printf_text(v, 17);
        INFO(text);
        const double back = parsed(text);
        if (std::isnan(v)) CHECK(std::isnan(back));
        else CHECK(std::memcmp(&back, &v, sizeof v) == 0);  // same bits, -0 included
    }
    // Outside double's range: strtod's infinity and zero, with their signs.
    CHECK(parsed("1e400") == std::numeric_limits<double>::infinity());
    CHECK(parsed("-1.7976931348623159e308") == -std::numeric_limits<double>::infinity());
    CHECK(parsed("0.0001e312") == 1e308);  // in range after all
    CHECK(parsed("1e-99999999999999") == 0.0);
    CHECK(std::signbit(parsed("-1.5e-400")));
    CHECK(parsed("-1.5e-400") == 0.0);
    CHECK(parsed("123456e-330") == 0.0);
    CHECK(parsed("5e-324") == std::numeric_limits<double>::denorm_min());
    // Not a number: nothing read.
    for (const std::string text : {"", "abc", ",5", "+1", " 1"}) {
        double v = -7;
        const auto r = parse_double(text.data(), text.data() + text.size(), v);
        CHECK(r.ec == std::errc::invalid_argument);
        CHECK(r.ptr == text.data());
    }
    // The number ends where strtod's would: "1,5" is 1 followed by ",5".
    const std::string comma = "1,5";
    double v = 0;
    CHECK(parse_double(comma.data(), comma.data() + comma.size(), v).ptr == comma.data() + 1);
}

TEST_CASE("number_text: a decimal-comma C locale changes neither writing nor reading", "[core][locale]") {
    const std::string in_c = significant_text(0.5, 17) + significant_text(1.0 / 3, 3) + significant_text(2.25e-7, 12);
    const bpm::test_support::CommaLocale comma;
    CHECK(printf_text(0.5, 17) == "0,5");  // what the library wrote before
    CHECK(significant_text(0.5, 17) + significant_text(1.0 / 3, 3) + significant_text(2.25e-7, 12) == in_c);
    CHECK(parsed("0.5") == 0.5);
    CHECK(parsed("-1.5e-400") == 0.0);  // strtod read "-1" here
}
