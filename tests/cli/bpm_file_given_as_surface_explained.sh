#!/usr/bin/env bash
# A .bpm file given where a surface belongs (a newcomer simplifying a result again):
# bpm-simplify said "cannot tell the surface format from the file name; expected the
# extension .off, ..." (the name ends in .bpm), and with --input-format off a parse error
# at byte 0. Now it says that this is an HDF5 file, not a surface, and how to write a
# .bpm file's coarse surface out; exit 3, no output.
# Usage: bpm_file_given_as_surface_explained.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
py=/usr/bin/python3
$py - "$work" "$src/tests/cli/lib" <<'PY'
import sys
sys.path.insert(0, sys.argv[2])
from grid_cube import cube_triangles
tris = cube_triangles(4)
index = {}
for t in tris:
    for v in t: index.setdefault(v, len(index))
lines = ["OFF", "%d %d 0" % (len(index), len(tris))]
lines += ["%r %r %r" % v for v in index]
lines += ["3 %d %d %d" % tuple(index[v] for v in t) for t in tris]
open(sys.argv[1] + "/cube.off", "w").write("\n".join(lines) + "\n")
PY
expect 0 "simplify the cube" -- "$tools/bpm-simplify" "$work/cube.off" -o "$work/cube.bpm" --ratio 0.5 -q
expect 3 "bpm-simplify on a .bpm: exit 3" -- "$tools/bpm-simplify" "$work/cube.bpm" -o "$work/again.bpm" --ratio 0.5
contains "$work/err" "bpm-simplify: error: $work/cube.bpm: an HDF5 file (a .bpm?), not a surface" "the file and what it is"
contains "$work/err" "bpm-refine FILE --levels 0 -o coarse.off" "how to write its coarse surface out"
ok "no output" -- test ! -e "$work/again.bpm"
cp "$work/cube.bpm" "$work/cube.off"
expect 3 "the same with an .off name" -- "$tools/bpm-simplify" "$work/cube.off" -o "$work/again.bpm" --ratio 0.5
contains "$work/err" "an HDF5 file (a .bpm?), not a surface" "... and the same message"
expect 0 "the coarse surface as the message says" -- "$tools/bpm-refine" "$work/cube.bpm" --levels 0 -o "$work/coarse.off" -q
expect 0 "... simplifies" -- "$tools/bpm-simplify" "$work/coarse.off" -o "$work/again.bpm" --ratio 0.5 -q
finish
