#!/usr/bin/env bash
# An OBJ whose groups are plain names (a CAD export: inlet, outlet, wall) kept the groups
# as patches but dropped their names: every patch was named "<file>|exterior", so the
# physical surfaces of bpm-refine's and bpm-mesh's MSH output all had one name, and a
# solver could not find "inlet" by name. The names are now the patches' names; the
# material is still the file's (one file, one material).
# Usage: obj_group_names_kept.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
cat >"$work/duct.obj" <<'END'
# a box-shaped duct: inlet at x = 0, outlet at x = 2, the rest wall
o Duct
v 0 0 0
v 2 0 0
v 2 1 0
v 0 1 0
v 0 0 1
v 2 0 1
v 2 1 1
v 0 1 1
vn 0 0 1
g inlet
usemtl blue
f 1//1 5//1 8//1
f 1//1 8//1 4//1
g outlet
f 2 3 7
f 2 7 6
g wall
usemtl grey
f 1 4 3
f 1 3 2
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 4 8 7
f 4 7 3
END
expect 0 "simplify" -- "$tools/bpm-simplify" "$work/duct.obj" -o "$work/duct.bpm" --ratio 1 -q
expect 0 "info" -- "$tools/bpm-info" "$work/duct.bpm"
contains "$work/out" '0: "inlet (blue)" (front exterior, back duct)' "the inlet keeps its name, the file's material"
contains "$work/out" '1: "outlet (blue)"' "the outlet keeps its name"
contains "$work/out" '2: "wall (grey)"' "the wall keeps its name"
expect 0 "refine to MSH" -- "$tools/bpm-refine" "$work/duct.bpm" --levels 1 -o "$work/duct.msh" -q
contains "$work/duct.msh" '2 1 "inlet (blue)"' "MSH physical surface 1 is the inlet"
contains "$work/duct.msh" '2 3 "wall (grey)"' "MSH physical surface 3 is the wall"
if command -v tetgen >/dev/null; then
    expect 0 "mesh to MSH" -- "$tools/bpm-mesh" "$work/duct.bpm" -o "$work/duct.tet.msh"
    contains "$work/err" "1 material: 1 duct (region 1)" "the region is the file's material"
    contains "$work/duct.tet.msh" '2 2 "outlet (blue)"' "the volume mesh's boundary keeps the names"
fi
# From standard input there is no file material: the names alone.
expect 0 "simplify from stdin" -- sh -c "'$tools/bpm-simplify' - --input-format obj -o '$work/stdin.bpm' --ratio 1 -q < '$work/duct.obj'"
expect 0 "info" -- "$tools/bpm-info" "$work/stdin.bpm"
contains "$work/out" '0: "inlet (blue)"' "names without a file material"
finish
