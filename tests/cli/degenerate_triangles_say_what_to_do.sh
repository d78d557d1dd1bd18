#!/usr/bin/env bash
# A degenerate triangle (two corners the same vertex, or three collinear corners) is
# refused (exit 3) with the triangle named; before, the message stopped there and a user
# looked in --help for a repair flag that does not exist. Now it says that there is none
# and what to do.
# Usage: degenerate_triangles_say_what_to_do.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
tet='OFF\n4 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n'
printf "${tet}3 0 0 1\n" >"$work/repeated.off"
printf 'OFF\n5 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n2 0 0\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n3 0 1 4\n' >"$work/collinear.off"
for f in repeated collinear; do
    expect 3 "$f: refused" -- "$tools/bpm-simplify" "$work/$f.off" -o "$work/x.bpm" --vertices 4
    contains "$work/err" "triangle 4 (vertices" "$f: the triangle is named"
    contains "$work/err" "bpm has no repair option for degenerate triangles: remove them from the input" \
        "$f: no flag to look for, and what to do"
done
# With a repair that does exist, both are said.
printf 'OFF\n5 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 0 0\n3 0 2 1\n3 4 1 3\n3 0 3 2\n3 1 2 3\n3 0 0 1\n' >"$work/both.off"
expect 3 "a degenerate triangle and duplicate vertices" -- "$tools/bpm-simplify" "$work/both.off" -o "$work/x.bpm" --vertices 4
contains "$work/err" "bpm has no repair option for degenerate triangles" "the degenerate triangle is explained"
finish
