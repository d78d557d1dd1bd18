#!/usr/bin/env bash
# Installs what is missing, builds (Release), and runs the whole test suite:
# unit tests, Python interop tests and pipeline tests of the real executables.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
# The deal.II example and its Debug-mode test are part of the suite when deal.II is
# installed (setup.sh installs it); they are built once here, not in a build of their own.
./scripts/build.sh -DBPM_WITH_DEALII=ON >&2
cd build
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" --timeout 1200 "$@"
