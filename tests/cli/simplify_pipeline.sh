#!/usr/bin/env bash
# bpm-simplify end to end: pipes through standard input/output, exit codes, no partial
# output on failure, byte-identical output for identical runs.
# Usage: simplify_pipeline.sh TOOL_DIR SOURCE_DIR WORK_DIR
set -u
tools=$1
src=$2
work=$3
rm -rf "$work"
mkdir -p "$work"
source "$(dirname "$0")/lib/harness.bash"
simplify=$tools/bpm-simplify
check=$tools/bpm-check
femur=$src/.data/meshes/femur.off


if [ ! -f "$femur" ]; then
    echo "missing $femur (run scripts/setup.sh)"
    exit 1
fi

# A pipe: surface on stdin, .bpm on stdout, checked from stdin.
"$simplify" - --format off -o - --ratio 0.2 -q <"$femur" >"$work/pipe.bpm" 2>"$work/err"
ok "simplify from stdin to stdout exits 0" -- test $? -eq 0
expect 0 "pipe output passes bpm-check" -- "$check" - <"$work/pipe.bpm"
"$simplify" - --format off -o - --ratio 0.2 -q <"$femur" | "$check" - >"$work/out" 2>&1
ok "simplify | check in one pipe" -- test $? -eq 0

# Files, and determinism.
expect 0 "simplify to a file" -- "$simplify" "$femur" -o "$work/a.bpm" --vertices 500 --deterministic -q
expect 0 "same run again" -- "$simplify" "$femur" -o "$work/b.bpm" --vertices 500 --deterministic -q
ok "identical runs give identical bytes except the file name in provenance" -- \
    test "$(cmp -l "$work/a.bpm" "$work/b.bpm" | wc -l)" -le 2
expect 0 "file passes bpm-check" -- "$check" "$work/a.bpm"

# Several inputs (one surface per material, as segmentation tools export them): one
# coarse surface, the files' patches apart; the same file twice shares every position.
/usr/bin/python3 - "$femur" "$work/femur_moved.off" <<'PY'
import sys
t = open(sys.argv[1]).read().split()
nv, nf = int(t[1]), int(t[2]); i = 4
with open(sys.argv[2], "w") as f:
    f.write("OFF\n%d %d 0\n" % (nv, nf))
    for k in range(nv): f.write("%r %s %s\n" % (float(t[i + 3 * k]) + 3.0, t[i + 3 * k + 1], t[i + 3 * k + 2]))
    i += 3 * nv
    for k in range(nf):
        n = int(t[i]); f.write(" ".join(t[i:i + n + 1]) + "\n"); i += n + 1
PY
expect 0 "two inputs simplified together" -- "$simplify" "$femur" "$work/femur_moved.off" -o "$work/two.bpm" --ratio 0.1
contains "$work/err" "femur_moved.off patch 0" "the second file's patch is named"
expect 0 "the pair passes bpm-check" -- "$check" "$work/two.bpm"
contains "$work/out" "2 components" "two components"
expect 3 "the same file twice: duplicate positions across the inputs" -- "$simplify" "$femur" "$femur" -o "$work/dup.bpm" --ratio 0.1
contains "$work/err" "the inputs together" "says it is the combination"
expect 2 "standard input is not one of several inputs" -- "$simplify" - "$femur" -o "$work/x.bpm" --ratio 0.1

# Usage errors (2) before any work, input errors (3), nothing left behind.
expect 2 "no stopping rule" -- "$simplify" "$femur" -o "$work/x.bpm"
expect 2 "ratio out of range" -- "$simplify" "$femur" -o "$work/x.bpm" --ratio 1.5
expect 2 "negative vertex count" -- "$simplify" "$femur" -o "$work/x.bpm" --vertices -5
expect 2 "output directory missing" -- "$simplify" "$femur" -o "$work/missing/x.bpm" --ratio 0.5
expect 2 "unknown format" -- "$simplify" - --format xyz -o "$work/x.bpm" --ratio 0.5
expect 3 "missing input" -- "$simplify" "$work/nope.off" -o "$work/x.bpm" --ratio 0.5
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\nnan 1 0\n3 0 1 2\n' >"$work/nan.off"
expect 3 "NaN coordinate" -- "$simplify" "$work/nan.off" -o "$work/x.bpm" --ratio 0.5
ok "the NaN message names the vertex" -- grep -q "vertex 2" "$work/err"
expect 3 "directory as input" -- "$simplify" "$work" --format off -o "$work/x.bpm" --ratio 0.5
ok "no output file after failures" -- test ! -e "$work/x.bpm"
ok "no temporary files left" -- test -z "$(ls -A "$work" | grep '\.tmp')"
crossed=$src/.data/meshes/tetra_intersected_by_triangle.off
if [ -f "$crossed" ]; then
    expect 5 "self-intersecting input is refused" -- "$simplify" "$crossed" -o "$work/x.bpm" --ratio 0.5
    ok "the refusal names the intersecting triangles" -- grep -q "intersects itself" "$work/err"
    expect 0 "... unless allowed" -- "$simplify" "$crossed" -o "$work/y.bpm" --ratio 0.9 --allow-self-intersecting-input
fi
# Polygon faces: refused with the repair named, read with it (a cube of 6 quads).
printf 'OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n' >"$work/quads.off"
expect 3 "quads are refused by default" -- "$simplify" "$work/quads.off" -o "$work/q.bpm" --vertices 8
ok "the refusal names the repair" -- grep -q "triangulate-polygons repair" "$work/err"
expect 0 "quads with --triangulate-polygons" -- "$simplify" "$work/quads.off" -o "$work/q.bpm" --vertices 8 --triangulate-polygons
ok "the repair is reported" -- grep -q "triangulated 6 polygon faces (up to 4 corners)" "$work/err"
expect 0 "the triangulated cube passes bpm-check" -- "$check" "$work/q.bpm"
expect 0 "bpm-check --surface --triangulate-polygons" -- "$check" --surface --triangulate-polygons "$work/quads.off"
expect 0 "--help" -- "$simplify" --help
expect 0 "--version" -- "$simplify" --version
ok "--version names the format version" -- grep -q "bpm format 1" "$work/out"

finish
