#!/usr/bin/env bash
# A NIfTI label image (two touching balls, labels 1 and 2, in a box of label 3; background 0
# outside) through the whole pipeline: bpm-simplify extracts the multi-material surface
# (surface nets) and simplifies it, bpm-check passes, bpm-mesh gives one region per label
# with the label's material. Also: a reflected sform with anisotropic voxels, float32
# labels placed by the qform, a noisy checkerboard, and the reader's errors (exit 3,
# naming the file and the field).
# Usage: label_image_pipeline.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
if ! command -v tetgen >/dev/null; then
    echo "skipped: needs tetgen (scripts/setup.sh installs it)"
    exit 1
fi
py=/usr/bin/python3
$py "$(dirname "$0")/lib/label_images.py" "$work"

expect 0 "simplify a gzipped NIfTI label image" -- "$tools/bpm-simplify" "$work/spheres.nii.gz" --ratio 0.2 -o "$work/s.bpm" -v
contains "$work/err" "NIfTI-1 label image: 24 x 24 x 24 voxels of uint8" "the log describes the image"
contains "$work/err" "coordinates in LPS: the file's RAS coordinates turned by 180 degrees about z" "NIfTI's RAS made LPS"
contains "$work/err" "labels 0, 1, 2, 3" "and its labels"
contains "$work/err" "4 interfaces (patches)" "four interfaces: box|exterior, 1|2, 1|3, 2|3"
contains "$work/err" "patch 1 'label_2|label_1': front label_1, back label_2" "patches named and oriented"
expect 0 "bpm-check passes" -- "$tools/bpm-check" "$work/s.bpm"
expect 0 "bpm-check --surface on the image itself (no self-intersection)" -- "$tools/bpm-check" --surface "$work/spheres.nii.gz"
expect 0 "mesh, JSON" -- "$tools/bpm-mesh" "$work/s.bpm" -o "$work/s.tet.bpm" --json
ok "one region per label, with the label's material, no problem" -- $py -c '
import json, sys
j = json.load(open(sys.argv[1]))
names = sorted(r["material_name"] for r in j["regions"])
assert names == ["label_1", "label_2", "label_3"], j["regions"]
assert j["material_problems"] == 0, j
' "$work/out"
expect 0 "the meshed file passes bpm-check" -- "$tools/bpm-check" "$work/s.tet.bpm"
expect 0 "MSH export" -- "$tools/bpm-mesh" "$work/s.tet.bpm" --existing -o "$work/s.msh" -q
contains "$work/s.msh" '"label_3|exterior"' "MSH keeps the patch names"
contains "$work/s.msh" '"label_2"' "MSH names the physical volumes by material"

expect 0 "a reflected sform with anisotropic voxels" -- "$tools/bpm-simplify" "$work/reflected.nii.gz" --ratio 0.2 -o "$work/r.bpm" -q
expect 0 "its mesh" -- "$tools/bpm-mesh" "$work/r.bpm" -o "$work/r.tet.bpm" --json -q
ok "three labelled regions again (the triangles still face the smaller label)" -- $py -c '
import json, sys
j = json.load(open(sys.argv[1]))
assert sorted(r["material_name"] for r in j["regions"]) == ["label_1", "label_2", "label_3"], j["regions"]
assert j["material_problems"] == 0, j
' "$work/out"
expect 0 "float32 labels placed by the qform" -- "$tools/bpm-simplify" "$work/float.nii" --ratio 0.3 -o "$work/f.bpm" -v
contains "$work/err" "placed by the qform" "the qform is used"
expect 0 "and bpm-check passes" -- "$tools/bpm-check" "$work/f.bpm"
expect 0 "a noisy checkerboard of four labels" -- "$tools/bpm-simplify" "$work/noisy.nii" --ratio 0.3 -o "$work/n.bpm" -v
contains "$work/err" "vertices moved back where it made slivers (R/r > 30)" "the log says where smoothing was undone"
expect 0 "passes bpm-check" -- "$tools/bpm-check" "$work/n.bpm"
# Smoothing straightened junction lines into triangles of almost no area (R/r 1.9e5 here).
expect 0 "its surface has no sliver (R/r <= 30)" -- "$tools/bpm-check" --surface "$work/noisy.nii" --checks quality --max-aspect 30
# Its noise makes dozens of regions per material (thousands at 64^3): the log lists a few
# ids per material and counts the rest (one line naming every region was tens of kB).
expect 0 "mesh the noisy checkerboard" -- "$tools/bpm-mesh" "$work/n.bpm" -o "$work/n.tet.bpm"
ok "the materials line lists at most 8 regions per material and counts the rest" -- $py -c '
import re, sys
lines = [l for l in open(sys.argv[1]) if " materials: " in l]
assert len(lines) == 1, lines
line = lines[0]
print(len(line), "characters:", line[:200])
assert re.search(r"\(regions (\d+,){7}\d+ and \d+ more\)", line), line[:300]
for ids in re.findall(r"\(regions? ([\d,]+)", line):
    assert len(ids.split(",")) <= 8, ids
assert len(line) < 600, len(line)
' "$work/err"

# NRRD: 3D Slicer's .seg.nrrd (gzip, segment names) and raw big-endian int16.
expect 0 "simplify a .seg.nrrd" -- "$tools/bpm-simplify" "$work/spheres.seg.nrrd" --ratio 0.2 -o "$work/seg.bpm" -v
contains "$work/err" "segments 1 = bone, 2 = marrow, 3 = muscle" "the segment names are read"
contains "$work/err" "coordinates in LPS, as in the file" "the log says the frame"
contains "$work/err" "'marrow|bone': front bone, back marrow" "and name the materials"
expect 0 "mesh it" -- "$tools/bpm-mesh" "$work/seg.bpm" -o "$work/seg.tet.bpm" --json -q
ok "regions named by the segments" -- $py -c '
import json, sys
j = json.load(open(sys.argv[1]))
assert sorted(r["material_name"] for r in j["regions"]) == ["bone", "marrow", "muscle"], j["regions"]
assert j["material_problems"] == 0, j
' "$work/out"
# One frame for every format: the NIfTI file (RAS) and the .seg.nrrd (LPS) hold the same
# segmentation at the same place, so their surfaces have the same coordinates (LPS by default).
ok "NIfTI and .seg.nrrd give the same coordinates, in LPS, recorded in the file" -- $py -c '
import h5py, numpy, sys
a, b = (h5py.File(f, "r") for f in sys.argv[1:3])
va, vb = a["original/vertices"][()], b["original/vertices"][()]
assert va.shape == vb.shape and numpy.abs(va - vb).max() < 1e-9, numpy.abs(va - vb).max()
for f in (a, b):
    assert f.attrs["coordinate_frame"] in (b"LPS", "LPS"), dict(f.attrs)
' "$work/s.bpm" "$work/seg.bpm"
expect 0 "--image-frame ras" -- "$tools/bpm-simplify" "$work/spheres.seg.nrrd" --ratio 0.2 -o "$work/seg_ras.bpm" -v --image-frame ras
contains "$work/err" "coordinates in RAS: the file's LPS coordinates turned by 180 degrees about z" "says it turned them"
ok "RAS: x and y negated, recorded" -- $py -c '
import h5py, numpy, sys
a, b = (h5py.File(f, "r") for f in sys.argv[1:3])
va, vb = a["original/vertices"][()], b["original/vertices"][()]
assert numpy.array_equal(va[:, :2], -vb[:, :2]) and numpy.array_equal(va[:, 2], vb[:, 2])
assert b.attrs["coordinate_frame"] in (b"RAS", "RAS"), dict(b.attrs)
' "$work/seg.bpm" "$work/seg_ras.bpm"
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$work/tet.off"
expect 0 "--image-frame on a surface input" -- "$tools/bpm-simplify" "$work/tet.off" --ratio 0.5 -o "$work/x.bpm" --image-frame ras
contains "$work/err" "warning: --image-frame ras did nothing: the input is not a label image" "is not silent"
ok "and no frame recorded" -- $py -c '
import h5py, sys
assert "coordinate_frame" not in h5py.File(sys.argv[1], "r").attrs
' "$work/x.bpm"
# MetaImage: a compressed .mha and a .mhd with its .raw data file, both LPS (as ITK writes them).
expect 0 "simplify a compressed .mha" -- "$tools/bpm-simplify" "$work/spheres.mha" --ratio 0.2 -o "$work/mha.bpm" -v
contains "$work/err" "MetaImage label image: 24 x 24 x 24 voxels of uint8 (compressed), placed by the TransformMatrix" "the log describes it"
expect 0 "simplify a .mhd + .raw (uint16, big-endian)" -- "$tools/bpm-simplify" "$work/spheres.mhd" --ratio 0.2 -o "$work/mhd.bpm" -v
contains "$work/err" "in 'spheres.raw'" "the data file is read"
ok "MetaImage, NIfTI and NRRD give the same coordinates" -- $py -c '
import h5py, numpy, sys
v = [h5py.File(f, "r")["original/vertices"][()] for f in sys.argv[1:]]
for w in v[1:]:
    assert w.shape == v[0].shape and numpy.abs(w - v[0]).max() < 1e-9, numpy.abs(w - v[0]).max()
' "$work/s.bpm" "$work/mha.bpm" "$work/mhd.bpm"
expect 0 "bpm-check passes" -- "$tools/bpm-check" "$work/mhd.bpm"
expect 3 "a .mhd whose data file is missing" -- "$tools/bpm-simplify" "$work/bad_missing_data.mhd" --ratio 0.5 -o "$work/x.bpm"
contains "$work/err" "bad_missing_data.mhd: key ElementDataFile: the data file 'nowhere.raw' cannot be read" "names the header, the key and the data file"
# A data file that is not a regular file (a device, a FIFO) is refused, not read until
# memory runs out or waited on forever (it was read to the end).
sed 's#^ElementDataFile = .*#ElementDataFile = /dev/zero#' "$work/bad_missing_data.mhd" >"$work/bad_device_data.mhd"
expect 3 "a .mhd whose data file is /dev/zero" -- timeout 60 "$tools/bpm-simplify" "$work/bad_device_data.mhd" --ratio 0.5 -o "$work/x.bpm"
contains "$work/err" "/dev/zero: the header's ElementDataFile is not a regular file" "says why"
expect 0 "raw big-endian int16 NRRD with spacings" -- "$tools/bpm-simplify" "$work/spheres_raw.nrrd" --ratio 0.2 -o "$work/raw.bpm" -q
expect 0 "passes bpm-check" -- "$tools/bpm-check" "$work/raw.bpm"
expect 3 "NRRD of an unknown type" -- "$tools/bpm-simplify" "$work/bad_type.nrrd" --ratio 0.5 -o "$work/x.bpm"
contains "$work/err" "bad_type.nrrd: field 'type' is 'block'" "names the field"
expect 3 "overlapping segments" -- "$tools/bpm-simplify" "$work/bad_layers.nrrd" --ratio 0.5 -o "$work/x.bpm"
contains "$work/err" "the segments overlap" "says so"
expect 3 "truncated NRRD" -- "$tools/bpm-simplify" "$work/bad_truncated.nrrd" --ratio 0.5 -o "$work/x.bpm"
contains "$work/err" "bad_truncated.nrrd: truncated" "says so"

# Errors: exit 3, the file and what is wrong.
expect 3 "non-integer labels" -- "$tools/bpm-simplify" "$work/bad_float_values.nii" --ratio 0.5 -o "$work/x.bpm"
contains "$work/err" "bad_float_values.nii: voxel (0, 0, 0) has the value 0.5" "names the voxel and its value"
expect 3 "a 4-D image" -- "$tools/bpm-simplify" "$work/bad_4d.nii" --ratio 0.5 -o "$work/x.bpm"
contains "$work/err" "bad_4d.nii: a 4-D image (dim[4] = 3)" "says it is 4-D"
expect 3 "a complex data type" -- "$tools/bpm-simplify" "$work/bad_datatype.nii" --ratio 0.5 -o "$work/x.bpm"
contains "$work/err" "field datatype is 32 (complex64)" "names the field and the type"
expect 3 "truncated voxel data" -- "$tools/bpm-simplify" "$work/bad_truncated.nii" --ratio 0.5 -o "$work/x.bpm"
contains "$work/err" "bad_truncated.nii: truncated: 24 x 24 x 24 voxels of uint8 need 13824 bytes" "says how much is missing"
expect 3 "a truncated header" -- "$tools/bpm-simplify" "$work/bad_header.nii" --ratio 0.5 -o "$work/x.bpm"
contains "$work/err" "the file ends inside the NIfTI-1 header (200 of 348 bytes)" "says where it ends"
expect 3 "one label only" -- "$tools/bpm-simplify" "$work/bad_one_label.nii" --ratio 0.5 -o "$work/x.bpm"
contains "$work/err" "no two labels meet, so there is no surface" "says why there is no surface"
finish
