#!/usr/bin/env bash
# The whole test suite again, built with AddressSanitizer + UndefinedBehaviorSanitizer
# (leak detection on) in build-asan/. CI runs it after scripts/test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
jobs=$(nproc 2>/dev/null || echo 2)
# The bench tools are not tested: not building them under the sanitizers saves CI minutes.
# -g1 (line tables only): the sanitizers' reports still name file and line; full debug
# information of the CGAL templates made the sanitized build ~30 % slower to compile.
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DBPM_SANITIZE=ON -DBPM_BUILD_BENCH=OFF >/dev/null
cmake --build build-asan -j "$jobs" >&2
cd build-asan
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --output-on-failure -j "$jobs" --timeout 1800 "$@"
