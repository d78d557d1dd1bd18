#pragma once
// Numbers as text, in files and in messages, independent of the C locale (not public API).
// printf, strtod and iostreams follow the locale a program sets with setlocale: under
// de_DE.UTF-8 they write and expect "0,5", so a GUI or a Python program that links libbpm
// and called setlocale(LC_ALL, "") would get TetGen input and .mesh files with commas, and
// TetGen's "0.5" would read as 0. std::to_chars and std::from_chars ignore the locale;
// every number libbpm writes or parses as text goes through here.

#include <charconv>
#include <string>

namespace bpm::detail {

// `v` with `digits` (1..17) significant digits: byte for byte what printf's "%.<digits>g"
// writes in the "C" locale ("1e-05", "0.5", "inf", "-nan").
std::string significant_text(double v, int digits);
void append_significant_text(std::string& out, double v, int digits);

// 17 significant digits, so that reading the text back gives the same double bit for bit:
// for files (and for positions in messages, which the user may look up in the file).
inline std::string round_trip_text(double v) { return significant_text(v, 17); }
inline void append_round_trip_text(std::string& out, double v) { append_significant_text(out, v, 17); }

// Three significant digits: ratios, tolerances and sizes in messages.
inline std::string three_digit_text(double v) { return significant_text(v, 3); }

// "1 problem", "3 problems": a count and its noun, singular for exactly one (nouns whose
// plural adds an "s"). Messages count things that are often single.
inline std::string count_text(long long n, const char* noun) {
    return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

// A double at the start of [first, last), as std::from_chars reads it (general format: no
// leading blanks, no '+', no hexadecimal; '.' is the decimal point whatever the locale;
// "inf", "nan" in any case), except that a number outside double's range is no error but
// gives strtod's value: +-infinity for an overflow, +-0 for an underflow. `ptr` is past the
// number; `ec` is std::errc::invalid_argument (and `ptr` == `first`) when none starts there.
std::from_chars_result parse_double(const char* first, const char* last, double& value);

}  // namespace bpm::detail
