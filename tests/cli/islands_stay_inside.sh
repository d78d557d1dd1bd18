#!/usr/bin/env bash
# A removal must not sweep a sheet across a whole component it does not touch (an island:
# a cavity in a solid, a blob of one label inside another). The island touches no new
# triangle, so the intersection test let it pass; bpm-check passed and bpm-mesh found
# regions whose sides disagreed (noisy32 label image at --ratio 0.2: one region). Here a
# slab whose top has a bump over a small cavity (tests/cli/lib/island.py): flattening the
# bump would leave the cavity outside the solid. The simplifier keeps the bump's vertex
# ("island" among the kept vertices' reasons), and bpm-check's junctions check compares the
# material every component lies in with S0's (it failed on the old simplifier's output).
# Usage: islands_stay_inside.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
py=/usr/bin/python3
$py "$(dirname "$0")/lib/island.py" "$work/solid.off"

expect 0 "simplify the slab with a cavity as far as it goes" -- "$tools/bpm-simplify" "$work/solid.off" --vertices 12 -o "$work/s.bpm"
contains "$work/err" "1 vertex kept: would sweep a sheet across another component of the surface (island)" "the bump's removal is refused and counted"
expect 0 "bpm-check passes: the cavity lies in the solid on S as on S0" -- "$tools/bpm-check" "$work/s.bpm" --json
ok "the junctions check compared both components" -- $py -c '
import json, sys
r = json.load(open(sys.argv[1]))
j = [c for c in r["checks"] if c["name"] == "junctions"][0]
assert j["passed"], j
c = j["counts"]
assert c["components"] == 2 and c["original_components"] == 2, c
assert c["components_in_other_materials"] == 0 and c["components_not_compared"] == 0, c
' "$work/out"
finish
