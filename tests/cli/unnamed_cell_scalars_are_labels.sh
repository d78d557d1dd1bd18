#!/usr/bin/env bash
# vtkDiscreteMarchingCubes writes one closed surface per label and the labels as unnamed
# cell scalars, which VTK's writers name "scalars" (legacy .vtk) and "Scalars_" (.vtp).
# They were ignored: the whole file was one patch, and after --merge-duplicate-triangles
# bpm-mesh named the region inside the inner label "exterior". They are the patch ids
# when no cell array is named patch/material/label/...
# Usage: unnamed_cell_scalars_are_labels.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
if ! command -v tetgen >/dev/null; then
    echo "skipped: needs tetgen (scripts/setup.sh installs it)"
    exit 1
fi
py=/usr/bin/python3

# labels.obj: the cubes [0,1]^3 (group patch_1) and [1,2]x[0,1]^2 (patch_2), each closed,
# the square x = 1 in both. As VTK files with the groups as unnamed cell scalars.
$py "$(dirname "$0")/lib/two_cubes.py" "$work"
$py - "$work" <<'PY'
import sys
work = sys.argv[1]
verts, tris, labels, label = [], [], [], 0
for line in open(f"{work}/labels.obj"):
    w = line.split()
    if not w:
        continue
    if w[0] == "v":
        verts.append(w[1:4])
    elif w[0] == "g":
        label = int(w[1].split("_")[1])
    elif w[0] == "f":
        tris.append([int(c.split("/")[0]) - 1 for c in w[1:]])
        labels.append(label)
with open(f"{work}/cubes.vtk", "w") as f:
    f.write("# vtk DataFile Version 4.2\nvtk output\nASCII\nDATASET POLYDATA\n")
    f.write("POINTS %d float\n" % len(verts) + "".join(" ".join(v) + "\n" for v in verts))
    f.write("POLYGONS %d %d\n" % (len(tris), 4 * len(tris)) + "".join("3 %d %d %d\n" % tuple(t) for t in tris))
    f.write("CELL_DATA %d\nSCALARS scalars float\nLOOKUP_TABLE default\n" % len(tris))
    f.write("".join("%d\n" % l for l in labels))
with open(f"{work}/cubes.vtp", "w") as f:
    f.write('<?xml version="1.0"?>\n<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian">\n<PolyData>\n')
    f.write('<Piece NumberOfPoints="%d" NumberOfPolys="%d">\n' % (len(verts), len(tris)))
    f.write('<CellData Scalars="Scalars_">\n<DataArray type="Float32" Name="Scalars_" format="ascii">\n')
    f.write(" ".join(str(l) for l in labels) + "\n</DataArray>\n</CellData>\n")
    f.write('<Points>\n<DataArray type="Float32" NumberOfComponents="3" format="ascii">\n')
    f.write(" ".join(" ".join(v) for v in verts) + "\n</DataArray>\n</Points>\n<Polys>\n")
    f.write('<DataArray type="Int64" Name="connectivity" format="ascii">\n')
    f.write(" ".join("%d %d %d" % tuple(t) for t in tris) + "\n</DataArray>\n")
    f.write('<DataArray type="Int64" Name="offsets" format="ascii">\n')
    f.write(" ".join(str(3 * (i + 1)) for i in range(len(tris))) + "\n</DataArray>\n")
    f.write("</Polys>\n</Piece>\n</PolyData>\n</VTKFile>\n")
PY

# One region per label, each its own material, no region named "exterior".
materials_are() {
    expect 0 "mesh $(basename "$1")" -- "$tools/bpm-mesh" "$1" -o "${1%.bpm}.msh" --json
    ok "$(basename "$1"): regions of materials $2, no problem" -- $py -c '
import json, sys
j = json.load(open(sys.argv[1]))
assert sorted(r["material_name"] for r in j["regions"]) == sys.argv[2].split(","), j["regions"]
assert j["material_problems"] == 0, j
' "$work/out" "$2"
}
for f in cubes.vtk cubes.vtp; do
    expect 0 "simplify $f" -- "$tools/bpm-simplify" "$work/$f" --merge-duplicate-triangles --ratio 1 \
        -o "$work/$f.bpm" -v
    contains "$work/err" "VTK's name for unnamed cell scalars" "$f: the log says where the patch ids come from"
    contains "$work/err" "materials cubes_1, cubes_2 (one per patch" "$f: each label is a material"
    materials_are "$work/$f.bpm" cubes_1,cubes_2
done

# A named patch array wins over the unnamed scalars.
sed 's/^SCALARS scalars float$/SCALARS label float/' "$work/cubes.vtk" >"$work/named.vtk"
printf 'FIELD FieldData 1\nscalars 1 %d int\n' "$(grep -c '^3 ' "$work/named.vtk")" >>"$work/named.vtk"
grep '^3 ' "$work/named.vtk" | awk '{print 7}' >>"$work/named.vtk"
expect 0 "simplify a file with both" -- "$tools/bpm-simplify" "$work/named.vtk" --merge-duplicate-triangles \
    --ratio 1 -o "$work/named.bpm" -v
contains "$work/err" "patch ids from the cell data array 'label'" "the named array gives the patches"
contains "$work/err" "cell data ignored: 'scalars'" "the unnamed one is ignored"

# Unnamed scalars that are not whole numbers are no labels.
awk 'BEGIN{c=0} /^LOOKUP_TABLE/{print; c=1; next} c==1{print $1 + 0.5; next} {print}' "$work/cubes.vtk" >"$work/float.vtk"
expect 3 "non-integral scalars: no patches, so duplicate triangles of one patch" -- "$tools/bpm-simplify" \
    "$work/float.vtk" -o "$work/float.bpm" --ratio 1
contains "$work/err" "same three vertices as triangle" "non-integral scalars are ignored: both cubes are one patch"

# The real thing, where VTK is installed: a label 2 ball inside a label 1 shell.
if $py -c "import vtk" 2>/dev/null; then
    $py - "$work" <<'PY'
import sys, vtk
img = vtk.vtkImageData()
img.SetDimensions(24, 24, 24)
img.AllocateScalars(vtk.VTK_UNSIGNED_CHAR, 1)
for k in range(24):
    for j in range(24):
        for i in range(24):
            r2 = (i - 12) ** 2 + (j - 12) ** 2 + (k - 12) ** 2
            img.SetScalarComponentFromDouble(i, j, k, 0, 2 if r2 < 16 else 1 if r2 < 64 else 0)
mc = vtk.vtkDiscreteMarchingCubes()
mc.SetInputData(img)
mc.GenerateValues(2, 1, 2)
mc.Update()
for writer, name in ((vtk.vtkPolyDataWriter(), "mc.vtk"), (vtk.vtkXMLPolyDataWriter(), "mc.vtp")):
    writer.SetFileName(sys.argv[1] + "/" + name)
    writer.SetInputData(mc.GetOutput())
    writer.Write()
PY
    for f in mc.vtk mc.vtp; do
        expect 0 "simplify vtkDiscreteMarchingCubes' $f" -- "$tools/bpm-simplify" "$work/$f" \
            --merge-duplicate-triangles --ratio 0.3 -o "$work/$f.bpm" -q
        materials_are "$work/$f.bpm" mc_1,mc_2
    done
fi
finish
