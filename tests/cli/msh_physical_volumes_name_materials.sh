#!/usr/bin/env bash
# Gmsh's physical volumes name the materials (defect of a new-user audit): a sphere in a
# box from gmsh -2 with Physical Volume("shell") and ("core") was meshed by bpm-mesh into
# regions named region_1 and region_2; the volumes were read and ignored. Now MSH 4.1's
# $Entities (which surfaces bound which volume) give the physical surfaces their two
# materials; MSH 2.2, which does not have that, says that they are ignored and what to do.
# Usage: msh_physical_volumes_name_materials.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
if ! command -v gmsh >/dev/null || ! command -v tetgen >/dev/null; then
    echo "skipped: needs gmsh and tetgen"
    finish
    exit
fi
cat >"$work/box.geo" <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 4, 4, 4};
Sphere(2) = {2, 2, 2, 1};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Physical Volume("core") = {2};
Physical Volume("shell") = {3};
Physical Surface("interface") = Boundary{ Volume{2}; };
Physical Surface("outside") = {8, 9, 10, 11, 12, 13};
Mesh.MeshSizeMax = 1.0;
GEO
for v in 41 22; do
    gmsh -2 "$work/box.geo" -o "$work/box$v.msh" -format msh$v >/dev/null 2>&1 ||
        { echo "skipped: gmsh could not mesh the box"; finish; exit; }
done
expect 0 "simplify the MSH 4.1 file" -- "$tools/bpm-simplify" "$work/box41.msh" -o "$work/box41.bpm" --ratio 0.5 -v
contains "$work/err" "'interface': between core and shell (sides not known)" "the interface lies between the two volumes"
contains "$work/err" "'outside': between exterior and shell (sides not known)" "the box's faces bound the shell only"
expect 0 "mesh it" -- "$tools/bpm-mesh" "$work/box41.bpm" -o "$work/box41.msh.vtu"
contains "$work/err" "2 materials: 1 shell (region 1); 2 core (region 2)" "the regions are named after the volumes"

expect 0 "simplify the MSH 2.2 file" -- "$tools/bpm-simplify" "$work/box22.msh" -o "$work/box22.bpm" --ratio 0.5
contains "$work/err" "physical volumes 'core', 'shell' ignored: MSH 2.2 does not say which surfaces bound a volume (write MSH 4.1" \
    "MSH 2.2: the physical volumes are said to be ignored, and what to do"
finish
