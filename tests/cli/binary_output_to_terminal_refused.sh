#!/usr/bin/env bash
# `-o -` with standard output on a terminal must not dump binary data (HDF5 .bpm, binary
# STL/PLY, --binary or --compress MSH/VTU) onto it: exit 2 before any work, naming a file or a pipe, as gzip does. Text
# formats still go to the terminal, and a pipe still gets the binary data.
# Usage: binary_output_to_terminal_refused.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
if ! command -v script >/dev/null; then
    echo "skipped: needs script(1) (util-linux) for a terminal"
    exit 1
fi
# on_terminal CMD...: runs CMD with stdout (and stderr) on a pseudo-terminal; exit status kept.
on_terminal() {
    script -qec "$(printf '%q ' "$@")" /dev/null
}
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$work/tet.off"
expect 0 "simplify a tetrahedron" -- "$tools/bpm-simplify" "$work/tet.off" -o "$work/tet.bpm" --vertices 4 -q

expect 2 "bpm-simplify -o - on a terminal" -- on_terminal "$tools/bpm-simplify" "$work/tet.off" -o - --vertices 4
contains "$work/out" "to the terminal" "bpm-simplify says why"
contains "$work/out" "pipe" "bpm-simplify names a pipe"
ok "no HDF5 bytes on the terminal" -- bash -c "! grep -qa $'\\x89HDF' '$work/out'"
expect 2 "bpm-smooth -o - on a terminal" -- on_terminal "$tools/bpm-smooth" "$work/tet.bpm" -o -
contains "$work/out" "to the terminal" "bpm-smooth says why"
expect 2 "bpm-refine -o - .bpm on a terminal" -- on_terminal "$tools/bpm-refine" "$work/tet.bpm" --levels 1 -o - --output-format bpm
contains "$work/out" "to the terminal" "bpm-refine (.bpm) says why"
expect 2 "bpm-refine -o - binary STL on a terminal" -- on_terminal "$tools/bpm-refine" "$work/tet.bpm" --levels 1 -o - --output-format stl
contains "$work/out" "binary stl" "bpm-refine (.stl) says why"
expect 2 "bpm-refine -o - --binary VTU on a terminal" -- on_terminal "$tools/bpm-refine" "$work/tet.bpm" --levels 1 -o - --output-format vtu --binary
contains "$work/out" "binary vtu data" "bpm-refine (--binary .vtu) says why"
expect 2 "bpm-refine -o - --compress VTU on a terminal" -- on_terminal "$tools/bpm-refine" "$work/tet.bpm" --levels 1 -o - --output-format vtu --compress
contains "$work/out" "compressed VTU data" "bpm-refine (--compress) says why"
expect 2 "bpm-mesh -o - --binary MSH on a terminal" -- on_terminal "$tools/bpm-mesh" "$work/tet.bpm" -o - --output-format msh --binary
contains "$work/out" "binary msh data" "bpm-mesh (--binary .msh) says why"
# The hint named "-o out.bpm" whatever the output format: a .msh user was sent to .bpm.
ok "bpm-mesh (--binary .msh) names no .bpm file to write instead" -- bash -c "! grep -q 'out.bpm' '$work/out'"
expect 0 "bpm-refine -o - --binary VTU into a pipe still works" -- bash -c "'$tools/bpm-refine' '$work/tet.bpm' --levels 1 -o - --output-format vtu --binary -q | cat > '$work/piped.vtu'"
contains "$work/piped.vtu" "AppendedData" "the piped VTU is binary"
expect 2 "bpm-mesh -o - (.bpm) on a terminal" -- on_terminal "$tools/bpm-mesh" "$work/tet.bpm" -o -
contains "$work/out" "to the terminal" "bpm-mesh says why"

expect 0 "bpm-refine -o - as OFF text on a terminal is fine" -- on_terminal "$tools/bpm-refine" "$work/tet.bpm" --levels 1 -o - --output-format off -q
contains "$work/out" "OFF" "the OFF text reaches the terminal"
expect 0 "bpm-simplify -o - into a pipe still works" -- bash -c "'$tools/bpm-simplify' '$work/tet.off' -o - --vertices 4 -q | cat > '$work/piped.bpm'"
expect 0 "the piped file is a valid .bpm" -- "$tools/bpm-check" "$work/piped.bpm"
finish
