#pragma once
// Small helpers shared by the unit tests.

#include <catch2/catch.hpp>

#include <cstdlib>

namespace bpm::test_support {

// Is the tetgen executable on PATH? (Debian package `tetgen`, installed by scripts/setup.sh)
inline bool have_tetgen() {
    static const bool found = std::system("command -v tetgen >/dev/null 2>&1") == 0;
    return found;
}

}  // namespace bpm::test_support

// Skips the current test case, saying why, when tetgen is missing.
#define REQUIRE_TETGEN()                                                                       \
    do {                                                                                       \
        if (!bpm::test_support::have_tetgen()) {                                               \
            WARN("SKIPPED: the tetgen executable (Debian package 'tetgen') is not on PATH"); \
            return;                                                                            \
        }                                                                                      \
    } while (0)
