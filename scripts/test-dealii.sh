#!/usr/bin/env bash
# Builds and runs the deal.II adapter's tests (examples/dealii) in build-dealii/: bpm in
# Release as usual, the deal.II programs against deal.II's Debug library (assertions on;
# deal.II 9.4's simplex refinement is only checked there). Separate from scripts/test.sh
# because each deal.II program takes about a minute and 1.7 GB of memory to compile.
# Extra arguments go to ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
launcher=()
if [ -n "${CCACHE_DIR:-}" ] && command -v ccache >/dev/null; then  # a shared compiler cache, when one is set up
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B build-dealii -DCMAKE_BUILD_TYPE=Release -DBPM_WITH_DEALII=ON -DBPM_BUILD_BENCH=OFF "${launcher[@]}" >/dev/null
# One job for the deal.II programs (memory), two for the rest.
cmake --build build-dealii -j 2 --target bpm-simplify bpm-mesh >&2
cmake --build build-dealii -j 1 --target bpm-dealii-torsion bpm_dealii_adapter_tests >&2
cd build-dealii
ctest --output-on-failure -L dealii --timeout 1800 "$@"
