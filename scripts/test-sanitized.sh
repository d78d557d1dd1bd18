#!/usr/bin/env bash
# The whole test suite again, built with AddressSanitizer + UndefinedBehaviorSanitizer
# (leak detection on) by clang in build-asan/ (scripts/configure-sanitized.sh: the build the
# fuzz targets use too; CI then runs scripts/fuzz.sh in this directory instead of compiling
# libbpm once more). CI runs it after scripts/test.sh. clang compiles libbpm with ASan and
# coverage in about half the CPU time GCC took with ASan and UBSan (0.56x over 68 units).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
jobs=$(nproc 2>/dev/null || echo 2)
./scripts/configure-sanitized.sh build-asan
cmake --build build-asan -j "$jobs" >&2
cd build-asan
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --output-on-failure -j "$jobs" --timeout 1800 "$@"
