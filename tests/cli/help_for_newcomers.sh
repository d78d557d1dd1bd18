#!/usr/bin/env bash
# Every tool's --help ends with examples and the exit-code table, groups its options
# (internals such as --queue-tolerance under "Advanced", not beside the basics) with one
# line per option, and every tool prints at most two lines on stderr by default (bpm-smooth printed ~15: one per sweep and the
# breakdown of skipped / rejected updates, now under -v).
# Usage: help_for_newcomers.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
for t in bpm-simplify bpm-smooth bpm-check bpm-refine bpm-mesh bpm-info; do
    expect 0 "$t --help" -- "$tools/$t" --help
    contains "$work/out" "Exit codes:" "$t --help has the exit-code table"
    contains "$work/out" "  6   an external program" "$t --help lists exit code 6"
    contains "$work/out" "Examples:" "$t --help has examples"
    contains "$work/out" "Output:" "$t --help groups the output options"
    # bpm-info has no internals to set apart (FILE, --json, -v, -q).
    [ "$t" = bpm-info ] || contains "$work/out" "Advanced:" "$t --help has an Advanced group"
    ok "$t --help: one line per option, at most 150 characters" -- \
        test "$(grep -E '^  +-' "$work/out" | awk 'length > 150' | wc -l)" -eq 0
done
# The option after a group header up to the next header is in that group.
in_group() {  # in_group TOOL GROUP OPTION
    awk -v g="$2:" -v o="$3" '/^[A-Z][^ ].*:$/ { cur = $0 } $1 == o || index($0, "  " o " ") || index($0, ", " o " ") \
        { if (cur == g) found = 1 } END { exit !found }' <("$tools/$1" --help)
}
ok "bpm-simplify: --queue-tolerance under Advanced" -- in_group bpm-simplify Advanced --queue-tolerance
ok "bpm-simplify: --one-removal-per-step under Advanced" -- in_group bpm-simplify Advanced --one-removal-per-step
ok "bpm-simplify: --ratio under Target" -- in_group bpm-simplify "Target (the first one reached stops)" --ratio
ok "bpm-simplify: --merge-duplicate-vertices under Input repairs" -- \
    in_group bpm-simplify "Input repairs (each is reported)" --merge-duplicate-vertices
ok "bpm-simplify: --feature-angle under Features" -- in_group bpm-simplify Features --feature-angle
ok "bpm-check: --max-distance under Thresholds" -- in_group bpm-check "Thresholds (each adds a check)" --max-distance
ok "bpm-refine: --levels under Target" -- in_group bpm-refine "Target (one of)" --levels
ok "bpm-mesh: --tetgen under Advanced" -- in_group bpm-mesh Advanced --tetgen
ok "bpm-smooth: --weights under Advanced" -- in_group bpm-smooth Advanced --weights
# bpm-mesh (issue 20 item 1: "the default of every option shown in --help"): every option
# with a number says its default (--max-volume and --refine did not). Option lines that
# wrap are joined first.
"$tools/bpm-mesh" --help | awk '/^  +-/ { if (o != "") print o; o = $0; next }
    /^      +[^ -]/ { o = o " " $0; next } { if (o != "") print o; o = "" }' >"$work/mesh-options"
ok "bpm-mesh --help: a default for every numeric option" -- \
    test "$(grep -E '^  +--[a-z-]+ (FLOAT|INT|UINT)' "$work/mesh-options" | grep -vc 'default')" -eq 0
"$tools/bpm-check" --help >"$work/out"
ok "bpm-check --help in plain words (no Conjecture 2.1, CSR offsets, Z2 Betti)" -- \
    test "$(grep -cE 'Conjecture|CSR|Betti' "$work/out")" -eq 0
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$work/tet.off"
expect 0 "simplify" -- "$tools/bpm-simplify" "$work/tet.off" -o "$work/a.bpm" --vertices 4
ok "bpm-simplify: at most 2 lines besides warnings by default" -- test "$(grep -vc "warning:" "$work/err")" -le 2
expect 0 "smooth" -- "$tools/bpm-smooth" "$work/a.bpm" -o "$work/b.bpm"
ok "bpm-smooth: at most 2 lines by default" -- test "$(wc -l <"$work/err")" -le 2
expect 0 "smooth -v" -- "$tools/bpm-smooth" "$work/a.bpm" -o "$work/b.bpm" -v
contains "$work/err" "sweep 1" "bpm-smooth -v still shows the sweeps"
expect 0 "refine" -- "$tools/bpm-refine" "$work/a.bpm" --levels 1 -o "$work/c.off"
ok "bpm-refine: at most 2 lines by default" -- test "$(wc -l <"$work/err")" -le 2
expect 0 "info" -- "$tools/bpm-info" "$work/a.bpm"
ok "bpm-info: nothing on stderr by default (the summary is on stdout)" -- test ! -s "$work/err"
finish
