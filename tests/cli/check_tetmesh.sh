#!/usr/bin/env bash
# bpm-check's tetmesh check: bpm-mesh's outputs (one material and two, level 0 and a
# refined level) pass; copies broken one way each (an inverted tetrahedron, a missing one,
# a face on S reversed, a face listed twice, a region id changed across a face not on S,
# a coarse vertex moved) fail with the element named; --checks tetmesh on a file without
# a tet mesh fails and says which tool writes one.
# Usage: check_tetmesh.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
elephant=$src/.data/meshes/elephant.off
if [ ! -f "$elephant" ] || ! command -v tetgen >/dev/null; then
    echo "skipped: needs $elephant and tetgen (scripts/setup.sh installs both)"
    exit 1
fi
py=/usr/bin/python3

# Two unit cubes side by side, one OFF file per material (tests/cli/lib/two_cubes.py).
$py "$(dirname "$0")/lib/two_cubes.py" "$work"

expect 0 "simplify elephant" -- "$tools/bpm-simplify" "$elephant" -o "$work/e.bpm" --ratio 0.1 -q
expect 0 "bpm-check on a file without a tet mesh: no tetmesh line" -- "$tools/bpm-check" "$work/e.bpm"
ok "no tetmesh line without a tet mesh" -- bash -c "! grep -q tetmesh '$work/out'"
expect 0 "--checks all on a file without a tet mesh passes" -- "$tools/bpm-check" "$work/e.bpm" --checks all
ok "--checks all adds no tetmesh line without a tet mesh" -- bash -c "! grep -q tetmesh '$work/out'"
expect 1 "--checks tetmesh on a file without one fails" -- "$tools/bpm-check" "$work/e.bpm" --checks tetmesh
contains "$work/out" "no tetrahedral mesh" "the report says the file has no tet mesh"
contains "$work/out" "bpm-mesh" "and which tool writes one"

expect 0 "mesh elephant" -- "$tools/bpm-mesh" "$work/e.bpm" -o "$work/e0.bpm" -q
expect 0 "level 0 passes" -- "$tools/bpm-check" "$work/e0.bpm"
contains "$work/out" "PASS tetmesh" "the tetmesh check runs by default"
contains "$work/out" "0 inverted, conforming" "level 0 is conforming"
expect 0 "refine the volume mesh once" -- "$tools/bpm-refine" "$work/e0.bpm" --volume --levels 1 -o "$work/e1.bpm" -q
expect 0 "level 1 passes" -- "$tools/bpm-check" "$work/e1.bpm" --checks tetmesh --json
contains "$work/out" '"name": "tetmesh", "passed": true' "level 1 passes the tetmesh check"
expect 0 "two materials" -- "$tools/bpm-simplify" "$work/left.off" "$work/right.off" -o "$work/c.bpm" --ratio 1 \
    --merge-duplicate-vertices --merge-duplicate-triangles -q
expect 0 "mesh two materials" -- "$tools/bpm-mesh" "$work/c.bpm" -o "$work/c0.bpm" -q
expect 0 "two materials pass" -- "$tools/bpm-check" "$work/c0.bpm" --checks tetmesh
contains "$work/out" "PASS tetmesh" "two regions pass the tetmesh check"

# Broken copies: each must fail the tetmesh check with the given text in the report.
break_copy() {  # break_copy INPUT OUTPUT HOW
    cp "$1" "$2"
    $py - "$2" "$3" <<'PY'
import sys
import h5py
import numpy as np
path, how = sys.argv[1:3]
with h5py.File(path, "r+") as f:
    g = f["tetmesh"]
    tets = g["tetrahedra"][()]
    faces = g["faces"][()]
    if how == "inverted":
        tets[5, [0, 1]] = tets[5, [1, 0]]
        g["tetrahedra"][...] = tets
    elif how == "missing":
        # Drop the last tetrahedron: its faces become holes (or were on S and are now
        # faces of no tetrahedron).
        for name in ("tetrahedra", "regions", "tet_ancestor"):
            if name in g:
                data = g[name][()][:-1]
                del g[name]
                g.create_dataset(name, data=data)
    elif how == "reversed":
        faces[3, [1, 2]] = faces[3, [2, 1]]
        g["faces"][...] = faces
    elif how == "duplicate":
        faces[4] = faces[3]
        g["faces"][...] = faces
    elif how == "region":
        regions = g["regions"][()]
        # A tetrahedron with no face on S: changing its region separates it from its
        # neighbours by faces that are not on S.
        on_s = {tuple(sorted(x)) for x in faces}
        for t, x in enumerate(tets):
            if not any(tuple(sorted(np.delete(x, i))) in on_s for i in range(4)):
                break
        regions[t] = regions.max() + 1
        g["regions"][...] = regions
        for name in ("region_material", "material_names"):  # optional; they would no longer match
            if name in g:
                del g[name]
    elif how == "moved":
        v = g["vertices"][()]
        v[0] += 1e-3
        g["vertices"][...] = v
PY
}
for case in "inverted:is inverted" "missing:not in /tetmesh/faces" "reversed:oriented against its coarse triangle" \
            "duplicate:listed twice" "region:regions are separated by S" "moved:not at its position"; do
    how=${case%%:*}
    text=${case#*:}
    break_copy "$work/e0.bpm" "$work/broken-$how.bpm" "$how"
    expect 1 "$how fails bpm-check" -- "$tools/bpm-check" "$work/broken-$how.bpm" --checks tetmesh
    contains "$work/out" "FAIL tetmesh" "$how: the tetmesh check fails"
    contains "$work/out" "$text" "$how: the report says what is wrong"
done
break_copy "$work/e1.bpm" "$work/broken-refined.bpm" reversed
expect 1 "a reversed face at level 1 fails" -- "$tools/bpm-check" "$work/broken-refined.bpm" --checks tetmesh
contains "$work/out" "oriented against its coarse triangle" "level 1: the reversed face is found"
finish
