#!/usr/bin/env bash
# One option vocabulary across the tools: --input-format / --output-format everywhere
# (--format was the input format in bpm-simplify/bpm-check and the output format in
# bpm-refine/bpm-mesh), the old --format still accepted with a deprecation warning and
# its old meaning; bpm-check has -q/-v; every check --help lists is accepted by --checks;
# a decimal comma gets a message that says so. One word per quantity: --max-error is
# max |phi(x) - x| (bpm-simplify, bpm-refine; bpm-check's --max-error, a Hausdorff distance,
# is --max-distance now), --tolerance is bpm-smooth's stopping threshold (bpm-refine's,
# the same quantity as --max-error, is --max-error now); the old spellings work with a
# deprecation warning (none with -q) and cannot be combined with the new ones.
# Usage: option_names_mean_one_thing.sh TOOL_DIR SOURCE_DIR WORK_DIR
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

# Every tool that lists a quantity's option outside "Deprecated:" says the same thing of it.
help_line() {  # help_line TOOL OPTION: OPTION's --help entry (and description) outside the Deprecated group
    awk -v o="$2" 'found { print; exit } /^[A-Z][^ ].*:$/ { group = $0 }
        group != "Deprecated:" && ($1 == o || index($0, ", " o " ")) { print; found = 1 }' <("$tools/$1" --help)
}
for t in bpm-simplify bpm-smooth bpm-check bpm-refine bpm-mesh; do
    line=$(help_line "$t" --max-error)
    [ -z "$line" ] || ok "$t --max-error is max |phi(x) - x|" -- grep -qF '|phi(x) - x|' <<<"$line"
    line=$(help_line "$t" --max-distance)
    [ -z "$line" ] || ok "$t --max-distance is a Hausdorff distance" -- grep -qF 'Hausdorff' <<<"$line"
    line=$(help_line "$t" --tolerance)
    [ -z "$line" ] || ok "$t --tolerance is a fraction of an edge length" -- grep -qF 'edge length' <<<"$line"
done
ok "bpm-simplify and bpm-refine have --max-error" -- test -n "$(help_line bpm-simplify --max-error)" -a -n "$(help_line bpm-refine --max-error)"
ok "bpm-check has --max-distance" -- test -n "$(help_line bpm-check --max-distance)"
ok "bpm-check lists no --max-error outside Deprecated" -- test -z "$(help_line bpm-check --max-error)"
ok "bpm-refine lists no --tolerance outside Deprecated" -- test -z "$(help_line bpm-refine --tolerance)"

expect 0 "bpm-check --max-distance" -- "$tools/bpm-check" "$work/a.bpm" --max-distance 0.5
contains "$work/out" "PASS distance" "--max-distance runs the distance check"
expect 0 "bpm-check --max-error (deprecated) is --max-distance" -- "$tools/bpm-check" "$work/a.bpm" --max-error 0.5
contains "$work/out" "PASS distance" "the old name still runs the distance check"
contains "$work/err" "--max-error is deprecated" "bpm-check warns about --max-error"
contains "$work/err" "use --max-distance" "the warning names --max-distance"
contains "$work/err" "max |phi(x) - x|" "the warning says what --max-error means elsewhere"
expect 0 "bpm-check --error-spacing (deprecated) is --sample-spacing" -- "$tools/bpm-check" "$work/a.bpm" --max-distance 0.5 --error-spacing 0.5
contains "$work/err" "--error-spacing is deprecated" "bpm-check warns about --error-spacing"
contains "$work/err" "use --sample-spacing" "the warning names --sample-spacing"
expect 0 "bpm-check --max-error -q: no warning" -- "$tools/bpm-check" "$work/a.bpm" --max-error 0.5 -q
ok "-q keeps stderr empty (bpm-check)" -- test ! -s "$work/err"
expect 2 "bpm-check --max-error with --max-distance" -- "$tools/bpm-check" "$work/a.bpm" --max-error 0.5 --max-distance 0.5
expect 2 "bpm-check --max-error -1 (the old name keeps its check)" -- "$tools/bpm-check" "$work/a.bpm" --max-error -1

expect 0 "bpm-refine --max-error" -- "$tools/bpm-refine" "$work/a.bpm" --max-error 0.01 --max-level 1 -o "$work/r1.off"
expect 0 "bpm-refine --tolerance (deprecated) is --max-error" -- "$tools/bpm-refine" "$work/a.bpm" --tolerance 0.01 --max-level 1 -o "$work/r2.off"
contains "$work/err" "--tolerance is deprecated" "bpm-refine warns about --tolerance"
contains "$work/err" "use --max-error" "the warning names --max-error"
ok "the same refinement either way" -- cmp -s "$work/r1.off" "$work/r2.off"
expect 2 "bpm-refine --tolerance with --max-error" -- "$tools/bpm-refine" "$work/a.bpm" --tolerance 0.01 --max-error 0.01 -o "$work/r3.off"
expect 2 "bpm-refine --tolerance with --levels" -- "$tools/bpm-refine" "$work/a.bpm" --tolerance 0.01 --levels 1 -o "$work/r3.off"
expect 2 "bpm-refine --tolerance 0 (the old name keeps its check)" -- "$tools/bpm-refine" "$work/a.bpm" --tolerance 0 -o "$work/r3.off"
expect 0 "bpm-smooth --tolerance (its own quantity, not deprecated)" -- "$tools/bpm-smooth" "$work/a.bpm" --tolerance 0.01 -o "$work/s.bpm"
ok "bpm-smooth --tolerance: no deprecation warning" -- test "$(grep -c deprecated "$work/err")" -eq 0

expect 2 "bpm-simplify --ratio 0,1" -- "$tools/bpm-simplify" "$work/tet.off" -o "$work/c.bpm" --ratio 0,1
contains "$work/err" "(0, 1]" "the message gives the range"
contains "$work/err" "dot" "the message says the decimal point is a dot"
expect 2 "bpm-simplify --ratio 0" -- "$tools/bpm-simplify" "$work/tet.off" -o "$work/c.bpm" --ratio 0
contains "$work/err" "(0, 1]" "0 is outside (0, 1]"
finish
