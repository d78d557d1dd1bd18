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

# A .bpm written elsewhere with such coordinates (the unit cube's file scaled by 1e80 and
# 1e-80): bpm-check passed it with NaN distortions, bpm-smooth and bpm-refine wrote
# nonsense, TetGen aborted under bpm-mesh. Now bpm-check fails the format check and the
# tools that compute refuse it, naming the file, writing nothing.
$py - "$work" <<'PY'
import shutil, sys
import h5py
work = sys.argv[1]
for name, scale in [("big80", 1e80), ("small80", 1e-80)]:
    shutil.copy("%s/unit.bpm" % work, "%s/%s-file.bpm" % (work, name))
    with h5py.File("%s/%s-file.bpm" % (work, name), "r+") as f:
        for d in ("original/vertices", "coarse/vertices"):
            f[d][...] = f[d][()] * scale
PY
for name in big80 small80; do
    file=$work/$name-file.bpm
    expect 1 "$name .bpm: bpm-check fails" -- "$tools/bpm-check" "$file"
    contains "$work/out" "FAIL format" "$name .bpm: the format check fails"
    contains "$work/out" "coordinates out of range" "$name .bpm: bpm-check says why"
    for tool in bpm-mesh bpm-refine bpm-smooth; do
        args=()
        [ $tool != bpm-refine ] || args=(--levels 1)
        expect 5 "$name .bpm: $tool refuses it" -- "$tools/$tool" "$file" -o "$work/$name-$tool.bpm" "${args[@]}"
        contains "$work/err" "$tool: error: $file: coordinates out of range" "$name .bpm: $tool names the file and the problem"
        ok "$name .bpm: $tool writes nothing" -- test ! -e "$work/$name-$tool.bpm"
    done
done
finish
