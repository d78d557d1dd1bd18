#!/usr/bin/env bash
# Around an edge where three or more sheets meet (a junction of materials), a vertex
# removal must not turn a sheet past another: two triangles that share an edge never
# intersect, so the intersection test let it pass, bpm-check passed, and bpm-mesh found
# regions whose sides disagreed about their material. A 32^3 label image of four labels
# with 15 % noise (bpm-simplify extracts its multi-material surface) at --ratio 0.2 had
# 13 such edges; bpm-check's junctions check finds them, the simplifier now refuses those
# removals ("sheet order" in the kept vertices' reasons). The same image had a small
# island swept by a removal (see islands_stay_inside.sh): no component may lie in another
# material than on S0.
# Usage: sheets_keep_their_order.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
py=/usr/bin/python3
$py -c "
import sys; sys.path.insert(0, sys.argv[1])
import label_images as L
L.write(sys.argv[2], L.noisy(32, 3))" "$(dirname "$0")/lib" "$work/noisy32.nii"

expect 0 "simplify the noisy label image to 20 %" -- "$tools/bpm-simplify" "$work/noisy32.nii" --ratio 0.2 -o "$work/n.bpm"
contains "$work/err" "would turn a sheet past another around a junction edge (sheet order)" "removals refused for the sheet order are counted"
expect 0 "bpm-check passes, junctions included" -- "$tools/bpm-check" "$work/n.bpm" --json
ok "the junctions check ran on S and S0, every edge with materials" -- $py -c '
import json, sys
r = json.load(open(sys.argv[1]))
j = [c for c in r["checks"] if c["name"] == "junctions"][0]
assert j["passed"], j
c = j["counts"]
assert c["junction_edges"] > 1000 and c["original_junction_edges"] > 1000, c
assert c["inconsistent_junction_edges"] == 0 and c["original_inconsistent_junction_edges"] == 0, c
assert c["junction_edges_without_materials"] == 0, c
# and no sheet was swept across an island (one component lay in another material before
# the island guard: islands_stay_inside.sh)
assert c["components"] == c["original_components"] > 100, c
assert c["components_in_other_materials"] == 0 and c["components_not_compared"] == 0, c
' "$work/out"
finish
