#!/usr/bin/env bash
# The main job on a real surface: installs what is missing, builds, and runs the whole
# pipeline that exists on a surface (default: femur from Debian's libcgal-demo data).
#   scripts/demo.sh [SURFACE] [RATIO]
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
# Only the five tools: the demo need not wait for the tests and the solver examples.
BPM_BUILD_TARGETS="bpm-simplify bpm-check bpm-smooth bpm-refine bpm-mesh" ./scripts/build.sh >&2
input=${1:-.data/meshes/femur.off}
ratio=${2:-0.1}
out=out
mkdir -p "$out"
name=$(basename "${input%.*}")
bin=build/bin
echo "== bpm-simplify $input --ratio $ratio" >&2
"$bin/bpm-simplify" "$input" -o "$out/$name.bpm" --ratio "$ratio"
echo "== bpm-check $out/$name.bpm" >&2
"$bin/bpm-check" "$out/$name.bpm"
last="$out/$name.bpm"
if [ -x "$bin/bpm-smooth" ]; then
  echo "== bpm-smooth" >&2
  "$bin/bpm-smooth" "$last" -o "$out/$name.smooth.bpm"
  "$bin/bpm-check" "$out/$name.smooth.bpm" >/dev/null
  last="$out/$name.smooth.bpm"
fi
if [ -x "$bin/bpm-refine" ]; then
  echo "== bpm-refine --levels 2" >&2
  "$bin/bpm-refine" "$last" -o "$out/$name.refined.vtu" --levels 2
fi
if [ -x "$bin/bpm-mesh" ]; then
  echo "== bpm-mesh" >&2
  "$bin/bpm-mesh" "$last" -o "$out/$name.mesh.vtu" || echo "bpm-mesh could not mesh this surface (see above)" >&2
fi
echo
echo "Outputs in $out/:"
ls -l "$out" | sed 1d | grep " $name\." | awk '{print "  " $NF "  (" $5 " bytes)"}'
echo "Open $out/$name.bpm in ParaView (VTKHDF) to see the coarse surface; spec/bpm-format.md describes the file."
