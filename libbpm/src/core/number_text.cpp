#include "core/number_text.h"

#include <cctype>
#include <limits>

namespace bpm::detail {

void append_significant_text(std::string& out, double v, int digits) {
    char buffer[64];  // at most 17 digits, sign, point, "e-308" or the zeros of "0.0000x"
    const std::to_chars_result r = std::to_chars(buffer, buffer + sizeof buffer, v, std::chars_format::general, digits);
    out.append(buffer, r.ptr);
}

std::string significant_text(double v, int digits) {
    std::string out;
    append_significant_text(out, v, digits);
    return out;
}

namespace {

bool is_digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

// Whether the number [first, last) - which std::from_chars read, and found outside double's
// range - is large (an overflow) rather than tiny. Its decimal exponent tells: the position
// of the first non-zero digit plus the written exponent is >= 308 for an overflow and
// <= -324 for an underflow, never near 0.
bool overflows(const char* first, const char* last) {
    const char* p = first;
    if (p < last && *p == '-') ++p;
    long long integer_digits = 0;  // digits before the point, from the first non-zero one
    long long leading_fraction_zeros = 0;
    bool nonzero_integer = false, nonzero_fraction = false, after_point = false;
    for (; p < last && (is_digit(*p) || *p == '.'); ++p) {
        if (*p == '.') {
            after_point = true;
        } else if (!after_point) {
            if (nonzero_integer || *p != '0') nonzero_integer = true, ++integer_digits;
        } else if (!nonzero_integer && !nonzero_fraction) {
            if (*p == '0') ++leading_fraction_zeros;
            else nonzero_fraction = true;
        }
    }
    const long long magnitude = nonzero_integer ? integer_digits - 1 : -(leading_fraction_zeros + 1);
    long long exponent = 0;
    if (p < last && (*p == 'e' || *p == 'E')) {
        ++p;
        const bool negative = p < last && *p == '-';
        if (p < last && (*p == '-' || *p == '+')) ++p;
        for (; p < last && is_digit(*p); ++p)
            if (exponent < 1000000) exponent = exponent * 10 + (*p - '0');  // saturates, far out of range
        if (negative) exponent = -exponent;
    }
    return magnitude + exponent >= 0;
}

}  // namespace

std::from_chars_result parse_double(const char* first, const char* last, double& value) {
    std::from_chars_result r = std::from_chars(first, last, value);
    if (r.ec == std::errc::result_out_of_range) {
        const double size = overflows(first, r.ptr) ? std::numeric_limits<double>::infinity() : 0.0;
        value = *first == '-' ? -size : size;
        r.ec = std::errc();
    }
    return r;
}

}  // namespace bpm::detail
