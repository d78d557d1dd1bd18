#!/usr/bin/env bash
# Materials from the input to the volume mesh: two touching cubes as one OFF file per
# material (fused interface), an Amira HyperSurface with InnerRegion/OuterRegion, a Gmsh
# MSH round trip through $PhysicalNames, --material, and files without patch information.
# Usage: materials.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
if ! command -v tetgen >/dev/null; then
    echo "skipped: needs tetgen (scripts/setup.sh installs it)"
    exit 1
fi
py=/usr/bin/python3

# left.off = [0,1]^3 and right.off = [1,2]x[0,1]^2, sharing the square x = 1.
$py "$(dirname "$0")/lib/two_cubes.py" "$work"

expect 0 "simplify one file per material, interfaces fused" -- "$tools/bpm-simplify" "$work/left.off" "$work/right.off" \
    --merge-duplicate-vertices --merge-duplicate-triangles --ratio 1 -o "$work/cubes.bpm" -v
contains "$work/err" "patch 2 'left|right': front right, back left" "the fused interface separates the two files' materials"
expect 0 "mesh, JSON" -- "$tools/bpm-mesh" "$work/cubes.bpm" -o "$work/cubes.tet.bpm" --json
contains "$work/err" "2 materials: 1 left (region 1); 2 right (region 2)" "the log names the materials and their regions"
ok "two regions, materials named after the files, no problem" -- $py -c '
import json, sys
j = json.load(open(sys.argv[1]))
names = sorted(r["material_name"] for r in j["regions"])
assert len(j["regions"]) == 2 and names == ["left", "right"], j["regions"]
assert [m["name"] for m in j["materials"]] == ["left", "right"] and j["material_problems"] == 0, j
' "$work/out"
ok "the .bpm holds /patch_info and the region materials (since format 1.3)" -- $py -c '
import h5py, sys
f = h5py.File(sys.argv[1], "r")
assert list(f.attrs["format_version"]) == [2, 1]
pi = f["patch_info"]
assert [n.decode() for n in pi["name"][()]] == ["left|exterior", "right|exterior", "left|right"], pi["name"][()]
assert [n.decode() for n in pi["front_material"][()]] == ["exterior", "exterior", "right"]
assert [n.decode() for n in pi["back_material"][()]] == ["left", "right", "left"]
assert list(pi["oriented"][()]) == [1, 1, 1]
tm = f["tetmesh"]
names = [n.decode() for n in tm["material_names"][()]]
mat = tm["region_material"][()][tm["regions"][()] - 1]
assert sorted(set(names[m - 1] for m in mat)) == ["left", "right"], names
' "$work/cubes.tet.bpm"
ok "the spec's independent reader reads /patch_info" -- $py -c '
import sys
sys.path.insert(0, sys.argv[2] + "/tests/python")
import bpm_spec_reader
d = bpm_spec_reader.read(sys.argv[1])
assert d["patch_info"][2] == {"name": "left|right", "front": "right", "back": "left", "oriented": True}, d["patch_info"]
' "$work/cubes.tet.bpm" "$src"
expect 0 "the meshed file passes bpm-check" -- "$tools/bpm-check" "$work/cubes.tet.bpm"

# Exports.
expect 0 "MSH export" -- "$tools/bpm-mesh" "$work/cubes.tet.bpm" --existing -o "$work/cubes.msh" -q
contains "$work/cubes.msh" '3 1 "left"' "MSH physical volume 1 is named left"
contains "$work/cubes.msh" '3 2 "right"' "MSH physical volume 2 is named right"
contains "$work/cubes.msh" '2 3 "left|right"' "MSH keeps the patch names (physical tag = patch + 1)"
expect 0 "VTU export" -- "$tools/bpm-mesh" "$work/cubes.tet.bpm" --existing -o "$work/cubes.vtu" -q
contains "$work/cubes.vtu" 'Name="material"' "VTU has cell data material"
if $py -c "import vtk" 2>/dev/null; then
    ok "VTK reads the material cell data" -- $py -c '
import sys, vtk
r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName(sys.argv[1]); r.Update()
g = r.GetOutput()
m = g.GetCellData().GetArray("material")
assert sorted(set(int(m.GetValue(i)) for i in range(g.GetNumberOfCells()))) == [1, 2]
' "$work/cubes.vtu"
fi
expect 0 "MEDIT export" -- "$tools/bpm-mesh" "$work/cubes.tet.bpm" --existing -o "$work/cubes.mesh" -q
contains "$work/cubes.mesh" "# material 2 right" "MEDIT names the material references"

# MSH round trip: the physical names come back as patch names and give the materials again.
expect 0 "simplify the exported MSH" -- "$tools/bpm-simplify" "$work/cubes.msh" --drop-unreferenced-vertices --ratio 1 -o "$work/rt.bpm"
expect 0 "mesh it again" -- "$tools/bpm-mesh" "$work/rt.bpm" -o "$work/rt.msh"
contains "$work/err" "2 materials: 1 left" "the round trip keeps the materials"
contains "$work/rt.msh" '2 3 "left|right"' "and the patch names and tags (patch 2 is tag 3 before and after)"

# Amira HyperSurface: two tetrahedra A (above) and B (below) sharing a face.
cat > "$work/two.surf" <<'SURF'
# HyperSurface 0.1 ASCII

Parameters {
    Materials { Exterior { Id 0 } A { Id 1 } B { Id 2 } }
}

Vertices 5
0 0 0
1 0 0
0 1 0
0 0 1
0.25 0.25 -1
NBranchingPoints 0
NVerticesOnCurves 0
BoundaryCurves 0
Patches 3
{
InnerRegion A
OuterRegion Exterior
Triangles 3
1 2 4
2 3 4
3 1 4
}
{
InnerRegion B
OuterRegion Exterior
Triangles 3
1 5 2
2 5 3
3 5 1
}
{
InnerRegion A
OuterRegion B
Triangles 1
1 3 2
}
SURF
expect 0 "simplify the HyperSurface" -- "$tools/bpm-simplify" "$work/two.surf" --ratio 1 -o "$work/two.bpm"
expect 0 "mesh it" -- "$tools/bpm-mesh" "$work/two.bpm" -o "$work/two.msh" --json
ok "materials named as in the file" -- $py -c '
import json, sys
j = json.load(open(sys.argv[1]))
assert sorted(r["material_name"] for r in j["regions"]) == ["A", "B"], j["regions"]
assert j["material_problems"] == 0
' "$work/out"
contains "$work/two.msh" '2 3 "A|B"' "the MSH patch is named by its regions"

# bpm-mesh FILE.bpm gives two regions with the materials NAMES (sorted, comma separated)
# and no material problem.
meshes_to_materials() {
    expect 0 "mesh $(basename "$1")" -- "$tools/bpm-mesh" "$1" -o "${1%.bpm}.msh" --json
    ok "two regions, materials $2, no problem" -- $py -c '
import json, sys
j = json.load(open(sys.argv[1]))
assert sorted(r["material_name"] for r in j["regions"]) == sys.argv[2].split(","), j["regions"]
assert j["material_problems"] == 0
' "$work/out" "$2"
}

# One OBJ whose groups name the materials they separate (the convention of Gmsh's physical
# names): the two cubes with their interface stored once (two_cubes.py's named.obj).
expect 0 "simplify the OBJ with named groups" -- "$tools/bpm-simplify" "$work/named.obj" --ratio 1 -o "$work/named.bpm" -v
contains "$work/err" "patch 1 'left|right': between left and right (sides not known)" "the group names give the materials"
meshes_to_materials "$work/named.bpm" left,right

# One file, one closed surface per label (as multi-label marching cubes writes them): the
# two cubes as groups patch_1 and patch_2 of one OBJ, the interface in both (labels.obj).
expect 0 "simplify one file with a closed surface per label" -- "$tools/bpm-simplify" "$work/labels.obj" \
    --merge-duplicate-triangles --ratio 1 -o "$work/labels.bpm" -v
contains "$work/err" "materials labels_1, labels_2 (one per patch, instead of labels for all)" "each label is a material"
meshes_to_materials "$work/labels.bpm" labels_1,labels_2

# --material overrides; a bad one is a usage error.
expect 0 "--material names a region" -- "$tools/bpm-mesh" "$work/two.bpm" -o "$work/user.vtu" --material 1=bone --json -q
contains "$work/out" '"material_name": "bone"' "the user's name is used"
expect 2 "--material without '='" -- "$tools/bpm-mesh" "$work/two.bpm" -o "$work/x.vtu" --material bone
expect 2 "--material for a region that does not exist" -- "$tools/bpm-mesh" "$work/two.bpm" -o "$work/x.vtu" --material 7=bone
ok "no output after failures" -- test ! -e "$work/x.vtu"

# Standard input names nothing: regions are their own materials, as before 1.3.
expect 0 "simplify from standard input" -- sh -c "'$tools/bpm-simplify' - --format off --ratio 1 -o '$work/anon.bpm' < '$work/left.off'"
expect 0 "mesh a file without /patch_info" -- "$tools/bpm-mesh" "$work/anon.bpm" -o "$work/anon.msh"
contains "$work/anon.msh" '3 1 "region_1"' "a region without information is material region_1"
# Regions the input leaves undecided (the outer groups name no materials, the interface
# names two in no known order): the warnings end with the --material flags that name them.
sed -e 's/^g exterior|left$/g left_skin/' -e 's/^g exterior|right$/g right_skin/' "$work/named.obj" >"$work/ambiguous.obj"
expect 0 "simplify an OBJ whose only materials are an unordered interface" -- "$tools/bpm-simplify" \
    "$work/ambiguous.obj" --ratio 1 -o "$work/ambiguous.bpm" -q
expect 0 "mesh it" -- "$tools/bpm-mesh" "$work/ambiguous.bpm" -o "$work/ambiguous.msh"
contains "$work/err" "(ambiguous); named region_1" "region 1 is undecided"
contains "$work/err" "to name the regions the input does not decide, rerun with --material 1=NAME --material 2=NAME" \
    "the warning names the flag that decides"
finish
