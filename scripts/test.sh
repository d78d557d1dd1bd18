#!/usr/bin/env bash
# Installs what is missing, builds (Release), and runs the whole test suite:
# unit tests, Python interop tests and pipeline tests of the real executables.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
./scripts/build.sh >&2
cd build
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" --timeout 1200 "$@"
