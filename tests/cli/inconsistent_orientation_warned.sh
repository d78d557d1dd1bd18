#!/usr/bin/env bash
# An input whose triangles are not consistently oriented (a few flipped, as some STL
# exporters and scan pipelines leave them) is accepted, but bpm-simplify now says so:
# before, nothing did, and the user saw only "phi turns pieces by up to 180 degrees
# (672 > 90)" with no cause, while the materials of the flipped triangles' front and back
# sides (patch_info, bpm-mesh) were swapped there.
# Usage: inconsistent_orientation_warned.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"

# An octahedron (6 vertices, 8 triangles), outward; then the same with triangle 5 flipped.
good='OFF\n6 8 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n'
printf "$good" >"$work/good.off"
printf "$good" | sed 's/^3 1 2 5$/3 2 1 5/' >"$work/flipped.off"
ok "the fixture has one triangle flipped" -- grep -q '^3 2 1 5$' "$work/flipped.off"

expect 0 "a consistently oriented input" -- "$tools/bpm-simplify" "$work/good.off" -o "$work/good.bpm" --vertices 6
ok "no orientation warning" -- bash -c "! grep -q 'not consistently oriented' '$work/err'"
expect 0 "one flipped triangle: accepted" -- "$tools/bpm-simplify" "$work/flipped.off" -o "$work/flipped.bpm" --vertices 6
contains "$work/err" "bpm-simplify: warning: the triangles are not consistently oriented: at 3 edges two neighbours face opposite sides (first: triangles 1 and 5 at the edge of vertices 1 and 2)" \
    "the warning counts the edges and names the first pair"
contains "$work/err" "Orient the input consistently" "the warning says what to do"
ok "the output is written" -- test -s "$work/flipped.bpm"
expect 0 "-q silences it" -- "$tools/bpm-simplify" "$work/flipped.off" -o "$work/flipped.bpm" --vertices 6 -q
ok "nothing on stderr with -q" -- test ! -s "$work/err"
# Two files (the flipped one moved away): the warning names the file.
awk 'NR >= 3 && NR <= 8 { $1 += 5 } { print }' "$work/flipped.off" >"$work/far.off"
expect 0 "two inputs, one of them flipped" -- "$tools/bpm-simplify" "$work/good.off" "$work/far.off" -o "$work/two.bpm" \
    --vertices 12
contains "$work/err" "warning: $work/far.off: the triangles are not consistently oriented" "the file is named"
ok "the good file is not named" -- bash -c "! grep -q 'good.off: the triangles are not' '$work/err'"
finish
