#!/usr/bin/env bash
# bpm-simplify --repair-self-intersections on a real scan that intersects itself in three
# places (bull.off of the libcgal-demo meshes, which scripts/setup.sh unpacks): refused
# without the flag, with the flag named; repaired with it, reported, and the result passes
# bpm-check; the same bytes twice; so does camel.off (20 pairs). A clean input is left as
# it is; two interpenetrating cubes (not a local crossing) stay refused, with the flag's
# failure said; a repair that moves the surface far (bones.off) needs --max-repair-change.
# Usage: repair_self_intersections.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
simplify=$tools/bpm-simplify
check=$tools/bpm-check
bull=$src/.data/meshes/bull.off
femur=$src/.data/meshes/femur.off
ok "the test meshes are there (scripts/setup.sh)" -- test -f "$bull" -a -f "$femur"

expect 5 "a self-intersecting scan is refused" -- "$simplify" "$bull" -o "$work/x.bpm" --ratio 0.1
contains "$work/err" "rerun with --repair-self-intersections" "the refusal names the repair flag"
contains "$work/err" "use --allow-self-intersecting-input" "... and the flag that allows it"
ok "no output after the refusal" -- test ! -e "$work/x.bpm"

expect 0 "repaired" -- "$simplify" "$bull" -o "$work/bull.bpm" --ratio 0.1 --repair-self-intersections --deterministic
contains "$work/err" "--repair-self-intersections: 3 intersecting pairs, 0 left" "the repair is reported"
contains "$work/err" "phi maps onto the repaired surface" "the report says what phi maps onto"
expect 0 "the repaired result passes bpm-check" -- "$check" "$work/bull.bpm"
mv "$work/bull.bpm" "$work/bull.first.bpm"
expect 0 "repaired again" -- "$simplify" "$bull" -o "$work/bull.bpm" --ratio 0.1 --repair-self-intersections --deterministic
ok "the same bytes twice" -- cmp -s "$work/bull.bpm" "$work/bull.first.bpm"

# camel: 20 pairs; CGAL rebuilds some triangles under their old index (a mapping that once
# left them with a vertex -1).
camel=$src/.data/meshes/camel.off
expect 0 "camel repaired" -- "$simplify" "$camel" -o "$work/camel.bpm" --ratio 0.1 --repair-self-intersections
contains "$work/err" "--repair-self-intersections: 20 intersecting pairs, 0 left" "camel: every pair repaired"
expect 0 "camel passes bpm-check" -- "$check" "$work/camel.bpm"

# bones: the repair replaces 40 % of the surface (loose shells crossing the rest), moving
# it by ~0.07 of the diagonal: refused by default, done when the limit allows it.
bones=$src/.data/meshes/bones.off
expect 5 "bones: a repair that is not local is refused" -- "$simplify" "$bones" -o "$work/bones.bpm" --ratio 0.1 --repair-self-intersections
contains "$work/err" "more than --max-repair-change 0.01" "the refusal names the limit's flag"
expect 0 "bones with --max-repair-change 0.1" -- "$simplify" "$bones" -o "$work/bones.bpm" --ratio 0.1 --repair-self-intersections --max-repair-change 0.1
expect 0 "bones passes bpm-check" -- "$check" "$work/bones.bpm"

expect 0 "a clean input with the flag" -- "$simplify" "$femur" -o "$work/femur.bpm" --ratio 0.1 --repair-self-intersections
contains "$work/err" "does not intersect itself; nothing to repair" "nothing to repair is said"

# Two cubes, one through the other: every face crosses, no local patch repairs that.
cube() {  # cube NAME OFFSET
    local o=$2
    {
        echo "OFF"; echo "8 12 0"
        for x in 0 1; do for y in 0 1; do for z in 0 1; do
            echo "$(echo "$x + $o" | bc) $(echo "$y + $o" | bc) $(echo "$z + $o" | bc)"
        done; done; done
        printf '3 0 1 3\n3 0 3 2\n3 4 6 7\n3 4 7 5\n3 0 4 5\n3 0 5 1\n3 2 3 7\n3 2 7 6\n3 0 2 6\n3 0 6 4\n3 1 5 7\n3 1 7 3\n'
    } >"$work/$1.off"
}
cube A 0
cube B 0.5
expect 5 "interpenetrating cubes stay refused" -- "$simplify" "$work/A.off" "$work/B.off" -o "$work/ab.bpm" --vertices 10 --repair-self-intersections
contains "$work/err" "was left as it is" "the repair says it left the input"
contains "$work/err" "--repair-self-intersections could not repair these" "the refusal does not suggest the flag again"
finish
