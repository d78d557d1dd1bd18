#!/usr/bin/env bash
# bpm-mesh's .msh output gave the surface of patch 0 physical tag 0, which Gmsh and its
# readers (meshio, DUNE's GmshReader) take as "no physical group": every physical tag
# must be >= 1, the names keep the patch ids (patch_0 -> tag 1), and every surface entity
# and element block must use a declared physical tag.
# Usage: msh_physical_tags_start_at_1.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
if ! command -v tetgen >/dev/null; then
    echo "skipped: needs tetgen"
    exit 1
fi
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$work/tet.off"
expect 0 "simplify a tetrahedron" -- "$tools/bpm-simplify" "$work/tet.off" -o "$work/tet.bpm" --vertices 4 -q
expect 0 "bpm-mesh to .msh" -- "$tools/bpm-mesh" "$work/tet.bpm" -o "$work/tet.msh" -q
ok "physical tags >= 1, patch_0 is tag 1, entities use declared tags" -- /usr/bin/python3 - "$work/tet.msh" <<'PY'
import sys
lines = open(sys.argv[1]).read().split("\n")
i = lines.index("$PhysicalNames")
n = int(lines[i + 1])
names = {}
for line in lines[i + 2 : i + 2 + n]:
    dim, tag, name = line.split(maxsplit=2)
    names[(int(dim), int(tag))] = name.strip('"')
assert all(tag >= 1 for _, tag in names), names
# patch 0 is tag 1; names from the one-file-per-material convention (tet.off encloses "tet")
assert names.get((2, 1)) == "tet|exterior", names
assert names.get((3, 1)) == "tet", names
e = lines.index("$Entities")
npts, ncurves, nsurf, nvol = map(int, lines[e + 1].split())
for line in lines[e + 2 : e + 2 + nsurf + nvol]:
    f = line.split()
    # tag minX minY minZ maxX maxY maxZ numPhysicalTags physicalTag ... 
    dim = 2 if lines.index(line) < e + 2 + nsurf else 3
    count = int(f[7])
    for t in f[8 : 8 + count]:
        assert (dim, int(t)) in names, (dim, t, names)
PY
finish
