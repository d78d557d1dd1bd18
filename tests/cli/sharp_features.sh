#!/usr/bin/env bash
# Sharp features: corners of creases are kept (bpm-simplify --no-keep-corners lets them
# go), targets below them stop there and say why, crease lines stay lines.
# Usage: sharp_features.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
simplify=$tools/bpm-simplify
check=$tools/bpm-check
refine=$tools/bpm-refine
shapes="/usr/bin/python3 $(dirname "$0")/lib/sharp_shapes.py"
for s in cube10 cube-quads lblock cylinder; do $shapes $s "$work/$s.off"; done

# Coarse vertices of an OFF file that are not on the given corner coordinates.
off_corners() {  # FILE: number of vertices with a coordinate other than 0, 1 (2 for the L-block)
    /usr/bin/python3 - "$1" <<'PY'
import sys
t = open(sys.argv[1]).read().split()
nv = int(t[1])
xyz = [tuple(float(c) for c in t[4 + 3 * i:7 + 3 * i]) for i in range(nv)]
print(sum(1 for p in xyz if any(c not in (0.0, 1.0, 2.0) for c in p)))
PY
}

# The cube of 10 x 10 squares per face at 8 vertices is the cube: error 0, 8 corners.
expect 0 "cube to 8 vertices" -- "$simplify" "$work/cube10.off" -o "$work/c8.bpm" --vertices 8
contains "$work/err" "-> 8 vertices (12 triangles)" "cube reaches 8 vertices"
expect 0 "cube at 8 vertices is the cube (Hausdorff 0)" -- "$check" "$work/c8.bpm" --max-distance 1e-9
expect 0 "cube corners written" -- "$refine" "$work/c8.bpm" --levels 0 -o "$work/c8.off"
ok "the 8 vertices are the corners" -- test "$(off_corners "$work/c8.off")" -eq 0

# Below the corners: stops at 8 and says why.
expect 0 "cube to 4 vertices" -- "$simplify" "$work/cube10.off" -o "$work/c4.bpm" --vertices 4
contains "$work/err" "-> 8 vertices" "cube to 4 stops at 8"
contains "$work/err" "the target of 4 vertices is below the 8 feature vertices" "says why it stopped"
contains "$work/err" "--no-keep-corners" "names the option"
expect 0 "without corners" -- "$simplify" "$work/cube10.off" -o "$work/c4n.bpm" --vertices 4 --no-keep-corners
contains "$work/err" "-> 4 vertices" "--no-keep-corners reaches 4"
expect 0 "without corners still valid" -- "$check" "$work/c4n.bpm"

# A cube of 6 quads stays a cube (it became a tetrahedron).
expect 0 "cube of quads" -- "$simplify" "$work/cube-quads.off" --triangulate-polygons --ratio 0.5 -o "$work/cq.bpm"
contains "$work/err" "8 -> 8 vertices" "cube of quads keeps its 8 corners"
expect 0 "cube of quads is the cube" -- "$check" "$work/cq.bpm" --max-distance 1e-9

# The L-block: 12 corners, reached exactly.
expect 0 "L-block to 12" -- "$simplify" "$work/lblock.off" -o "$work/l.bpm" --vertices 12
contains "$work/err" "-> 12 vertices" "L-block reaches its 12 corners"
expect 0 "L-block at 12 vertices is the L-block" -- "$check" "$work/l.bpm" --max-distance 1e-9

# The cylinder: no corners; the circular creases stay lines while the error allows, so
# every coarse triangle lies in a cap or on the side (none cuts across the rim).
expect 0 "cylinder to 100" -- "$simplify" "$work/cylinder.off" -o "$work/cy.bpm" --vertices 100
contains "$work/err" "-> 100 vertices" "cylinder reaches 100"
expect 0 "cylinder checks" -- "$check" "$work/cy.bpm" --max-distance 0.02
expect 0 "cylinder written" -- "$refine" "$work/cy.bpm" --levels 0 -o "$work/cy.off"
ok "no coarse triangle of the cylinder cuts across a rim" -- /usr/bin/python3 - "$work/cy.off" <<'PY'
import math, sys
t = open(sys.argv[1]).read().split()
nv, nf = int(t[1]), int(t[2])
v = [tuple(float(c) for c in t[4 + 3 * i:7 + 3 * i]) for i in range(nv)]
f = [tuple(int(c) for c in t[4 + 3 * nv + 4 * i + 1:4 + 3 * nv + 4 * i + 4]) for i in range(nf)]
def side(p): return abs(math.hypot(p[0], p[1]) - 1) < 1e-9
bad = [x for x in f if not (all(v[i][2] == 0 for i in x) or all(v[i][2] == 2 for i in x) or all(side(v[i]) for i in x))]
sys.exit(1 if bad else 0)
PY
finish
