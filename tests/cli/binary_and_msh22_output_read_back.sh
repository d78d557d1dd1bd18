#!/usr/bin/env bash
# The binary outputs (--binary: MSH 4.1 binary, VTU appended raw; --compress: VTU in zlib
# blocks) and --output-format msh22 of bpm-refine (surfaces) and bpm-mesh (tet meshes) are
# read back with the same counts and ids as the ASCII files: by bpm's own readers
# (bpm-check --surface), by meshio, by Gmsh (the MSH files) and by VTK (the VTU files),
# each where installed (else skipped with a message). Encodings a format lacks and unknown
# formats are usage errors (exit 2) that name what is valid.
# Usage: binary_and_msh22_output_read_back.sh TOOL_DIR SOURCE_DIR WORK_DIR
set -u
tools=$1
work=$3
rm -rf "$work"
mkdir -p "$work"
source "$(dirname "$0")/lib/harness.bash"
# A cube of 12 triangles: the tet mesh has several tetrahedra and boundary faces.
printf 'OFF\n8 12 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n' >"$work/cube.off"
expect 0 "simplify the cube" -- "$tools/bpm-simplify" "$work/cube.off" -o "$work/cube.bpm" --vertices 8 -q --deterministic

# Surfaces (bpm-refine) and tet meshes (bpm-mesh), one file per encoding.
surface=(ascii.msh bin.msh v22.msh ascii.vtu bin.vtu zlib.vtu)
expect 0 "refine: ASCII .msh" -- "$tools/bpm-refine" "$work/cube.bpm" --levels 2 -o "$work/s-ascii.msh" -q
expect 0 "refine: --binary .msh" -- "$tools/bpm-refine" "$work/cube.bpm" --levels 2 -o "$work/s-bin.msh" --binary -q
expect 0 "refine: --output-format msh22" -- "$tools/bpm-refine" "$work/cube.bpm" --levels 2 -o "$work/s-v22.msh" --output-format msh22 -q
expect 0 "refine: ASCII .vtu" -- "$tools/bpm-refine" "$work/cube.bpm" --levels 2 -o "$work/s-ascii.vtu" -q
expect 0 "refine: --binary .vtu" -- "$tools/bpm-refine" "$work/cube.bpm" --levels 2 -o "$work/s-bin.vtu" --binary -q
expect 0 "refine: --compress .vtu" -- "$tools/bpm-refine" "$work/cube.bpm" --levels 2 -o "$work/s-zlib.vtu" --compress -q
expect 0 "mesh: .tet.bpm" -- "$tools/bpm-mesh" "$work/cube.bpm" -o "$work/cube.tet.bpm" -q --deterministic
expect 0 "mesh: ASCII .msh" -- "$tools/bpm-mesh" "$work/cube.tet.bpm" --existing -o "$work/t-ascii.msh" -q
expect 0 "mesh: --binary .msh" -- "$tools/bpm-mesh" "$work/cube.tet.bpm" --existing -o "$work/t-bin.msh" --binary -q
expect 0 "mesh: --output-format msh22" -- "$tools/bpm-mesh" "$work/cube.tet.bpm" --existing -o "$work/t-v22.msh" --output-format msh22 -q
expect 0 "mesh: ASCII .vtu" -- "$tools/bpm-mesh" "$work/cube.tet.bpm" --existing -o "$work/t-ascii.vtu" -q
expect 0 "mesh: --binary .vtu" -- "$tools/bpm-mesh" "$work/cube.tet.bpm" --existing -o "$work/t-bin.vtu" --binary -q
expect 0 "mesh: --compress .vtu" -- "$tools/bpm-mesh" "$work/cube.tet.bpm" --existing -o "$work/t-zlib.vtu" --compress -q
expect 0 "refine --volume: --binary .msh" -- "$tools/bpm-refine" "$work/cube.tet.bpm" --volume --levels 1 -o "$work/r-bin.msh" --binary -q
contains "$work/s-bin.msh" "4.1 1 8" "the binary MSH says file type 1"
contains "$work/s-v22.msh" "2.2 0 8" "msh22 is MSH 2.2"
contains "$work/t-zlib.vtu" "vtkZLibDataCompressor" "the compressed VTU names its compressor"
contains "$work/r-bin.msh" "4.1 1 8" "bpm-refine --volume writes binary MSH"

# bpm's readers: every surface file gives the surface of the ASCII one (bpm-check counts).
for f in "${surface[@]}"; do
    expect 0 "bpm reads s-$f" -- "$tools/bpm-check" --surface "$work/s-$f" --checks topology
    contains "$work/out" "chi 2" "s-$f is the closed refined cube"
done
"$tools/bpm-check" --surface "$work/s-ascii.msh" --checks intersections >"$work/ascii.txt" 2>&1
for f in "${surface[@]}"; do
    expect 0 "bpm: s-$f" -- "$tools/bpm-check" --surface "$work/s-$f" --checks intersections
    ok "s-$f has the triangles of s-ascii.msh" -- cmp -s "$work/out" "$work/ascii.txt"
done
# The tet meshes' boundary faces read as a surface (tets skipped, their unused nodes dropped;
# bpm's VTU reader reads surface cells only, so not the tet VTU files).
for f in t-bin.msh t-v22.msh; do
    expect 0 "bpm reads the boundary of $f" -- "$tools/bpm-check" --surface "$work/$f" --drop-unreferenced-vertices --checks topology
    contains "$work/out" "chi 2" "$f's boundary is closed"
done

# meshio (Debian python3-meshio): the same cells and ids in every encoding.
if /usr/bin/python3 -c 'import meshio' 2>/dev/null; then
    expect 0 "meshio reads every file with the cells of the ASCII one" -- /usr/bin/python3 - "$work" <<'PY'
import sys, meshio, numpy as np
work = sys.argv[1]
def summary(path):
    m = meshio.read(path)
    cells = sorted((c.type, len(c.data)) for c in m.cells)
    ids = {}
    for key in ("gmsh:physical", "patch", "material", "region"):
        if key in m.cell_data:
            ids[key] = sorted(np.concatenate([np.asarray(a).ravel() for a in m.cell_data[key]]).tolist())
    return m.points.shape, cells, ids
bad = 0
for group in (["s-ascii.msh", "s-bin.msh", "s-v22.msh"], ["s-ascii.vtu", "s-bin.vtu", "s-zlib.vtu"],
              ["t-ascii.msh", "t-bin.msh"], ["t-ascii.vtu", "t-bin.vtu", "t-zlib.vtu"]):
    want = summary(f"{work}/{group[0]}")
    for f in group[1:]:
        got = summary(f"{work}/{f}")
        if got != want:
            print(f"{f}: {got} != {group[0]}: {want}"); bad += 1
# MSH 2.2 of a tet mesh: the tets and the outer boundary faces of the MSH 4.1 file.
t41, t22 = meshio.read(f"{work}/t-ascii.msh"), meshio.read(f"{work}/t-v22.msh")
count = lambda m, t: sum(len(c.data) for c in m.cells if c.type == t)
if count(t22, "tetra") != count(t41, "tetra") or count(t22, "triangle") != count(t41, "triangle"):
    print("t-v22.msh differs from t-ascii.msh"); bad += 1
sys.exit(bad)
PY
else
    echo "skipped: meshio (python3-meshio) is not installed"
fi

# Gmsh reads the MSH files (binary and 2.2) with their elements.
if command -v gmsh >/dev/null; then
    for f in s-bin.msh s-v22.msh t-bin.msh t-v22.msh; do
        expect 0 "gmsh reads $f" -- gmsh "$work/$f" -0 -o "$work/gmsh-$f"
        ok "gmsh reports no error on $f" -- bash -c "! grep -q '^Error' '$work/out' '$work/err'"
        # Surfaces name their patches as the input did (cube.off encloses "cube", so
        # "cube|exterior"; refined surfaces wrote "patch_0" before); the mesh's volume is the
        # material "cube".
        name='"cube|exterior"'
        [[ $f == t-* ]] && name='3 1 "cube"'
        contains "$work/gmsh-$f" "$name" "gmsh keeps the physical names of $f"
    done
else
    echo "skipped: gmsh is not installed"
fi

# VTK's own reader on the binary and compressed VTU files.
if /usr/bin/python3 -c 'import vtk' 2>/dev/null; then
    expect 0 "VTK reads the binary and compressed VTU files" -- /usr/bin/python3 - "$work" <<'PY'
import sys, vtk
work = sys.argv[1]
def read(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    arrays = sorted(g.GetCellData().GetArrayName(i) for i in range(g.GetCellData().GetNumberOfArrays()))
    return r.GetErrorCode(), g.GetNumberOfPoints(), g.GetNumberOfCells(), arrays, g.GetPoint(g.GetNumberOfPoints() - 1)
bad = 0
for prefix in ("s", "t"):
    want = read(f"{work}/{prefix}-ascii.vtu")
    for enc in ("bin", "zlib"):
        got = read(f"{work}/{prefix}-{enc}.vtu")
        if got != want:
            print(f"{prefix}-{enc}.vtu: {got} != {want}"); bad += 1
sys.exit(bad)
PY
else
    echo "skipped: VTK for Python (python3-vtk9) is not installed"
fi

# Usage errors name what is valid, before any work.
expect 2 "--compress with .msh" -- "$tools/bpm-refine" "$work/cube.bpm" --levels 1 -o "$work/x.msh" --compress
contains "$work/err" "only .vtu output is compressed" "says which output is compressed"
expect 2 "--binary with .off" -- "$tools/bpm-refine" "$work/cube.bpm" --levels 1 -o "$work/x.off" --binary
contains "$work/err" "--binary writes msh (MSH 4.1) and vtu" "names the binary formats"
expect 2 "--binary with msh22" -- "$tools/bpm-mesh" "$work/cube.tet.bpm" --existing -o "$work/x.msh" --output-format msh22 --binary
contains "$work/err" "msh22 has no binary form" "MSH 2.2 is ASCII only"
expect 2 "bpm-refine --output-format nonsense" -- "$tools/bpm-refine" "$work/cube.bpm" --levels 1 -o "$work/x.dat" --output-format nonsense
contains "$work/err" "valid: off obj ply stl msh msh22 vtu bpm" "bpm-refine lists the valid formats"
expect 2 "bpm-mesh --output-format nonsense" -- "$tools/bpm-mesh" "$work/cube.tet.bpm" --existing -o "$work/x.dat" --output-format nonsense
contains "$work/err" "valid: bpm msh msh22 vtu mesh" "bpm-mesh lists the valid formats"
ok "no file left by the refused runs" -- bash -c "! ls '$work'/x.* 2>/dev/null | grep -q ."
for t in bpm-refine bpm-mesh; do
    expect 0 "$t --help" -- "$tools/$t" --help
    contains "$work/out" "--binary" "$t --help lists --binary"
    contains "$work/out" "--compress" "$t --help lists --compress"
    contains "$work/out" "msh22" "$t --help names msh22"
done
finish
