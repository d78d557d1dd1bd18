#!/usr/bin/env bash
# Pipeline: bpm-simplify -> bpm-smooth -> bpm-refine -> bpm-check on femur, plus the
# usage / input errors of bpm-refine and bpm-smooth.
# Usage: refine_smooth.sh TOOL_DIR SOURCE_DIR WORK_DIR
set -u
tools=$1
src=$2
work=$3
mkdir -p "$work"
source "$(dirname "$0")/lib/harness.bash"
meshes=$src/.data/meshes
example=$src/spec/examples/two_triangles.bpm


refine=$tools/bpm-refine
smooth=$tools/bpm-smooth
check=$tools/bpm-check

# Usage and input errors.
expect 0 "refine help" -- "$refine" --help
expect 0 "smooth help" -- "$smooth" --help
expect 2 "refine needs levels or tolerance" -- "$refine" "$example" -o "$work/x.off"
expect 2 "levels and tolerance exclude each other" -- "$refine" "$example" -o "$work/x.off" --levels 1 --tolerance 0.01
expect 2 "unknown output format" -- "$refine" "$example" -o "$work/x.xyz" --levels 1
expect 2 "stdout needs --format" -- "$refine" "$example" -o - --levels 1
expect 2 "missing output directory" -- "$refine" "$example" -o "$work/no/such/dir/x.off" --levels 1
expect 3 "missing input" -- "$refine" "$work/does-not-exist.bpm" -o "$work/x.off" --levels 1
expect 3 "smooth missing input" -- "$smooth" "$work/does-not-exist.bpm" -o "$work/x.bpm"

# The spec example: every output format, K = 0 reproduces the coarse surface.
expect 0 "example K=0" -- "$refine" "$example" -o "$work/ex0.off" --levels 0
contains "$work/ex0.off" "4 2 0" "K=0 keeps 4 vertices and 2 triangles"
for ext in off obj ply stl vtu bpm; do
    expect 0 "example to .$ext" -- "$refine" "$example" -o "$work/ex.$ext" --levels 2
done
expect 0 "example refined .bpm passes bpm-check" -- "$check" "$work/ex.bpm"
expect 0 "stdout" -- bash -c "'$refine' '$example' -o - --format off --levels 1 > '$work/stdout.off'"
contains "$work/stdout.off" "OFF" "OFF on stdout"
expect 0 "stdin" -- bash -c "cat '$example' | '$refine' - -o '$work/stdin.off' --levels 1"

# femur: simplify -> smooth -> refine -> check.
if [ -f "$meshes/femur.off" ]; then
    expect 0 "simplify femur" -- "$tools/bpm-simplify" "$meshes/femur.off" -o "$work/femur.bpm" --ratio 0.1
    expect 0 "smooth femur" -- "$smooth" "$work/femur.bpm" -o "$work/femur_smooth.bpm" --iterations 5 -v
    contains "$work/err" "aspect ratio of the 3-times refined surface" "smooth reports quality"
    cat "$work/err" | sed 's/^/  /'
    expect 0 "smoothed femur passes bpm-check" -- "$check" "$work/femur_smooth.bpm"
    expect 0 "refine femur K=2 to .bpm" -- "$refine" "$work/femur_smooth.bpm" -o "$work/femur_k2.bpm" --levels 2 -v
    # The refined surface of a distorted phi may touch itself (thin triangles); format,
    # topology and bijectivity of the refined phi must hold regardless.
    expect 0 "refined femur .bpm is a valid parametrization" -- "$check" --checks format,topology,bijectivity "$work/femur_k2.bpm"
    "$check" --checks intersections "$work/femur_k2.bpm" | sed 's/^/  (information) /'
    expect 0 "refine femur adaptive to .vtu with data" -- "$refine" "$work/femur_smooth.bpm" -o "$work/femur_adaptive.vtu" --tolerance 0.002 --data
    contains "$work/femur_adaptive.vtu" "Name=\"original_normal\"" "normals in VTU"
    expect 0 "refine femur K=1 to .off" -- "$refine" "$work/femur_smooth.bpm" -o "$work/femur_k1.off" --levels 1
    expect 0 "refined surface reads back" -- "$check" --surface --checks topology "$work/femur_k1.off"
else
    echo "skipping femur: $meshes/femur.off missing"
fi

finish
