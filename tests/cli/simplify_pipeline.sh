#!/usr/bin/env bash
# bpm-simplify end to end: pipes through standard input/output, exit codes, no partial
# output on failure, byte-identical output for identical runs.
# Usage: simplify_pipeline.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
simplify=$tools/bpm-simplify
check=$tools/bpm-check
femur=$src/.data/meshes/femur.off


if [ ! -f "$femur" ]; then
    echo "missing $femur (run scripts/setup.sh)"
    exit 1
fi

# A pipe: surface on stdin, .bpm on stdout, checked from stdin.
"$simplify" - --input-format off -o - --ratio 0.2 -q <"$femur" >"$work/pipe.bpm" 2>"$work/err"
ok "simplify from stdin to stdout exits 0" -- test $? -eq 0
expect 0 "pipe output passes bpm-check" -- "$check" - <"$work/pipe.bpm"
"$simplify" - --input-format off -o - --ratio 0.2 -q <"$femur" | "$check" - >"$work/out" 2>&1
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
# One closed surface per material with a shared interface (two unit cubes touching at
# x = 1): the interface is in both files. Refused as duplicate triangles with the repair
# named; with it the interface becomes a sheet between the two materials.
/usr/bin/python3 - "$work/cube_a.off" "$work/cube_b.off" <<'PY'
import sys
def cube(x0, res, path):
    index, verts, faces = {}, [], []
    def v(p):
        if p not in index: index[p] = len(verts); verts.append(p)
        return index[p]
    for axis in range(3):
        o = [k for k in range(3) if k != axis]
        for side in (0, 1):
            for i in range(res):
                for j in range(res):
                    def pt(a, b):
                        c = [0, 0, 0]; c[axis] = side * res; c[o[0]] = a; c[o[1]] = b
                        return (x0 * res + c[0], c[1], c[2])
                    q = [v(pt(i, j)), v(pt(i + 1, j)), v(pt(i + 1, j + 1)), v(pt(i, j + 1))]
                    if (side == 0) != (axis == 1): q = [q[0], q[3], q[2], q[1]]  # outwards
                    faces += [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
    with open(path, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(verts), len(faces)))
        for p in verts: f.write("%r %r %r\n" % tuple(c / res for c in p))
        for t in faces: f.write("3 %d %d %d\n" % t)
cube(0, 4, sys.argv[1]); cube(1, 4, sys.argv[2])
PY
expect 3 "two touching materials without the repairs" -- "$simplify" "$work/cube_a.off" "$work/cube_b.off" -o "$work/ab.bpm" --ratio 0.3 --merge-duplicate-vertices
contains "$work/err" "Rerun with: --merge-duplicate-triangles" "the refusal names the flag of the repair"
expect 0 "two touching materials with --merge-duplicate-triangles" -- "$simplify" "$work/cube_a.off" "$work/cube_b.off" -o "$work/ab.bpm" --ratio 0.3 --merge-duplicate-vertices --merge-duplicate-triangles
contains "$work/err" "removed 32 duplicate triangles" "the fused triangles are reported"
contains "$work/err" "patch 2 = the 32 triangles that patches 0 and 1 had in common" "the interface patch is named"
expect 0 "the two materials pass bpm-check" -- "$check" "$work/ab.bpm"
contains "$work/out" "non-manifold" "the interface is a sheet"
contains "$work/out" "1 topological feature lines" "its rim is a (topological) feature line of three sheets"
# The same two materials as an Amira HyperSurface (BINARY): one vertex list, the patches
# Exterior|A, Exterior|B and A|B; no repairs needed, the interface is stored once.
/usr/bin/python3 - "$work/cube_a.off" "$work/cube_b.off" "$work/ab.surf" <<'PY'
import struct, sys
index, verts, tris = {}, [], []
for path in sys.argv[1:3]:
    t = open(path).read().split(); nv, nf = int(t[1]), int(t[2])
    p = [tuple(t[4 + 3 * k:7 + 3 * k]) for k in range(nv)]
    for p_ in p: index.setdefault(p_, len(index) + 1)
    o = 4 + 3 * nv
    tris.append([tuple(index[p[int(i)]] for i in t[o + 4 * k + 1:o + 4 * k + 4]) for k in range(nf)])
shared = set(map(frozenset, tris[0])) & set(map(frozenset, tris[1]))
patches = [("A", "Exterior", [x for x in tris[0] if frozenset(x) not in shared]),
           ("B", "Exterior", [x for x in tris[1] if frozenset(x) not in shared]),
           ("A", "B", [x for x in tris[0] if frozenset(x) in shared])]
out = b'# HyperSurface 0.1 BINARY\n\nParameters {\n    Materials { Exterior { Id 0 } A { Id 1 } B { Id 2 } }\n}\n'
out += b"Vertices %d\n" % len(index) + b"".join(struct.pack(">3f", *map(float, p)) for p in index) + b"\n"
out += b"NBranchingPoints 0\nNVerticesOnCurves 0\nBoundaryCurves 0\nPatches 3\n"
for inner, outer, ts in patches:
    out += b"{\nInnerRegion %s\nOuterRegion %s\nBoundaryID 0\nBranchingPoints 0\n\nTriangles %d\n" % (inner.encode(), outer.encode(), len(ts))
    out += b"".join(struct.pack(">3i", *x) for x in ts) + b"\n}\n"
open(sys.argv[3], "wb").write(out)
PY
expect 0 "two materials as one HyperSurface (.surf)" -- "$simplify" "$work/ab.surf" -o "$work/surf.bpm" --ratio 0.3
contains "$work/err" "patch 2 = InnerRegion A / OuterRegion B (32 triangles)" "the interface patch is named by its regions"
expect 0 "the HyperSurface materials pass bpm-check" -- "$check" "$work/surf.bpm"
contains "$work/out" "non-manifold" "the interface is a sheet"
# Both simplified inputs mesh into two regions named by their materials (spec/tetmesh.md 3.7).
if command -v tetgen >/dev/null; then
    expect 0 "mesh the two files' materials" -- "$tools/bpm-mesh" "$work/ab.bpm" -o "$work/ab.msh"
    # Which material gets number 1 follows TetGen's region order, not the files' order.
    ok "regions named after the files" -- grep -qE "2 materials: 1 cube_(a|b) \(region 1\); 2 cube_(a|b) \(region 2\)" "$work/err"
    ok "each file is one region" -- bash -c "grep -q 'cube_a (region' '$work/err' && grep -q 'cube_b (region' '$work/err'"
    expect 0 "mesh the HyperSurface materials" -- "$tools/bpm-mesh" "$work/surf.bpm" -o "$work/surf.msh"
    ok "regions named as in the HyperSurface" -- grep -qE "2 materials: 1 (A|B) \(region 1\); 2 (A|B) \(region 2\)" "$work/err"
    ok "each HyperSurface material is one region" -- bash -c "grep -q ' A (region' '$work/err' && grep -q ' B (region' '$work/err'"
fi

# Usage errors (2) before any work, input errors (3), nothing left behind.
expect 2 "no stopping rule" -- "$simplify" "$femur" -o "$work/x.bpm"
expect 2 "ratio out of range" -- "$simplify" "$femur" -o "$work/x.bpm" --ratio 1.5
expect 2 "negative vertex count" -- "$simplify" "$femur" -o "$work/x.bpm" --vertices -5
expect 2 "output directory missing" -- "$simplify" "$femur" -o "$work/missing/x.bpm" --ratio 0.5
expect 2 "unknown format" -- "$simplify" - --input-format xyz -o "$work/x.bpm" --ratio 0.5
expect 3 "missing input" -- "$simplify" "$work/nope.off" -o "$work/x.bpm" --ratio 0.5
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\nnan 1 0\n3 0 1 2\n' >"$work/nan.off"
expect 3 "NaN coordinate" -- "$simplify" "$work/nan.off" -o "$work/x.bpm" --ratio 0.5
ok "the NaN message names the vertex" -- grep -q "vertex 2" "$work/err"
expect 3 "directory as input" -- "$simplify" "$work" --input-format off -o "$work/x.bpm" --ratio 0.5
ok "no output file after failures" -- test ! -e "$work/x.bpm"
ok "no temporary files left" -- test -z "$(ls -A "$work" | grep '\.tmp')"
crossed=$src/.data/meshes/tetra_intersected_by_triangle.off
if [ -f "$crossed" ]; then
    expect 5 "self-intersecting input is refused" -- "$simplify" "$crossed" -o "$work/x.bpm" --ratio 0.5
    ok "the refusal names the intersecting triangles" -- grep -q "intersects itself" "$work/err"
    ok "the refusal names the flag that allows it" -- grep -q "use --allow-self-intersecting-input" "$work/err"
    expect 0 "... unless allowed" -- "$simplify" "$crossed" -o "$work/y.bpm" --ratio 0.9 --allow-self-intersecting-input
fi
# Polygon faces: refused with the repair named, read with it (a cube of 6 quads).
printf 'OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n' >"$work/quads.off"
expect 3 "quads are refused by default" -- "$simplify" "$work/quads.off" -o "$work/q.bpm" --vertices 8
ok "the refusal names the repair and its flag" -- grep -q "the repair it needs: triangulate polygons. Rerun with: --triangulate-polygons" "$work/err"
expect 0 "quads with --triangulate-polygons" -- "$simplify" "$work/quads.off" -o "$work/q.bpm" --vertices 8 --triangulate-polygons
ok "the repair is reported" -- grep -q "triangulated 6 polygon faces (up to 4 corners)" "$work/err"
expect 0 "the triangulated cube passes bpm-check" -- "$check" "$work/q.bpm"
expect 0 "bpm-check --surface --triangulate-polygons" -- "$check" --surface --triangulate-polygons "$work/quads.off"
expect 0 "--help" -- "$simplify" --help
expect 0 "--version" -- "$simplify" --version
ok "--version names the format version" -- grep -q "bpm format 2" "$work/out"

finish
