#pragma once
// Helpers shared by the check_*.cpp files; not part of the public API.

#include <optional>
#include <string>

#include "bpm/check.h"

namespace bpm::detail {

// The first reason why `param` cannot be examined safely (sizes, CSR offsets, index
// ranges, node kinds, finite numbers), or nullopt. check_format reports all of these
// in detail; the other parametrization checks refuse to run when one is present.
std::optional<std::string> parametrization_unsafe(const Parametrization& param);

// Same for a plain surface (triangle indices in range, finite coordinates; patch ids
// may be missing).
std::optional<std::string> surface_unsafe(const Surface& surface);

// Marks `result` as not checked because of `reason`.
void refuse(CheckResult& result, const std::string& reason);

// "%.6g"-style number formatting without locale surprises.
std::string format_number(double value);

}  // namespace bpm::detail
