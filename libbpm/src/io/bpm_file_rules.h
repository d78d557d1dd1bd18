#pragma once
// The rules of spec/bpm-format.md that the format itself can check, shared by the writer
// (which refuses to write a file that breaks one) and the reader (which refuses to read
// one). Internal to libbpm; bpm-check applies stricter ones (check/check_format.cpp).

#include <locale>
#include <sstream>
#include <string>

#include "bpm/bpm_file.h"

namespace bpm::detail {

// A number in a message about a file: integers as they are, doubles with 17 significant
// digits (the value in the file, bit for bit), in the "C" locale whatever the host's
// global one: no "12.345", no "0,5".
template <typename T>
std::string num_text(T v) {
    std::ostringstream s;
    s.imbue(std::locale::classic());
    s.precision(17);
    s << v;
    return s.str();
}

// Empty if `file` satisfies every rule of the spec that the format itself can check,
// otherwise the first violation, beginning with the dataset path. The layout (sizes,
// offsets, index ranges, kinds, finite numbers) is checked by detail::visit_phi_layout,
// shared with bpm-check; the value rules after it are the format's own.
std::string find_inconsistency(const BpmFile& file);

// The first violation of the rules of §10.1 (/simplification_steps: sizes, CSR offsets,
// index ranges into the `original_vertices` of /original), beginning with the dataset
// path; empty if none. What the steps mean (is each a valid point removal?) is
// bpm-check --replay's business.
std::string find_steps_inconsistency(const SimplificationSteps& steps, int64_t original_vertices);

}  // namespace bpm::detail
