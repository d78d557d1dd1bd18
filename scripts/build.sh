#!/usr/bin/env bash
# Configures and builds bpm (Release) into build/. Extra arguments go to cmake.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
# BPM_BUILD_TARGETS (space-separated) builds only those targets, e.g. the tools for the demo.
if [ -n "${BPM_BUILD_TARGETS:-}" ]; then
  cmake --build build -j "$jobs" --target ${BPM_BUILD_TARGETS}
else
  cmake --build build -j "$jobs"
fi
