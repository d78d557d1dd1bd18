#!/usr/bin/env bash
# bpm-torsion reports errors like the bpm tools: `bpm-torsion: error: FILE: message` and
# README.md's exit codes. Before: a missing file gave "bpm-torsion: cannot open: No such
# file or directory" (no file named) and exit 1; a .bpm without a tet mesh exit 1; an
# unknown option exit 106; --version was unknown ("INPUT is required", exit 106).
# Usage: test_torsion_errors.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$2/tests/cli/lib/harness.bash"
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$work/tet.off"
"$tools/bpm-simplify" "$work/tet.off" -o "$work/tet.bpm" --vertices 4 -q

expect 3 "a missing file" -- "$tools/bpm-torsion" "$work/missing.bpm"
contains "$work/err" "bpm-torsion: error: $work/missing.bpm: cannot open" "the file is named"
expect 3 "a .bpm without a tet mesh" -- "$tools/bpm-torsion" "$work/tet.bpm"
contains "$work/err" "bpm-torsion: error: $work/tet.bpm: the .bpm file has no tet mesh (/tetmesh): run bpm-mesh" \
    "the file and the fix are named"
expect 2 "an unknown option" -- "$tools/bpm-torsion" "$work/tet.bpm" --bogus
expect 2 "too many uniform levels" -- "$tools/bpm-torsion" "$work/tet.bpm" --levels 9
contains "$work/err" "at most 8 uniform levels" "the limit is said"
expect 0 "--version" -- "$tools/bpm-torsion" --version
contains "$work/out" "bpm-torsion" "the version line names the tool"
expect 0 "--help" -- "$tools/bpm-torsion" --help
contains "$work/out" "Exit codes:" "--help lists the exit codes"
finish
