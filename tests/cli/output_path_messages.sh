#!/usr/bin/env bash
# An output path that cannot be a file name got messages about something else:
# '-o outdir/' and '-o outdir' said "'' does not end in .bpm" (bpm-simplify, bpm-smooth) or
# "unknown output format ''" (bpm-refine), '-o .bpm' said "'.bpm' does not end in .bpm",
# and '-o refined' (no extension) "unknown output format ''".
# Usage: output_path_messages.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
mesh="$src/.data/meshes/elephant.off"
mkdir -p "$work/outdir"
expect 0 "simplify" -- "$tools/bpm-simplify" "$mesh" -o "$work/e.bpm" --ratio 0.3 -q

for out in "$work/outdir/" "$work/outdir"; do
    expect 4 "simplify -o $out" -- "$tools/bpm-simplify" "$mesh" -o "$out" --ratio 0.3
    contains "$work/err" "is a directory: -o names the output file (e.g. $work/outdir/NAME.EXT)" \
        "simplify -o $out: says it is a directory"
    expect 4 "smooth -o $out" -- "$tools/bpm-smooth" "$work/e.bpm" -o "$out"
    contains "$work/err" "is a directory: -o names the output file" "smooth -o $out: says it is a directory"
    expect 4 "refine -o $out" -- "$tools/bpm-refine" "$work/e.bpm" --levels 1 -o "$out"
    contains "$work/err" "is a directory: -o names the output file" "refine -o $out: says it is a directory"
    expect 4 "mesh -o $out" -- "$tools/bpm-mesh" "$work/e.bpm" -o "$out"
    contains "$work/err" "is a directory: -o names the output file" "mesh -o $out: says it is a directory"
done
ok "nothing was written into the directory" -- test -z "$(ls -A "$work/outdir")"

expect 2 "simplify -o .bpm" -- "$tools/bpm-simplify" "$mesh" -o "$work/.bpm" --ratio 0.3
contains "$work/err" "'.bpm' has no name before the extension (e.g. -o coarse.bpm)" "-o .bpm: says what is missing"
expect 2 "simplify -o ''" -- "$tools/bpm-simplify" "$mesh" -o "" --ratio 0.3
contains "$work/err" "--output: the file name is empty" "-o '': says it is empty"
expect 2 "refine -o refined (no extension)" -- "$tools/bpm-refine" "$work/e.bpm" --levels 1 -o "$work/refined"
contains "$work/err" "cannot tell the format from '$work/refined' (no extension)" "no extension: says so"
finish
