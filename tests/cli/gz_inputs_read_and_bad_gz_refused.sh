#!/usr/bin/env bash
# Every input may be gzip-compressed: FILE.EXT.gz is read as EXT, gzip data on standard
# input (with --input-format) is recognised by its magic bytes, .bpm.gz too. A truncated
# or corrupt .gz, or a .gz name over plain data, is exit 3 with the file and what is
# wrong, never a crash.
# Usage: gz_inputs_read_and_bad_gz_refused.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"

eight=$src/.data/meshes/eight.off
if [ ! -f "$eight" ]; then
    echo "skipped: needs .data/meshes/eight.off (scripts/fetch_meshes.sh)"
    exit 1
fi
gzip -c "$eight" >"$work/eight.off.gz"
simplify() { "$tools/bpm-simplify" "$@" --vertices 100 --deterministic -q; }

expect 0 "plain OFF" -- simplify "$eight" -o "$work/plain.bpm"
expect 0 "FILE.off.gz" -- simplify "$work/eight.off.gz" -o "$work/gz.bpm"
expect 0 "gzip data on standard input with --input-format" -- sh -c "'$tools/bpm-simplify' - --input-format off \
    -o '$work/stdin.bpm' --vertices 100 --deterministic -q <'$work/eight.off.gz'"
# The files differ only in the command line stored as provenance: compare what a refinement makes of them.
for f in plain gz stdin; do
    "$tools/bpm-refine" "$work/$f.bpm" --levels 1 -o "$work/$f.off" -q
done
ok "FILE.off.gz gives the same coarse surface and phi as the plain file" -- cmp -s "$work/plain.off" "$work/gz.off"
ok "so does gzip data on standard input" -- cmp -s "$work/plain.off" "$work/stdin.off"
expect 0 "bpm-check --surface FILE.off.gz" -- "$tools/bpm-check" --surface "$work/eight.off.gz"

gzip -c "$work/plain.bpm" >"$work/plain.bpm.gz"
expect 0 "bpm-check FILE.bpm.gz" -- "$tools/bpm-check" "$work/plain.bpm.gz"
expect 0 "bpm-refine FILE.bpm.gz" -- "$tools/bpm-refine" "$work/plain.bpm.gz" --levels 1 -o "$work/from_gz.off" -q
ok "the same refinement from .bpm.gz" -- cmp -s "$work/plain.off" "$work/from_gz.off"
expect 0 "bpm-smooth FILE.bpm.gz" -- "$tools/bpm-smooth" "$work/plain.bpm.gz" -o "$work/smooth.bpm" -q

# Broken .gz: truncated (an interrupted download), corrupt, plain data under a .gz name.
size=$(stat -c %s "$work/eight.off.gz")
head -c $((size / 2)) "$work/eight.off.gz" >"$work/cut.off.gz"
expect 3 "truncated .off.gz" -- simplify "$work/cut.off.gz" -o "$work/x.bpm"
contains "$work/err" "bpm-simplify: error: $work/cut.off.gz: truncated gzip data" "names the file and says truncated"
ok "no output left behind" -- test ! -e "$work/x.bpm"
head -c $((size - 4)) "$work/eight.off.gz" >"$work/cut_trailer.off.gz"
expect 3 "a .gz without its last 4 bytes" -- simplify "$work/cut_trailer.off.gz" -o "$work/x.bpm"
contains "$work/err" "truncated gzip data" "the missing trailer is a truncation too"
expect 3 "truncated gzip on standard input" -- sh -c "'$tools/bpm-simplify' - --input-format off -o '$work/x.bpm' \
    --vertices 100 <'$work/cut.off.gz'"
contains "$work/err" "<stdin>: truncated gzip data" "standard input is named"
cp "$work/eight.off.gz" "$work/bad.off.gz"
printf 'XXXXXXXXXXXXXXXX' | dd of="$work/bad.off.gz" bs=1 seek=$((size / 2)) conv=notrunc status=none
expect 3 "corrupt .off.gz" -- simplify "$work/bad.off.gz" -o "$work/x.bpm"
contains "$work/err" "$work/bad.off.gz: corrupt gzip data" "names the file and says corrupt"
cp "$eight" "$work/plain.off.gz"
expect 3 "plain data named .gz" -- simplify "$work/plain.off.gz" -o "$work/x.bpm"
contains "$work/err" "is not gzip data" "says it is not gzip data"
head -c 3000 "$work/plain.bpm.gz" >"$work/cut.bpm.gz"
expect 3 "bpm-check on a truncated .bpm.gz" -- "$tools/bpm-check" "$work/cut.bpm.gz"
contains "$work/err" "$work/cut.bpm.gz: truncated gzip data" "bpm-check names it too"
finish
