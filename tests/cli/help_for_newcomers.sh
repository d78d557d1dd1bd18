#!/usr/bin/env bash
# Every tool's --help ends with examples and the exit-code table, and every tool prints
# at most two lines on stderr by default (bpm-smooth printed ~15: one per sweep and the
# breakdown of skipped / rejected updates, now under -v).
# Usage: help_for_newcomers.sh TOOL_DIR SOURCE_DIR WORK_DIR
set -u
tools=$1
work=$3
rm -rf "$work"
mkdir -p "$work"
source "$(dirname "$0")/lib/harness.bash"
for t in bpm-simplify bpm-smooth bpm-check bpm-refine bpm-mesh; do
    expect 0 "$t --help" -- "$tools/$t" --help
    contains "$work/out" "Exit codes:" "$t --help has the exit-code table"
    contains "$work/out" "  6   an external program" "$t --help lists exit code 6"
    contains "$work/out" "Examples:" "$t --help has examples"
done
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$work/tet.off"
expect 0 "simplify" -- "$tools/bpm-simplify" "$work/tet.off" -o "$work/a.bpm" --vertices 4
ok "bpm-simplify: at most 2 lines besides warnings by default" -- test "$(grep -vc "warning:" "$work/err")" -le 2
expect 0 "smooth" -- "$tools/bpm-smooth" "$work/a.bpm" -o "$work/b.bpm"
ok "bpm-smooth: at most 2 lines by default" -- test "$(wc -l <"$work/err")" -le 2
expect 0 "smooth -v" -- "$tools/bpm-smooth" "$work/a.bpm" -o "$work/b.bpm" -v
contains "$work/err" "sweep 1" "bpm-smooth -v still shows the sweeps"
expect 0 "refine" -- "$tools/bpm-refine" "$work/a.bpm" --levels 1 -o "$work/c.off"
ok "bpm-refine: at most 2 lines by default" -- test "$(wc -l <"$work/err")" -le 2
finish
