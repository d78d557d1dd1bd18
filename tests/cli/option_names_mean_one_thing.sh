#!/usr/bin/env bash
# One option vocabulary across the tools: --input-format / --output-format everywhere
# (--format was the input format in bpm-simplify/bpm-check and the output format in
# bpm-refine/bpm-mesh), the old --format still accepted with a deprecation warning and
# its old meaning; bpm-check has -q/-v; every check --help lists is accepted by --checks;
# a decimal comma gets a message that says so.
# Usage: option_names_mean_one_thing.sh TOOL_DIR SOURCE_DIR WORK_DIR
set -u
tools=$1
work=$3
rm -rf "$work"
mkdir -p "$work"
source "$(dirname "$0")/lib/harness.bash"
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$work/tet.off"

expect 0 "bpm-simplify --input-format off from stdin" -- "$tools/bpm-simplify" - --input-format off -o "$work/a.bpm" --vertices 4 -q <"$work/tet.off"
expect 0 "bpm-simplify --format (deprecated) still reads the input format" -- "$tools/bpm-simplify" - --format off -o "$work/b.bpm" --vertices 4 <"$work/tet.off"
contains "$work/err" "--format is deprecated" "deprecation warning"
contains "$work/err" "use --input-format" "the warning names the new option"
expect 0 "bpm-simplify --format -q: no deprecation warning" -- "$tools/bpm-simplify" - --format off -o "$work/b.bpm" --vertices 4 -q <"$work/tet.off"
ok "-q keeps stderr empty" -- test ! -s "$work/err"
expect 0 "bpm-refine --output-format off to stdout" -- "$tools/bpm-refine" "$work/a.bpm" --levels 1 -o - --output-format off -q
contains "$work/out" "OFF" "OFF on stdout"
expect 0 "bpm-refine --format (deprecated) still names the output format" -- "$tools/bpm-refine" "$work/a.bpm" --levels 1 -o - --format off
contains "$work/err" "use --output-format" "bpm-refine's warning names --output-format"
expect 0 "bpm-check --surface --input-format from stdin" -- "$tools/bpm-check" --surface - --input-format off <"$work/tet.off"
for t in bpm-simplify bpm-check; do
    expect 0 "$t --help" -- "$tools/$t" --help
    contains "$work/out" "--input-format" "$t --help lists --input-format"
done
for t in bpm-refine bpm-mesh; do
    expect 0 "$t --help" -- "$tools/$t" --help
    contains "$work/out" "--output-format" "$t --help lists --output-format"
done

expect 0 "bpm-check -q" -- "$tools/bpm-check" "$work/a.bpm" -q
expect 0 "bpm-check -v" -- "$tools/bpm-check" "$work/a.bpm" -v
expect 0 "bpm-check --checks distance (listed in --help)" -- "$tools/bpm-check" "$work/a.bpm" --checks distance
contains "$work/out" "PASS distance" "the distance check ran"
expect 0 "bpm-check --checks quality" -- "$tools/bpm-check" "$work/a.bpm" --checks quality
contains "$work/out" "PASS quality" "the quality check ran"
expect 2 "bpm-check --checks nonsense" -- "$tools/bpm-check" "$work/a.bpm" --checks nonsense
contains "$work/err" "known: format" "the error lists the known checks"

expect 2 "bpm-simplify --ratio 0,1" -- "$tools/bpm-simplify" "$work/tet.off" -o "$work/c.bpm" --ratio 0,1
contains "$work/err" "(0, 1]" "the message gives the range"
contains "$work/err" "dot" "the message says the decimal point is a dot"
expect 2 "bpm-simplify --ratio 0" -- "$tools/bpm-simplify" "$work/tet.off" -o "$work/c.bpm" --ratio 0
contains "$work/err" "(0, 1]" "0 is outside (0, 1]"
finish
