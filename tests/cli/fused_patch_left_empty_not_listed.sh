#!/usr/bin/env bash
# One closed surface per material, a ball inside a shell: every triangle of ball.off is
# also in shell.off (the shell's inner side), so --merge-duplicate-triangles fuses all of
# them into the interface patch. Before, the ball's own patch stayed in /patch_info with
# 0 triangles, and bpm-info listed it: '1: "ball|exterior" (front exterior, back ball)
# 0 original, 0 coarse triangles', a patch that is not there, saying the ball touches the
# exterior. Now the reader drops that row and says why in the log.
# Usage: fused_patch_left_empty_not_listed.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"

# Octahedra: the ball (radius 1), the shell = radius 3 outward + the ball inward.
octahedron() {  # RADIUS FLIP(0|1) FIRST_VERTEX -> the 8 faces, then the 6 vertices to $work/v
    local r=$1
    printf '%s 0 0\n-%s 0 0\n0 %s 0\n0 -%s 0\n0 0 %s\n0 0 -%s\n' $r $r $r $r $r $r
}
faces() {  # FLIP OFFSET
    local flip=$1 o=$2
    while read -r a b c; do
        if [ "$flip" = 1 ]; then echo "3 $((a + o)) $((c + o)) $((b + o))"; else echo "3 $((a + o)) $((b + o)) $((c + o))"; fi
    done <<'F'
0 2 4
2 1 4
1 3 4
3 0 4
2 0 5
1 2 5
3 1 5
0 3 5
F
}
{ echo OFF; echo "6 8 0"; octahedron 1; faces 0 0; } >"$work/ball.off"
{ echo OFF; echo "12 16 0"; octahedron 3; octahedron 1; faces 0 0; faces 1 6; } >"$work/shell.off"

expect 0 "ball in a shell, fused" -- "$tools/bpm-simplify" "$work/shell.off" "$work/ball.off" -o "$work/sb.bpm" --ratio 1 \
    --merge-duplicate-vertices --merge-duplicate-triangles
contains "$work/err" "patch 2 = the 8 triangles that patches 0 and 1 had in common (fused)" "the interface patch"
contains "$work/err" "patch 1 (\"ball|exterior\") has no triangles left: all of them were in common with other patches, fused into patch 2" \
    "the log says the ball's own patch is gone and where its triangles went"
expect 0 "bpm-info" -- "$tools/bpm-info" "$work/sb.bpm"
contains "$work/out" "patches     2" "two patches, not three"
ok "no empty patch listed" -- bash -c "! grep -q '0 original, 0 coarse triangles' '$work/out'"
ok "no ball|exterior" -- bash -c "! grep -q 'ball|exterior' '$work/out'"
contains "$work/out" "\"shell|ball\" (front ball, back shell) 8 original" "the interface names both materials"
contains "$work/out" "materials   ball, exterior, shell" "the ball is still a material"
expect 0 "bpm-info --json" -- "$tools/bpm-info" "$work/sb.bpm" --json
ok "the JSON lists patches 0 and 2" -- /usr/bin/python3 -c "
import json, sys
d = json.load(open('$work/out'))
ids = [p['id'] for p in d['patches']]
sys.exit(0 if ids == [0, 2] else 1)"
finish
