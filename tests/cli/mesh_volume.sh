#!/usr/bin/env bash
# Pipeline: bpm-simplify -> bpm-mesh -> bpm-refine --volume on elephant, with exports
# and the error cases of the volume path.
# Usage: mesh_volume.sh TOOL_DIR SOURCE_DIR WORK_DIR
set -u
tools=$1
src=$2
work=$3
rm -rf "$work"
mkdir -p "$work"
source "$(dirname "$0")/lib/harness.bash"
elephant=$src/.data/meshes/elephant.off
if [ ! -f "$elephant" ] || ! command -v tetgen >/dev/null; then
    echo "skipped: needs $elephant and tetgen (scripts/setup.sh installs both)"
    exit 1
fi
expect 0 "simplify" -- "$tools/bpm-simplify" "$elephant" -o "$work/e.bpm" --ratio 0.1 -q
expect 0 "mesh into .bpm" -- "$tools/bpm-mesh" "$work/e.bpm" -o "$work/e.tet.bpm" -q
expect 0 "mesh file still passes bpm-check" -- "$tools/bpm-check" "$work/e.tet.bpm"
for ext in msh vtu mesh bpm; do
    expect 0 "volume refinement to .$ext" -- "$tools/bpm-refine" "$work/e.tet.bpm" --volume --levels 1 -o "$work/fine.$ext"
    contains "$work/err" "0 inverted" "no inverted element (.$ext)"
done
expect 0 "refined file passes bpm-check" -- "$tools/bpm-check" "$work/fine.bpm"
expect 3 "volume refinement of a file without a mesh" -- "$tools/bpm-refine" "$work/e.bpm" --volume --levels 1 -o "$work/x.msh"
contains "$work/err" "bpm-mesh" "the message says how to get a mesh"
expect 2 "volume refinement needs --levels" -- "$tools/bpm-refine" "$work/e.tet.bpm" --volume --tolerance 0.01 -o "$work/x.msh"
expect 2 "volume refinement to a surface format" -- "$tools/bpm-refine" "$work/e.tet.bpm" --volume --levels 1 -o "$work/x.off"
ok "no output after failures" -- test ! -e "$work/x.msh" -a ! -e "$work/x.off"
finish
