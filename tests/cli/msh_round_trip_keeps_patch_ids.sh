#!/usr/bin/env bash
# The .msh files bpm writes give patch p the physical tag p + 1 (tag 0 means "no physical
# group" to Gmsh, meshio and DUNE), and bpm read them back with patch = tag: every patch
# id moved up by one on the round trip. They now end with a $BpmPatchIds section that
# bpm's reader uses (patch = tag - 1) and Gmsh and meshio skip. Also: bpm-refine writes a
# refined surface to .msh (it said "unknown output format 'msh'").
# Usage: msh_round_trip_keeps_patch_ids.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
# An octahedron in two patches (OBJ groups patch_<N> are patch N).
cat >"$work/octa.obj" <<'OBJ'
v 1 0 0
v -1 0 0
v 0 1 0
v 0 -1 0
v 0 0 1
v 0 0 -1
g patch_0
f 1 3 5
f 3 2 5
f 2 4 5
f 4 1 5
g patch_1
f 3 1 6
f 2 3 6
f 4 2 6
f 1 4 6
OBJ
expect 0 "simplify (nothing removed)" -- "$tools/bpm-simplify" "$work/octa.obj" -o "$work/octa.bpm" --vertices 6 -q
expect 0 "bpm-refine a surface to .msh" -- "$tools/bpm-refine" "$work/octa.bpm" --levels 1 -o "$work/fine.msh" -q
# Read back by bpm: the patches are 0 and 1 again (written out as OBJ groups).
expect 0 "read the .msh back" -- "$tools/bpm-simplify" "$work/fine.msh" -o "$work/back.bpm" --ratio 0.99 -q
expect 0 "surface of the read-back file" -- "$tools/bpm-refine" "$work/back.bpm" --levels 0 -o "$work/back.obj" -q
ok "surface .msh round trip keeps patches 0 and 1" -- \
    test "$(grep '^g ' "$work/back.obj" | sort -u | tr '\n' ' ')" = "g patch_0 g patch_1 "
ok "meshio and gmsh read the surface .msh with physical tags 1 and 2" -- /usr/bin/python3 - "$work/fine.msh" <<'PY'
import subprocess, sys, meshio
m = meshio.read(sys.argv[1])
tags = sorted(set(int(t) for t in m.cell_data_dict["gmsh:physical"]["triangle"]))
assert tags == [1, 2], tags
r = subprocess.run(["gmsh", "-check", sys.argv[1]], capture_output=True, text=True, timeout=60)
assert r.returncode == 0 and "rror" not in r.stdout + r.stderr, r.stdout + r.stderr
PY
if command -v tetgen >/dev/null; then
    expect 0 "bpm-mesh to .msh" -- "$tools/bpm-mesh" "$work/octa.bpm" -o "$work/octa.msh" -q
    expect 0 "read the boundary of the tet mesh back" -- "$tools/bpm-simplify" "$work/octa.msh" -o "$work/tb.bpm" \
        --ratio 0.99 --drop-unreferenced-vertices -q
    expect 0 "surface of it" -- "$tools/bpm-refine" "$work/tb.bpm" --levels 0 -o "$work/tb.obj" -q
    ok "tet mesh .msh round trip keeps patches 0 and 1" -- \
        test "$(grep '^g ' "$work/tb.obj" | sort -u | tr '\n' ' ')" = "g patch_0 g patch_1 "
fi
# A file that says patch = tag - 1 but has a triangle tagged 0 is refused, naming the file.
sed 's/^\(2 1 2 [0-9]*\)$/\1/' "$work/fine.msh" | /usr/bin/python3 -c '
import sys
lines = sys.stdin.read().split("\n")
e = lines.index("$Entities")
f = lines[e + 2].split(); f[8] = "0"; lines[e + 2] = " ".join(f)
sys.stdout.write("\n".join(lines))' >"$work/bad.msh"
expect 3 "a triangle tagged below the \$BpmPatchIds offset" -- "$tools/bpm-simplify" "$work/bad.msh" -o "$work/x.bpm" --ratio 0.5
contains "$work/err" "BpmPatchIds" "the error names the section"
finish
