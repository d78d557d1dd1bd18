#!/usr/bin/env bash
# Options a newcomer gives that cannot do what they say (defects of a new-user audit):
# bpm-check --max-aspect below 2 failed every triangle, since circumradius/inradius is 2
# for an equilateral triangle and more for every other (exit 1, "aspect ratio 2.08
# exceeds 1.5"); bpm-refine --levels with --max-level ran and ignored --max-level. Both
# are now usage errors (exit 2) that say why and what is expected.
# Usage: limits_that_cannot_apply_refused.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
py=/usr/bin/python3
$py - "$work" "$src/tests/cli/lib" <<'PY'
import sys
sys.path.insert(0, sys.argv[2])
from grid_cube import cube_triangles
tris = cube_triangles(4)
index = {}
for t in tris:
    for v in t: index.setdefault(v, len(index))
lines = ["OFF", "%d %d 0" % (len(index), len(tris))]
lines += ["%r %r %r" % v for v in index]
lines += ["3 %d %d %d" % tuple(index[v] for v in t) for t in tris]
open(sys.argv[1] + "/cube.off", "w").write("\n".join(lines) + "\n")
PY
expect 0 "simplify the cube" -- "$tools/bpm-simplify" "$work/cube.off" -o "$work/cube.bpm" --ratio 0.5 -q

for a in 1.5 1 0; do
    expect 2 "bpm-check --max-aspect $a: a usage error" -- "$tools/bpm-check" "$work/cube.bpm" --max-aspect "$a"
    contains "$work/err" "--max-aspect: expects a circumradius/inradius ratio of at least 2 (an equilateral triangle has 2" \
        "bpm-check --max-aspect $a: says the smallest possible value and why"
    contains "$work/err" "got '$a'" "bpm-check --max-aspect $a: names the value given"
done
expect 1 "bpm-check --max-aspect 2 is accepted (and fails the cube's right triangles)" -- \
    "$tools/bpm-check" "$work/cube.bpm" --max-aspect 2 --checks format
contains "$work/out" "exceeds 2" "bpm-check --max-aspect 2: the quality check ran"
expect 0 "bpm-check --max-aspect 30 passes" -- "$tools/bpm-check" "$work/cube.bpm" --max-aspect 30 --checks format
expect 2 "bpm-simplify --max-aspect 1.5: the same message" -- \
    "$tools/bpm-simplify" "$work/cube.off" -o "$work/x.bpm" --ratio 0.5 --max-aspect 1.5
contains "$work/err" "--max-aspect: expects a circumradius/inradius ratio of at least 2" "bpm-simplify says why"

expect 2 "bpm-refine --levels with --max-level: a usage error" -- \
    "$tools/bpm-refine" "$work/cube.bpm" --levels 1 --max-level 3 -o "$work/r.off"
contains "$work/err" "--levels excludes --max-level" "bpm-refine names both options"
ok "bpm-refine wrote nothing" -- test ! -e "$work/r.off"
expect 0 "bpm-refine --max-error with --max-level still runs" -- \
    "$tools/bpm-refine" "$work/cube.bpm" --max-error 0.01 --max-level 1 -o "$work/r.off" -q
finish
