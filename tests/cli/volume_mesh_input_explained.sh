#!/usr/bin/env bash
# A volume mesh given as the surface (gmsh -3 output, a VTK unstructured grid of
# tetrahedra with its boundary triangles): bpm reads the triangles and skips the
# tetrahedra, so the vertices inside the volume are used by no triangle. The error said
# only "vertex 4: not used by any triangle", which reads like a broken file; it now says
# that non-triangle elements were skipped (a volume mesh?), and still names the flag.
# Usage: volume_mesh_input_explained.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"

# A tetrahedron split at its centre (node 5) into 4 tetrahedra, with its 4 boundary
# triangles (physical surface 1) and the tetrahedra (physical volume 2): MSH 2.2 ASCII,
# as gmsh -3 -format msh22 writes it.
cat >"$work/tets.msh" <<'MSH'
$MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
5
1 0 0 0
2 1 0 0
3 0 1 0
4 0 0 1
5 0.25 0.25 0.25
$EndNodes
$Elements
8
1 2 2 1 1 1 3 2
2 2 2 1 1 1 2 4
3 2 2 1 1 1 4 3
4 2 2 1 1 2 3 4
5 4 2 2 1 1 2 3 5
6 4 2 2 1 1 2 4 5
7 4 2 2 1 1 3 4 5
8 4 2 2 1 2 3 4 5
$EndElements
MSH
# The same as a legacy VTK unstructured grid: 4 triangles (type 5), 4 tetrahedra (type 10).
cat >"$work/tets.vtk" <<'VTK'
# vtk DataFile Version 3.0
tets
ASCII
DATASET UNSTRUCTURED_GRID
POINTS 5 double
0 0 0
1 0 0
0 1 0
0 0 1
0.25 0.25 0.25
CELLS 8 36
3 0 2 1
3 0 1 3
3 0 3 2
3 1 2 3
4 0 1 2 4
4 0 1 3 4
4 0 2 3 4
4 1 2 3 4
CELL_TYPES 8
5
5
5
5
10
10
10
10
VTK

for f in tets.msh tets.vtk; do
    expect 3 "$f: a volume mesh without the repair" -- "$tools/bpm-simplify" "$work/$f" -o "$work/t.bpm" --vertices 4
    contains "$work/err" "$f: 4 elements that are not triangles skipped (the cells of a volume mesh?)" \
        "$f: the error says why vertices are unused"
    contains "$work/err" "vertex 4: not used by any triangle" "$f: the vertex is still named"
    contains "$work/err" "Rerun with: --drop-unreferenced-vertices" "$f: the flag is still named"
    expect 0 "$f: the flag as printed works" -- "$tools/bpm-simplify" "$work/$f" -o "$work/t.bpm" --vertices 4 \
        --drop-unreferenced-vertices
done
# An unused vertex in a file without skipped elements gets no such guess.
printf 'OFF\n5 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n5 5 5\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$work/extra.off"
expect 3 "an OFF with an unused vertex" -- "$tools/bpm-simplify" "$work/extra.off" -o "$work/t.bpm" --vertices 4
ok "no volume-mesh guess without skipped elements" -- bash -c "! grep -q 'volume mesh' '$work/err'"
finish
