#!/usr/bin/env bash
# Exit 5 ("the algorithm cannot proceed on this input") names the input like every other
# error, `tool: error: FILE: message` (README): before, bpm-mesh on a surface with a hole
# said only "bpm-mesh: error: surface has 3 boundary edges, first at vertices 0-1", with no
# file and coarse vertex numbers that mean nothing in the input; now the file, positions,
# and where the boundary comes from (the input: e.g. an open seam).
# Usage: algorithm_errors_name_the_file.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"

# A unit cube with its top face missing: an open box (a disk).
printf 'OFF\n8 10 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n3 0 2 1\n3 0 3 2\n3 0 1 5\n3 0 5 4\n3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n' >"$work/open.off"
expect 0 "bpm-simplify keeps the open box" -- "$tools/bpm-simplify" "$work/open.off" -o "$work/open.bpm" --ratio 1
expect 5 "bpm-mesh on an open surface" -- "$tools/bpm-mesh" "$work/open.bpm" -o "$work/open.tet.bpm"
contains "$work/err" "bpm-mesh: error: $work/open.bpm: the coarse surface has 4 boundary edges" "the file is named"
contains "$work/err" "first from vertex" "a boundary edge is given"
ok "with the positions of its ends" -- grep -qE "vertex [0-9]+ \(-?[0-9.e+-]+, -?[0-9.e+-]+, 1\) to vertex" "$work/err"
contains "$work/err" "The boundary is the input surface's" "the cause is said to be the input"
ok "no partial output" -- test ! -e "$work/open.tet.bpm"
expect 5 "bpm-mesh from standard input" -- bash -c "'$tools/bpm-mesh' - -o '$work/x.bpm' <'$work/open.bpm'"
contains "$work/err" "bpm-mesh: error: <stdin>: the coarse surface has" "standard input is named as the readers name it"

# bpm-simplify: an input that intersects itself (two overlapping tetrahedra, two files).
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$work/a.off"
printf 'OFF\n4 4 0\n0.2 0.2 0.2\n1.2 0.2 0.2\n0.2 1.2 0.2\n0.2 0.2 1.2\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$work/b.off"
expect 5 "bpm-simplify on inputs that intersect" -- "$tools/bpm-simplify" "$work/a.off" "$work/b.off" -o "$work/ab.bpm" --ratio 1
contains "$work/err" "bpm-simplify: error: $work/a.off + $work/b.off: the input surface intersects itself" \
    "both files are named"
# The first pair is one triangle of each file (two patches): the message says where the
# two materials' surfaces overlap and what a multi-material input must look like there.
contains "$work/err" "in patches 0 and 1 (if these are the surfaces of two materials" "the two patches are named"
contains "$work/err" "must be the same triangles in both" "what an interface must be is said"
# The same two tetrahedra in one file are one patch: no word of materials.
{ printf 'OFF\n8 8 0\n'; sed -n '3,6p' "$work/a.off"; sed -n '3,6p' "$work/b.off"
  sed -n '7,10p' "$work/a.off"; sed -n '7,10p' "$work/b.off" | awk '{print 3, $2 + 4, $3 + 4, $4 + 4}'; } >"$work/ab.off"
expect 5 "bpm-simplify on one file that intersects itself" -- "$tools/bpm-simplify" "$work/ab.off" -o "$work/one.bpm" --ratio 1
contains "$work/err" "the input surface intersects itself" "the one file is refused too"
ok "one patch: no patches named" -- bash -c "! grep -q 'in patches' '$work/err'"
finish
