#!/usr/bin/env bash
# Configures DIR (default build-asan/) as the clang build that scripts/test-sanitized.sh and
# scripts/fuzz.sh share: libbpm compiled with -fsanitize=address,undefined, its readers and
# checks also with -fsanitize=fuzzer-no-link (coverage for the fuzzers; not the simplifier,
# whose tests it slowed 1.6-1.9x: tests/fuzz/CMakeLists.txt), the tests and tools linked with
# address,undefined (the coverage hooks resolve to the no-ops of the sanitizer runtime), the
# fuzz targets with fuzzer. CI runs both scripts on one such directory, so libbpm's
# sanitized objects are compiled once instead of twice (GCC for the tests, clang for the
# fuzzers, until December 2026: 30 % of CI's CPU time was libbpm's compiles).
#
#   scripts/configure-sanitized.sh [DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${1:-build-asan}
for tool in clang clang++; do
    command -v $tool >/dev/null || { echo "configure-sanitized: $tool not found (Debian packages clang, libclang-rt-14-dev; scripts/setup.sh installs them)" >&2; exit 2; }
done
# A DIR configured before for another compiler (the sanitized build was GCC's until December
# 2026) is configured anew: CMake keeps the compiler of its cache.
if [ -f "$dir/CMakeCache.txt" ] && ! grep -q '^CMAKE_CXX_COMPILER:[A-Z]*=.*clang++' "$dir/CMakeCache.txt"; then
    echo "configure-sanitized: $dir/ was configured for another compiler; configuring it anew for clang" >&2
    rm -rf "$dir/CMakeCache.txt" "$dir/CMakeFiles"
fi
# -g1 (line tables only): the sanitizers' reports still name file and line; full debug
# information of the CGAL templates compiles ~30 % slower. The bench tools are not tested:
# not building them saves CI minutes.
cmake -S . -B "$dir" -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
    -DBPM_SANITIZE=ON -DBPM_FUZZ=ON -DBPM_BUILD_BENCH=OFF >/dev/null
