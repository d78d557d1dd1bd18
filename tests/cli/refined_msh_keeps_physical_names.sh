#!/usr/bin/env bash
# bpm-refine's surface .msh named every physical group "patch_<id>" although the .bpm
# holds the input's patch names (an input's "pair_0_1" came out as "patch_0"; bpm-mesh's
# .msh kept them). The names must survive, in MSH 4.1 ASCII and binary and in MSH 2.2,
# with physical tags >= 1, for Gmsh/meshio readers and for bpm reading the file back.
# Usage: refined_msh_keeps_physical_names.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
py=/usr/bin/python3
# A Gmsh 2.2 surface whose one physical group is named "pair_0_1" (two materials).
cat >"$work/in.msh" <<'MSH'
$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
1
2 7 "pair_0_1"
$EndPhysicalNames
$Nodes
4
1 0 0 0
2 1 0 0
3 0 1 0
4 0 0 1
$EndNodes
$Elements
4
1 2 2 7 1 1 3 2
2 2 2 7 1 1 2 4
3 2 2 7 1 1 4 3
4 2 2 7 1 2 3 4
$EndElements
MSH
expect 0 "simplify the named surface" -- "$tools/bpm-simplify" "$work/in.msh" -o "$work/in.bpm" --vertices 4 -q
expect 0 "bpm-info names the patch" -- "$tools/bpm-info" "$work/in.bpm"
contains "$work/out" '"pair_0_1"' "the .bpm keeps the input's name"
for variant in "msh41:" "msh41bin:--binary" "msh22:--output-format msh22"; do
    name=${variant%%:*}
    flags=${variant#*:}
    # shellcheck disable=SC2086
    expect 0 "bpm-refine to .msh ($name)" -- "$tools/bpm-refine" "$work/in.bpm" --levels 1 -o "$work/$name.msh" $flags -q
    contains "$work/$name.msh" '"pair_0_1"' "$name: the physical name is the input's"
    ok "$name: no made-up patch_0 name" -- bash -c "! grep -aq '\"patch_0\"' '$work/$name.msh'"
    expect 0 "$name: bpm reads the refined surface back" -- "$tools/bpm-simplify" "$work/$name.msh" \
        -o "$work/$name.bpm" --ratio 1 -q
    expect 0 "$name: bpm-info --json" -- "$tools/bpm-info" "$work/$name.bpm" --json
    ok "$name: read back with the name and materials 0, 1" -- $py -c '
import json, sys
j = json.load(open(sys.argv[1]))
assert [p["name"] for p in j["patches"]] == ["pair_0_1"], j["patches"]
assert j["materials"] == ["0", "1"], j["materials"]' "$work/out"
done
if $py -c "import meshio" 2>/dev/null; then
    # The input's physical tag 7 is patch 7, written as tag 8 (patch + 1, $BpmPatchIds 1).
    ok "meshio reads the name with its tag" -- $py - "$work/msh41.msh" "$work/msh22.msh" <<'PY'
import sys
import meshio
for path in sys.argv[1:]:
    m = meshio.read(path)
    assert "pair_0_1" in m.field_data, (path, m.field_data)
    assert [int(x) for x in m.field_data["pair_0_1"]] == [8, 2], (path, m.field_data)
    tags = {int(t) for block in m.cell_data["gmsh:physical"] for t in block}
    assert tags == {8}, (path, tags)
PY
else
    echo "note: meshio not installed, its read-back is not run"
fi
finish
