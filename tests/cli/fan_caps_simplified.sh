#!/usr/bin/env bash
# A closed cylinder whose two discs are fans around one centre vertex each, as CAD
# exporters write them (tests/cli/lib/fan_cylinder.py). Each centre is re-ranked every time
# one of its rim vertices goes; its plan retriangulated the whole rim (O(n^2)) each time,
# and 3000 segments took 77 s of CPU. Now a centre no retriangulation can pass is refused
# in O(n) (VertexRemover::set_aspect_limit). This checks the results, not the time: the
# caps of 300 segments are simplified away (their rims get short enough for the centres
# to go), those of 1000 keep their centres, and both outputs pass bpm-check.
# Usage: fan_caps_simplified.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
simplify=$tools/bpm-simplify
check=$tools/bpm-check
gen=$src/tests/cli/lib/fan_cylinder.py

/usr/bin/python3 "$gen" "$work/cyl300.off" 300
/usr/bin/python3 "$gen" "$work/cyl1000.off" 1000
contains "$work/cyl1000.off" "5002 10000 0" "1000 segments: 5 rings and 2 centres, 10 N triangles"

expect 0 "300 segments simplified" -- "$simplify" "$work/cyl300.off" -o "$work/cyl300.bpm" --ratio 0.1 --threads 1
contains "$work/err" "1502 -> 151 vertices (298 triangles)" "300 segments: target reached"
ok "300 segments: no sliver left (the centres went)" -- test "$(grep -c 'aspect ratio above' "$work/err")" -eq 0
expect 0 "300 segments pass bpm-check" -- "$check" "$work/cyl300.bpm"

expect 0 "1000 segments simplified" -- "$simplify" "$work/cyl1000.off" -o "$work/cyl1000.bpm" --ratio 0.1 --threads 1
contains "$work/err" "5002 -> 501 vertices (998 triangles)" "1000 segments: target reached"
# The rims keep about 250 vertices each: every retriangulation of such a disc is worse
# than its fan, so the centres stay and their slivers are reported, with the reason.
contains "$work/err" "kept: triangle shape limit (--max-aspect)" "the centres' reason is the shape limit"
expect 0 "1000 segments pass bpm-check" -- "$check" "$work/cyl1000.bpm"

finish
