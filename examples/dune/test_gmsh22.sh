#!/usr/bin/env bash
# bpm-mesh --output-format msh22 is read by DUNE's own Dune::GmshReader (DUNE 2.9 reads MSH
# 2.2 only) into a UGGrid<3>, with its element ids (material ids) and boundary ids (patch
# + 1), on two nested spheres (two materials, an interface between them). Fails when DUNE
# refuses the file or its counts differ from the MSH 4.1 file of the same mesh. Also shows
# the check can fail: the same file with $PhysicalNames before $Nodes (where Gmsh puts it)
# is refused by DUNE. (With the interface triangles kept UGGrid refuses it too: "You have
# supplied 506 parametrized boundary segments, but the coarse grid has only 336 boundary faces".)
# Usage: test_gmsh22.sh TOOL_DIR SOURCE_DIR WORK_DIR
set -euo pipefail
bin=$1
src=$2
work=$3
rm -rf "$work"
mkdir -p "$work"
/usr/bin/python3 "$src/bench/make_nested_spheres.py" "$work/outer.off" "$work/inner.off" 3
"$bin/bpm-simplify" "$work/outer.off" "$work/inner.off" --ratio 0.2 -o "$work/spheres.bpm" -q --deterministic
"$bin/bpm-mesh" "$work/spheres.bpm" -o "$work/spheres.tets.bpm" -q --deterministic
"$bin/bpm-mesh" "$work/spheres.tets.bpm" --existing -o "$work/m22.msh" --output-format msh22 -q
"$bin/bpm-mesh" "$work/spheres.tets.bpm" --existing -o "$work/m41.msh" -q
"$bin/read_gmsh22" "$work/m22.msh" > "$work/dune.json"
cat "$work/dune.json"

/usr/bin/python3 - "$work" <<'PY'
import json, os, sys
from collections import Counter
work = sys.argv[1]
ok = True
def check(cond, what):
    global ok
    print(("ok   " if cond else "FAIL ") + what)
    ok &= bool(cond)

def sections(path):
    out, name = {}, None
    for line in open(path):
        line = line.strip()
        if line.startswith("$End"): name = None
        elif line.startswith("$"): name = line[1:]; out[name] = []
        elif name: out[name].append(line.split())
    return out

# MSH 4.1: physical tag of each entity, then tets / triangles per physical tag.
s41 = sections(f"{work}/m41.msh")
ent = s41["Entities"]
counts = [int(x) for x in ent[0]]
physical = {}
row = 1
for dim in range(4):
    for _ in range(counts[dim]):
        r = ent[row]; row += 1
        physical[(dim, int(r[0]))] = int(r[8 if dim > 0 else 5])
tets41, tris41 = Counter(), Counter()
els = s41["Elements"]; row = 1
while row < len(els):
    dim, tag, typ, n = map(int, els[row]); row += 1 + n
    (tets41 if typ == 4 else tris41)[physical[(dim, tag)]] += n

# MSH 2.2: physical tag is the first tag of each element.
s22 = sections(f"{work}/m22.msh")
tets22, tris22 = Counter(), Counter()
for r in s22["Elements"][1:]:
    (tets22 if r[1] == "4" else tris22)[int(r[3])] += 1
check(tets22 == tets41, f"MSH 2.2 has the tets of MSH 4.1 per material: {dict(tets22)}")
check(sum(tris22.values()) < sum(tris41.values()), f"MSH 2.2 leaves out the interface: {sum(tris22.values())} of {sum(tris41.values())} triangles")

dune = json.load(open(f"{work}/dune.json"))
check(dune["elements"] == sum(tets41.values()), f"DUNE has all {dune['elements']} elements")
check({int(k): v for k, v in dune["element_ids"].items()} == dict(tets41), f"DUNE element ids = material ids: {dune['element_ids']}")
check(len(dune["element_ids"]) == 2, "two materials")
check({int(k): v for k, v in dune["boundary_ids"].items()} == dict(tris22), f"DUNE boundary ids = patch + 1: {dune['boundary_ids']}")
check(dune["boundary_faces"] == sum(tris22.values()), f"every boundary face has an id ({dune['boundary_faces']})")

# Variants DUNE refuses: names before $Nodes (Gmsh's order), interface triangles kept.
text = open(f"{work}/m22.msh").read()
names = text[text.index("$PhysicalNames"):text.index("$EndPhysicalNames") + len("$EndPhysicalNames\n")]
front = text.replace(names, "").replace("$EndMeshFormat\n", "$EndMeshFormat\n" + names)
open(f"{work}/names_first.msh", "w").write(front)
sys.exit(0 if ok else 1)
PY
if "$bin/read_gmsh22" "$work/names_first.msh" > /dev/null 2> "$work/names_first.err"; then
    echo "FAIL DUNE read the file with \$PhysicalNames before \$Nodes: this test cannot tell a bad order"
    exit 1
fi
echo "ok   DUNE refuses \$PhysicalNames before \$Nodes: $(cat "$work/names_first.err")"
