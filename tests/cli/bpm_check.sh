#!/usr/bin/env bash
# bpm-check end to end: exit codes, text lines, JSON validity.
# Usage: bpm_check.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
check=$tools/bpm-check
example=$src/spec/examples/two_triangles.bpm
meshes=$src/.data/meshes


expect 0 "help" -- "$check" --help
contains "$work/out" "--original" "help mentions --original"
contains "$work/out" "--max-aspect" "help mentions --max-aspect"

expect 0 "spec example passes" -- "$check" "$example"
contains "$work/out" "PASS format  " "format line"
contains "$work/out" "PASS bijectivity  " "bijectivity line"
contains "$work/out" "PASS distortion  " "distortion line (phi's area squeeze and normal deviation)"

expect 0 "stdin" -- bash -c "cat '$example' | '$check' -"

expect 0 "json" -- "$check" --json --original "$example"
cp "$work/out" "$work/report.json"
if command -v python3 >/dev/null; then
    expect 0 "json parses" -- python3 -c "import json,sys; r=json.load(open('$work/report.json')); assert r['passed'] and r['bpm_check_report']==1; assert [c['name'] for c in r['checks']]==['format','original-intersections','intersections','topology','junctions','bijectivity','distortion']; d=r['checks'][-1]; assert d['counts']['pieces'] > 0 and [m['name'] for m in d['measures']][2]=='area_squeeze_max'"
fi

expect 1 "quality gate fails" -- "$check" --max-aspect 2.01 "$example"
contains "$work/out" "FAIL quality  " "quality line"

expect 2 "unknown check" -- "$check" --checks format,nonsense "$example"
expect 2 "bad option" -- "$check" --no-such-option "$example"
expect 3 "missing file" -- "$check" "$work/does-not-exist.bpm"
printf 'not hdf5 at all' >"$work/garbage.bpm"
expect 3 "garbage file" -- "$check" "$work/garbage.bpm"

if [ -f "$meshes/tetra_intersected_by_triangle.off" ]; then
    expect 1 "self-intersecting surface" -- "$check" --surface "$meshes/tetra_intersected_by_triangle.off"
    contains "$work/out" "FAIL intersections  " "intersection line"
    expect 0 "clean surface" -- "$check" --surface "$meshes/elephant.off"
    contains "$work/out" "PASS topology  1 component, chi -4" "elephant topology"
fi

finish
