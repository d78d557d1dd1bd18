#!/usr/bin/env bash
# A cube scaled by 1e80 or 1e-80 (defect of a new-user audit): bpm-simplify removed
# nothing, exited 0 and blamed "input slivers" (R/r -nan or inf: the aspect ratio's
# fourth powers of lengths overflow or underflow). Now it refuses such coordinates with
# exit 5, the values found, the range bpm computes in and what to do (rescale), and
# writes no output; 1e30 and 1e-30 still simplify like the unit cube.
# Usage: coordinates_out_of_range_refused.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
py=/usr/bin/python3
$py - "$work" "$src/tests/cli/lib" <<'PY'
import sys
sys.path.insert(0, sys.argv[2])
from grid_cube import cube_triangles
work = sys.argv[1]
tris = cube_triangles(4)
index = {}
for t in tris:
    for v in t: index.setdefault(v, len(index))
for name, scale in [("unit", 1.0), ("big30", 1e30), ("small30", 1e-30), ("big80", 1e80), ("small80", 1e-80)]:
    lines = ["OFF", "%d %d 0" % (len(index), len(tris))]
    lines += ["%r %r %r" % tuple(c * scale for c in v) for v in index]
    lines += ["3 %d %d %d" % tuple(index[v] for v in t) for t in tris]
    open("%s/%s.off" % (work, name), "w").write("\n".join(lines) + "\n")
PY

for name in big80 small80; do
    expect 5 "$name: refused (exit 5)" -- "$tools/bpm-simplify" "$work/$name.off" -o "$work/$name.bpm" --ratio 0.5
    contains "$work/err" "bpm-simplify: error: $work/$name.off: coordinates out of range" "$name: the file is named"
    contains "$work/err" "Rescale the input" "$name: the message says what to do"
    contains "$work/err" "within +-1e+40" "$name: the message gives the range"
    ok "$name: no output file" -- test ! -e "$work/$name.bpm"
    if grep -qF "slivers" "$work/err"; then
        failures=$((failures + 1))
        echo "FAILED: $name: still blamed on slivers"
    else
        passes=$((passes + 1))
    fi
done
contains "$work/err" "the bounding box is only 1e-80 across" "small80: the message gives the size found"
expect 5 "big80 with --repair-self-intersections: refused before the repair" -- \
    "$tools/bpm-simplify" "$work/big80.off" -o "$work/big80.bpm" --ratio 0.5 --repair-self-intersections
contains "$work/err" "the largest magnitude is 1e+80" "big80: the message gives the largest coordinate"

# Inside the range the result is that of the unit cube.
expect 0 "the unit cube" -- "$tools/bpm-simplify" "$work/unit.off" -o "$work/unit.bpm" --ratio 0.5 -q
for name in big30 small30; do
    expect 0 "$name: simplified" -- "$tools/bpm-simplify" "$work/$name.off" -o "$work/$name.bpm" --ratio 0.5
    contains "$work/err" "98 -> 49 vertices" "$name: half of the vertices removed"
    expect 0 "$name: bpm-check passes" -- "$tools/bpm-check" "$work/$name.bpm"
done
finish
