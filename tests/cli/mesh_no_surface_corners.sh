#!/usr/bin/env bash
# bpm-mesh splits the level-0 tetrahedra with a *surface corner* (a corner whose three edges
# are edges of the surface: two faces on neighbouring coarse triangles, or three edges at a
# coarse vertex), whose refinement makes tetrahedra with four corners on the surface at every
# level (phi flattens those). On two_cubes (two materials; 71 such tetrahedra with
# --no-corner-split, 31 with two faces on the surface) none is left, the file passes
# bpm-check, the materials, faces and patches are those of --no-corner-split, and a red
# refinement (bpm-mesh --refine 2 --no-flip) has no tetrahedron with four corners on S.
# Usage: mesh_no_surface_corners.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
if ! command -v tetgen >/dev/null; then
    echo "skipped: needs tetgen (scripts/setup.sh installs it)"
    exit 1
fi
/usr/bin/python3 "$src/bench/make_two_cubes.py" "$work/two_cubes.obj" 4 >/dev/null
expect 0 "simplify two_cubes" -- "$tools/bpm-simplify" "$work/two_cubes.obj" -o "$work/c.bpm" --ratio 0.3 --deterministic -q
expect 0 "mesh (splits on)" -- "$tools/bpm-mesh" "$work/c.bpm" -o "$work/split.bpm" --deterministic --json -q
cp "$work/out" "$work/split.json"
expect 0 "mesh --no-corner-split" -- "$tools/bpm-mesh" "$work/c.bpm" -o "$work/plain.bpm" --deterministic -q --no-corner-split
expect 0 "the split mesh passes bpm-check" -- "$tools/bpm-check" "$work/split.bpm"
expect 0 "refine it twice, red only" -- "$tools/bpm-mesh" "$work/split.bpm" --existing --refine 2 --no-flip -o "$work/fine.bpm" -q
expect 0 "refine the unsplit mesh twice, red only" -- "$tools/bpm-mesh" "$work/plain.bpm" --existing --refine 2 --no-flip -o "$work/fine-plain.bpm" -q
ok "no level-0 tetrahedron with a surface corner or two faces on S; none with four corners on S at level 2" -- /usr/bin/python3 -c '
import itertools, json, sys
import h5py, numpy as np
def counts(path):
    with h5py.File(path, "r") as f:
        g = f["tetmesh"]
        T, F = g["tetrahedra"][()], g["faces"][()]
        on_s = g["vertex_parameter_triangle"][()] >= 0
        out = {k: g[k][()] for k in ("faces", "face_patches", "region_material")}
    edges = {tuple(sorted(e)) for t in F for e in itertools.combinations(t, 2)}
    faces = {tuple(sorted(t)) for t in F}
    corner = sum(any(all(tuple(sorted((v, w))) in edges for w in t if w != v) for v in t) for t in T)
    two_faces = sum(sum(tuple(sorted(c)) in faces for c in itertools.combinations(t, 3)) >= 2 for t in T)
    four_on_s = int(on_s[T].all(axis=1).sum())
    return corner, two_faces, four_on_s, out
split, plain, fine, fine_plain = (counts(p) for p in sys.argv[1:5])
print("surface corners / two faces on S: split", split[:2], "plain", plain[:2],
      "; four corners on S at level 2: split", fine[2], "plain", fine_plain[2])
assert plain[0] > 0 and plain[1] > 0, plain[:2]  # the fixture still has them without the splits
assert split[0] == 0 and split[1] == 0, split[:2]
assert fine_plain[2] > 0 and fine[2] == 0, (fine_plain[2], fine[2])
for k in ("faces", "face_patches", "region_material"):
    assert np.array_equal(split[3][k], plain[3][k]), k
report = json.load(open(sys.argv[5]))
assert report["surface_corner_splits"] > 0 and report["inverted"] == 0, report
' "$work/split.bpm" "$work/plain.bpm" "$work/fine.bpm" "$work/fine-plain.bpm" "$work/split.json"
finish
