#!/usr/bin/env bash
# A target the input already meets must not pass silently ("3897 -> 3897", exit 0, no
# word), and -q must mean what its help says: only errors on stderr, no warnings.
# Usage: no_silent_noops.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$work/tet.off"

expect 0 "--vertices above the input's count" -- "$tools/bpm-simplify" "$work/tet.off" -o "$work/a.bpm" --vertices 100000
contains "$work/err" "warning: --vertices 100000 is not below the input's 4 vertices" "the warning says the input's count"
expect 0 "--ratio 1" -- "$tools/bpm-simplify" "$work/tet.off" -o "$work/a.bpm" --ratio 1
contains "$work/err" "warning: --ratio 1 keeps all 4 vertices" "--ratio 1 is a no-op and says so"
expect 0 "--vertices above the count with -q" -- "$tools/bpm-simplify" "$work/tet.off" -o "$work/a.bpm" --vertices 100000 -q
ok "-q: no warning on stderr" -- test ! -s "$work/err"
# A target that cannot be reached (a tetrahedron keeps its 4 vertices): a warning, not under -q.
expect 0 "unreachable target" -- "$tools/bpm-simplify" "$work/tet.off" -o "$work/a.bpm" --vertices 2
contains "$work/err" "warning: stopped before the target" "the unreached target is a warning"
expect 0 "unreachable target with -q" -- "$tools/bpm-simplify" "$work/tet.off" -o "$work/a.bpm" --vertices 2 -q
ok "-q: stderr empty" -- test ! -s "$work/err"
expect 0 "bpm-smooth -q" -- "$tools/bpm-smooth" "$work/a.bpm" -o "$work/b.bpm" -q
ok "bpm-smooth -q: stderr empty" -- test ! -s "$work/err"
# bpm-smooth --iterations 0 wrote a copy and said "0 sweeps": a no-op, so a warning.
expect 0 "bpm-smooth --iterations 0" -- "$tools/bpm-smooth" "$work/a.bpm" -o "$work/b.bpm" --iterations 0
contains "$work/err" "warning: --iterations 0: no sweep, so phi is written out unchanged (give 1 or more" \
    "bpm-smooth --iterations 0 says it did nothing"
expect 0 "bpm-smooth --iterations 0 -q" -- "$tools/bpm-smooth" "$work/a.bpm" -o "$work/b.bpm" --iterations 0 -q
ok "bpm-smooth -q: stderr empty" -- test ! -s "$work/err"
expect 0 "bpm-refine -q" -- "$tools/bpm-refine" "$work/a.bpm" --max-error 1e-9 --max-level 1 -o "$work/b.off" -q
ok "bpm-refine -q: its max-level warning is not printed" -- test ! -s "$work/err"
expect 3 "an error is still printed under -q" -- "$tools/bpm-refine" "$work/missing.bpm" --levels 1 -o "$work/b.off" -q
contains "$work/err" "error:" "errors survive -q"
finish
