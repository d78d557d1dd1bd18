#!/usr/bin/env bash
# Error messages that name the fix: standard input without a format names --input-format
# (a usage error, exit 2); bpm-check on a plain surface file suggests --surface, the other
# .bpm readers bpm-simplify (or bpm-mesh, for bpm-refine --volume); an input
# that needs repairs lists every repair it needs in one message, as the flags to copy
# (two touching per-material surfaces needed two failed runs: duplicate vertices first,
# duplicate triangles only after).
# Usage: hints_name_the_fix.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$work/tet.off"

expect 2 "bpm-simplify from stdin without a format" -- "$tools/bpm-simplify" - -o "$work/a.bpm" --vertices 4 <"$work/tet.off"
contains "$work/err" "add --input-format" "the error names --input-format"
expect 2 "bpm-check --surface from stdin without a format" -- "$tools/bpm-check" --surface - <"$work/tet.off"
contains "$work/err" "add --input-format" "bpm-check names --input-format"
expect 3 "bpm-check on a surface file" -- "$tools/bpm-check" "$work/tet.off"
contains "$work/err" "bpm-check --surface $work/tet.off" "the error suggests --surface"
# The other tools that read a .bpm, given the surface or the tet mesh file a newcomer has at hand,
# say how to make the .bpm they need; a missing file gets no such hint.
for t in bpm-smooth bpm-mesh bpm-info; do
    args=(-o "$work/x.bpm"); [ "$t" = bpm-info ] && args=()
    expect 3 "$t on a surface file" -- "$tools/$t" "$work/tet.off" "${args[@]}"
    contains "$work/err" "make one with bpm-simplify $work/tet.off -o tet.bpm" "$t names bpm-simplify"
done
expect 3 "bpm-refine on a surface file" -- "$tools/bpm-refine" "$work/tet.off" --levels 1 -o "$work/x.off"
contains "$work/err" "make one with bpm-simplify $work/tet.off -o tet.bpm" "bpm-refine names bpm-simplify"
cp "$work/tet.off" "$work/tets.vtu"
expect 3 "bpm-refine --volume on a .vtu" -- "$tools/bpm-refine" "$work/tets.vtu" --volume --levels 1 -o "$work/x.vtu"
contains "$work/err" "the .bpm that bpm-mesh writes" "bpm-refine --volume names bpm-mesh"
expect 3 "bpm-info on a missing .off" -- "$tools/bpm-info" "$work/missing.off"
ok "a missing file gets no hint" -- bash -c "! grep -q 'make one with' '$work/err'"

# Two unit cubes touching at x = 1, one closed surface per material (STL: a triangle soup
# per file, positions shared only across files).
/usr/bin/python3 - "$work/a.stl" "$work/b.stl" <<'PY'
import struct, sys
def cube(x0, path):
    corners = [(x0 + x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = [t for q in quads for t in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]
    with open(path, "wb") as f:
        f.write(b"cube".ljust(80, b" ") + struct.pack("<I", len(tris)))
        for t in tris:
            f.write(struct.pack("<3f", 0, 0, 0))
            for i in t: f.write(struct.pack("<3f", *corners[i]))
            f.write(b"\0\0")
cube(0, sys.argv[1]); cube(1, sys.argv[2])
PY
expect 3 "two touching materials without repairs" -- "$tools/bpm-simplify" "$work/a.stl" "$work/b.stl" -o "$work/ab.bpm" --ratio 0.5
contains "$work/err" "Rerun with: --merge-duplicate-vertices --merge-duplicate-triangles" "both repairs named at once, as flags"
expect 0 "the flags as printed work" -- "$tools/bpm-simplify" "$work/a.stl" "$work/b.stl" -o "$work/ab.bpm" --ratio 0.5 --merge-duplicate-vertices --merge-duplicate-triangles
expect 3 "one repair given: the other still named" -- "$tools/bpm-simplify" "$work/a.stl" "$work/b.stl" -o "$work/ab.bpm" --ratio 0.5 --merge-duplicate-vertices
contains "$work/err" "Rerun with: --merge-duplicate-triangles" "the missing repair is named"
ok "the repair already given is not asked for again" -- bash -c "! grep -q 'Rerun with: --merge-duplicate-vertices' '$work/err'"
# The library names the SimplifyOptions field that blocked a removal; the tool says the flag.
expect 0 "a limit that stops the target" -- "$tools/bpm-simplify" "$2/.data/meshes/femur.off" -o "$work/f.bpm" --vertices 10 --max-error 0.001
contains "$work/err" "geometric error limit (--max-error)" "the blocking limit is named by its flag"
ok "no field name of the library shown" -- bash -c "! grep -q 'max_error' '$work/err'"
finish
