#!/usr/bin/env bash
# Pipeline: bpm-simplify -> bpm-smooth -> bpm-refine -> bpm-check on femur, plus the
# usage / input errors of bpm-refine and bpm-smooth.
# Usage: refine_smooth.sh TOOL_DIR SOURCE_DIR WORK_DIR
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
expect 2 "levels and max-error exclude each other" -- "$refine" "$example" -o "$work/x.off" --levels 1 --max-error 0.01
expect 2 "unknown output format" -- "$refine" "$example" -o "$work/x.xyz" --levels 1
expect 2 "stdout needs --output-format" -- "$refine" "$example" -o - --levels 1
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
expect 0 "stdout" -- bash -c "'$refine' '$example' -o - --output-format off --levels 1 > '$work/stdout.off'"
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
    expect 0 "refine femur adaptive to .vtu with data" -- "$refine" "$work/femur_smooth.bpm" -o "$work/femur_adaptive.vtu" --max-error 0.002 --data
    contains "$work/femur_adaptive.vtu" "Name=\"original_normal\"" "normals in VTU"
    expect 0 "refine femur K=1 to .off" -- "$refine" "$work/femur_smooth.bpm" -o "$work/femur_k1.off" --levels 1
    expect 0 "refined surface reads back" -- "$check" --surface --checks topology "$work/femur_k1.off"
    # Vertex data of the input (PLY properties) travels through simplify, smooth and
    # refine; a linear field of the position must come out as the same field of the
    # refined positions (phi interpolates linearly in original triangles).
    /usr/bin/python3 - "$meshes/femur.off" "$work/femur_data.ply" <<'PY'
import sys
t = open(sys.argv[1]).read().split()
nv, nf = int(t[1]), int(t[2]); i = 4
V = [tuple(map(float, t[i + 3 * k:i + 3 * k + 3])) for k in range(nv)]; i += 3 * nv
with open(sys.argv[2], "w") as f:
    f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty double x\nproperty double y\nproperty double z\n" % nv)
    f.write("property double temperature\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n")
    f.write("element face %d\nproperty list uchar int vertex_indices\nend_header\n" % nf)
    for (x, y, z) in V: f.write("%.17g %.17g %.17g %.17g 10 20 30\n" % (x, y, z, x + 2 * y + 3 * z))
    for k in range(nf):
        n = int(t[i]); f.write("%d %s\n" % (n, " ".join(t[i + 1:i + 1 + n]))); i += n + 1
PY
    expect 0 "simplify femur with vertex data" -- "$tools/bpm-simplify" "$work/femur_data.ply" -o "$work/femur_data.bpm" --ratio 0.1
    expect 0 "smooth keeps it" -- "$smooth" "$work/femur_data.bpm" -o "$work/femur_data_s.bpm" --iterations 2
    # (Data is defined at phi of a vertex's parameter; a vertex held back from phi to avoid
    # a self-intersection is off it, so the identity below needs every vertex at phi.)
    expect 0 "refine to .bpm keeps it" -- "$refine" "$work/femur_data_s.bpm" -o "$work/femur_data_k1.bpm" --levels 1 --allow-intersections
    expect 0 "refine again with --data" -- "$refine" "$work/femur_data_k1.bpm" -o "$work/femur_data.vtu" --levels 2 --data --allow-intersections
    contains "$work/femur_data.vtu" "Name=\"temperature\"" "temperature in VTU"
    expect 0 "temperature equals x + 2y + 3z at the refined vertices" -- /usr/bin/python3 - "$work/femur_data.vtu" <<'PY'
import sys, vtk
from vtk.util.numpy_support import vtk_to_numpy
r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName(sys.argv[1]); r.Update()
g = r.GetOutput(); P = vtk_to_numpy(g.GetPoints().GetData())
T = vtk_to_numpy(g.GetPointData().GetArray("temperature")).reshape(-1)
C = vtk_to_numpy(g.GetPointData().GetArray("colors"))
err = abs(T - (P[:, 0] + 2 * P[:, 1] + 3 * P[:, 2])).max()
print("points", len(P), "max error", err)
assert len(P) > 10000 and err < 1e-9, err
assert abs(C - [10, 20, 30]).max() < 1e-9
PY
else
    echo "skipping femur: $meshes/femur.off missing"
fi

finish
