#!/usr/bin/env bash
# A closed surface whose export left a seam open by rounding (the two sides' vertices
# 1e-9 of the diagonal apart, as CAD exports and format conversions write them): before,
# bpm-simplify accepted it without a word, --merge-duplicate-vertices (exact positions)
# did not close it, and only bpm-mesh failed later ("the coarse surface has N boundary
# edges ... e.g. an open seam"), with no way to fix it in bpm. Now the reader warns and
# names the repair, --merge-vertices-within TOL (a fraction of the bounding-box diagonal)
# closes the seam deterministically in bpm-simplify and bpm-check --surface, bpm-mesh's
# error names it, and a tolerance that would collapse triangles is refused.
# Usage: open_seam_merged_within_tolerance.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"

# The unit cube, each face a 4 x 4 grid of squares split in two, as STL and OBJ, with the
# triangles whose centroid has x > 0.5 moved by 1e-9 of the diagonal: the seam is the
# ring of vertices at x = 0.5, written once per side. Also the closed cube (OBJ).
/usr/bin/python3 - "$work" "$(dirname "$0")/lib" <<'PY'
import sys, math
sys.path.insert(0, sys.argv[2])
from grid_cube import cube_triangles
work = sys.argv[1]
n = 4
tris = cube_triangles(n)
delta = 1e-9 * math.sqrt(3)
def moved(t):
    if sum(v[0] for v in t) / 3 <= 0.5: return t
    return tuple((v[0] + 0.6 * delta, v[1], v[2] + 0.8 * delta) for v in t)
seam = [moved(t) for t in tris]
with open(work + "/seam.stl", "w") as f:
    f.write("solid seam\n")
    for t in seam:
        f.write("facet normal 0 0 0\nouter loop\n")
        for v in t: f.write("vertex %.17g %.17g %.17g\n" % v)
        f.write("endloop\nendfacet\n")
    f.write("endsolid seam\n")
def obj(path, triangles):
    index = {}
    with open(path, "w") as f:
        for t in triangles:
            for v in t:
                if v not in index:
                    index[v] = len(index) + 1
                    f.write("v %.17g %.17g %.17g\n" % v)
        for t in triangles: f.write("f %d %d %d\n" % tuple(index[v] for v in t))
obj(work + "/seam.obj", seam)
obj(work + "/closed.obj", tris)
PY
ok "the fixtures are written" -- test -s "$work/seam.stl" -a -s "$work/seam.obj" -a -s "$work/closed.obj"

# Without the repair: accepted (open surfaces are), with a warning that names it.
expect 0 "an open seam is accepted" -- "$tools/bpm-simplify" "$work/seam.stl" -o "$work/open.bpm" --ratio 0.5
contains "$work/err" "warning: the surface is open, and its 32 boundary edges pair up with other boundary edges within 1e-09 of the bounding-box diagonal" \
    "the warning says the boundary is a seam open by 1e-9"
contains "$work/err" "--merge-vertices-within 1e-08 closes it" "the warning names the repair and its tolerance"
expect 0 "bpm-check --surface: accepted" -- "$tools/bpm-check" --surface "$work/seam.obj"
contains "$work/err" "--merge-vertices-within 1e-08 closes it" "bpm-check --surface names it too"
contains "$work/out" "2 boundary loops" "the seam is two boundary loops"
expect 5 "bpm-mesh refuses the open coarse surface" -- "$tools/bpm-mesh" "$work/open.bpm" -o "$work/open.tet.bpm"
contains "$work/err" "Rerun bpm-simplify on the input with --merge-vertices-within 1e-08" "bpm-mesh's error names the repair"
expect 0 "exact merging cannot close it" -- "$tools/bpm-simplify" "$work/seam.obj" -o "$work/exact.bpm" --ratio 0.5 \
    --merge-duplicate-vertices
contains "$work/err" "--merge-vertices-within 1e-08 closes it" "the warning stays after exact merging"

# With the repair: closed, meshable, and the same file from STL and OBJ.
for f in stl obj; do
    expect 0 "$f: --merge-vertices-within 1e-8" -- "$tools/bpm-simplify" "$work/seam.$f" -o "$work/merged-$f.bpm" \
        --ratio 0.5 --merge-vertices-within 1e-8 --deterministic
    contains "$work/err" "merged 16 vertices within 1e-08 of the bounding-box diagonal (the largest move: 1e-09 of the diagonal)" \
        "$f: the log says what was merged and how far it moved"
    ok "$f: no seam warning after the merge" -- bash -c "! grep -q 'open seam' '$work/err'"
    expect 0 "$f: bpm-check passes" -- "$tools/bpm-check" "$work/merged-$f.bpm"
    contains "$work/out" "0 boundary loops" "$f: the surface is closed"
done
expect 0 "the merged cube meshes" -- "$tools/bpm-mesh" "$work/merged-obj.bpm" -o "$work/merged.tet.bpm"
# Deterministic: the same command gives the same file.
mv "$work/merged-obj.bpm" "$work/merged-first.bpm"
expect 0 "again" -- "$tools/bpm-simplify" "$work/seam.obj" -o "$work/merged-obj.bpm" --ratio 0.5 \
    --merge-vertices-within 1e-8 --deterministic
ok "the same file twice" -- cmp -s "$work/merged-obj.bpm" "$work/merged-first.bpm"
expect 0 "bpm-check --surface with the repair" -- "$tools/bpm-check" --surface "$work/seam.stl" --merge-vertices-within 1e-8
contains "$work/out" "0 boundary loops" "bpm-check --surface: closed"
expect 0 "a closed input: nothing to merge, no warning" -- "$tools/bpm-simplify" "$work/closed.obj" -o "$work/closed.bpm" \
    --ratio 0.5 --merge-vertices-within 1e-8
ok "no merge note, no warning" -- bash -c "! grep -qE 'merged|open seam' '$work/err'"

# A tolerance as large as the triangles is refused, not applied.
expect 3 "a tolerance that collapses triangles" -- "$tools/bpm-simplify" "$work/seam.obj" -o "$work/big.bpm" --ratio 0.5 \
    --merge-vertices-within 0.2
contains "$work/err" "merging vertices within 0.2 of the bounding-box diagonal would join vertices" "the error says why"
ok "nothing written" -- test ! -e "$work/big.bpm"
expect 2 "a negative tolerance is a usage error" -- "$tools/bpm-simplify" "$work/seam.obj" -o "$work/neg.bpm" --ratio 0.5 \
    --merge-vertices-within -1
expect 0 "--help documents it" -- "$tools/bpm-simplify" --help
contains "$work/out" "--merge-vertices-within" "bpm-simplify --help"
expect 0 "--help documents it" -- "$tools/bpm-check" --help
contains "$work/out" "--merge-vertices-within" "bpm-check --help"
finish
