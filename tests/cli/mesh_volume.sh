#!/usr/bin/env bash
# Pipeline: bpm-simplify -> bpm-mesh -> bpm-refine --volume on elephant, with exports
# and the error cases of the volume path.
# Usage: mesh_volume.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
elephant=$src/.data/meshes/elephant.off
if [ ! -f "$elephant" ] || ! command -v tetgen >/dev/null; then
    echo "skipped: needs $elephant and tetgen (scripts/setup.sh installs both)"
    exit 1
fi
expect 0 "simplify" -- "$tools/bpm-simplify" "$elephant" -o "$work/e.bpm" --ratio 0.1 -q
expect 0 "mesh into .bpm" -- "$tools/bpm-mesh" "$work/e.bpm" -o "$work/e.tet.bpm" -q
expect 0 "mesh file still passes bpm-check" -- "$tools/bpm-check" "$work/e.tet.bpm"
for ext in msh vtu mesh bpm; do
    expect 0 "volume refinement to .$ext" -- "$tools/bpm-refine" "$work/e.tet.bpm" --volume --levels 1 -o "$work/fine.$ext"
    contains "$work/err" "0 inverted" "no inverted element (.$ext)"
done
expect 0 "refined file passes bpm-check" -- "$tools/bpm-check" "$work/fine.bpm"
# Interior smoothing: on by default, --no-smooth turns it off; boundary vertices are not
# touched, so both give the same volumes, and smoothing never gives a worse minimum angle.
expect 0 "refinement with smoothing, JSON" -- "$tools/bpm-mesh" "$work/e.tet.bpm" --existing --refine 2 -o "$work/s.msh" --json -q
cp "$work/out" "$work/smooth.json"
contains "$work/smooth.json" '"smoothed": true' "smoothing is on by default"
expect 0 "refinement without smoothing, JSON" -- "$tools/bpm-mesh" "$work/e.tet.bpm" --existing --refine 2 --no-smooth -o "$work/n.msh" --json -q
cp "$work/out" "$work/plain.json"
contains "$work/plain.json" '"smoothed": false' "--no-smooth turns it off"
ok "smoothing raises the minimum dihedral angle, no inverted element" -- /usr/bin/python3 -c '
import json, sys
s, n = (json.load(open(f)) for f in sys.argv[1:3])
assert s["inverted"] == 0 and n["inverted"] == 0, (s["inverted"], n["inverted"])
assert s["min_dihedral_degrees"] > n["min_dihedral_degrees"], (s["min_dihedral_degrees"], n["min_dihedral_degrees"])
assert s["below_5_degrees"] <= n["below_5_degrees"], (s["below_5_degrees"], n["below_5_degrees"])
' "$work/smooth.json" "$work/plain.json"
expect 0 "bpm-refine --volume --no-smooth" -- "$tools/bpm-refine" "$work/e.tet.bpm" --volume --levels 1 --no-smooth --remedy-min-dihedral 0 -o "$work/ns.vtu"
contains "$work/err" "0 inverted" "no inverted element without smoothing"
expect 0 "bpm-refine --help documents --no-smooth" -- "$tools/bpm-refine" --help
contains "$work/out" "--no-smooth" "bpm-refine --help lists --no-smooth"
expect 0 "bpm-mesh --help documents --no-smooth" -- "$tools/bpm-mesh" --help
contains "$work/out" "--no-smooth" "bpm-mesh --help lists --no-smooth"
expect 2 "--no-smooth needs --volume" -- "$tools/bpm-refine" "$work/e.tet.bpm" --levels 1 --no-smooth -o "$work/x.off"
expect 2 "remedy angle out of range" -- "$tools/bpm-refine" "$work/e.tet.bpm" --volume --levels 1 --remedy-min-dihedral 90 -o "$work/x.msh"
expect 3 "volume refinement of a file without a mesh" -- "$tools/bpm-refine" "$work/e.bpm" --volume --levels 1 -o "$work/x.msh"
contains "$work/err" "bpm-mesh" "the message says how to get a mesh"
expect 2 "volume refinement needs --levels" -- "$tools/bpm-refine" "$work/e.tet.bpm" --volume --max-error 0.01 -o "$work/x.msh"
expect 2 "volume refinement to a surface format" -- "$tools/bpm-refine" "$work/e.tet.bpm" --volume --levels 1 -o "$work/x.off"
ok "no output after failures" -- test ! -e "$work/x.msh" -a ! -e "$work/x.off"
finish
