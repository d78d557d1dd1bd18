#!/usr/bin/env bash
# Refined .bpm files pass bpm-check: new vertices whose phi would make the refined surface
# intersect itself are held back (towards their parent edges); multi-material surfaces
# refine. Usage: refine_valid.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
simplify=$tools/bpm-simplify
smooth=$tools/bpm-smooth
refine=$tools/bpm-refine
check=$tools/bpm-check
femur=$src/.data/meshes/femur.off
if [ ! -f "$femur" ]; then
    echo "missing $femur (run scripts/setup.sh)"
    exit 1
fi

# Femur 10 %, smoothed, refined once and twice (bpm-check found 9 intersecting pairs at K = 1).
# --max-aspect 100 keeps the input's needle (R/r 92.8, an edge 1e-4 long) that bpm-simplify
# now removes first at the default 30: refined through phi, it makes the surface intersect
# itself, which is what the remedy is tested on.
expect 0 "simplify femur" -- "$simplify" "$femur" -o "$work/f.bpm" --ratio 0.1 --max-aspect 100 -q
expect 0 "smooth femur" -- "$smooth" "$work/f.bpm" -o "$work/fs.bpm" -q
for k in 1 2; do
    expect 0 "refine femur K=$k to .bpm" -- "$refine" "$work/fs.bpm" --levels $k -o "$work/r$k.bpm"
    contains "$work/err" "vertices held back from phi" "K=$k says how many vertices were held back"
    contains "$work/err" "passed the format, intersections, topology and bijectivity checks" "K=$k verified by all four checks"
    expect 0 "refined femur K=$k passes bpm-check" -- "$check" "$work/r$k.bpm"
done
# Without the remedy the refined surface intersects itself (what the remedy is for).
expect 0 "refine femur K=1 --allow-intersections" -- "$refine" "$work/fs.bpm" --levels 1 -o "$work/ra.bpm" --allow-intersections
expect 1 "... and bpm-check finds the intersections" -- "$check" "$work/ra.bpm" --checks intersections
# Surface output: the same positions.
expect 0 "refine femur K=1 to OFF" -- "$refine" "$work/fs.bpm" --levels 1 -o "$work/r1.off"
expect 0 "refined OFF does not intersect itself" -- "$check" --surface "$work/r1.off" --checks intersections

# Two materials (two cubes sharing a face) at 5 %: exited 5 with a bijectivity failure.
/usr/bin/python3 "$src/bench/make_two_cubes.py" "$work/tc.obj" 16
expect 0 "simplify two cubes" -- "$simplify" "$work/tc.obj" -o "$work/tc.bpm" --ratio 0.05 -q
for k in 1 2; do
    expect 0 "refine two cubes K=$k" -- "$refine" "$work/tc.bpm" --levels $k -o "$work/tc$k.bpm" -q
    expect 0 "refined two cubes K=$k passes bpm-check" -- "$check" "$work/tc$k.bpm"
done
finish
