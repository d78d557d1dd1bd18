#!/usr/bin/env bash
# Outputs are written atomically (a new file renamed over the old one). Renaming over a
# symbolic link replaced the link with a regular file and left its target unchanged, and
# the new file got the default permissions instead of the replaced file's (a chmod 600
# output became world-readable). Now the link is followed and stays a link, and the
# permission bits of the replaced file are kept: what '>' and cp do.
# Usage: output_through_symlink_keeps_link_and_mode.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"

cat >"$work/cube.off" <<'END'
OFF
8 12 0
0 0 0
1 0 0
1 1 0
0 1 0
0 0 1
1 0 1
1 1 1
0 1 1
3 0 2 1
3 0 3 2
3 4 5 6
3 4 6 7
3 0 1 5
3 0 5 4
3 1 2 6
3 1 6 5
3 2 3 7
3 2 7 6
3 3 0 4
3 3 4 7
END
expect 0 "simplify" -- "$tools/bpm-simplify" "$work/cube.off" -o "$work/cube.bpm" --ratio 1 --deterministic -q
expect 0 "refine, written directly" -- "$tools/bpm-refine" "$work/cube.bpm" --levels 1 -o "$work/direct.off" -q

# A link in another directory, relative, to a file that exists: the target is replaced.
mkdir -p "$work/data" "$work/links"
echo old >"$work/data/refined.off"
ln -s ../data/refined.off "$work/links/refined.off"
expect 0 "refine through a relative symlink" -- "$tools/bpm-refine" "$work/cube.bpm" --levels 1 \
    -o "$work/links/refined.off" -q
ok "the link is still a link" -- test -L "$work/links/refined.off"
ok "its target holds the output" -- cmp -s "$work/data/refined.off" "$work/direct.off"

# .bpm outputs (written by HDF5 through the same atomic writer), through a chain of two
# links, one of them absolute; and a dangling link makes its target.
ln -s "$work/data/smooth.bpm" "$work/links/a.bpm"
ln -s a.bpm "$work/links/b.bpm"
expect 0 "smooth through two links to a missing file" -- "$tools/bpm-smooth" "$work/cube.bpm" \
    -o "$work/links/b.bpm" -q
ok "both links are still links" -- test -L "$work/links/b.bpm" -a -L "$work/links/a.bpm"
ok "the missing target was made" -- test -f "$work/data/smooth.bpm"
expect 0 "and reads back" -- "$tools/bpm-check" "$work/links/b.bpm" --checks format

# A link loop is an output error.
ln -s loop2.off "$work/links/loop1.off"
ln -s loop1.off "$work/links/loop2.off"
expect 4 "a symlink loop is an output error" -- "$tools/bpm-refine" "$work/cube.bpm" --levels 1 \
    -o "$work/links/loop1.off" -q
contains "$work/err" "too many levels of symbolic links" "the error says why"

# Permission bits of the replaced file are kept (a private output stays private).
cp "$work/direct.off" "$work/private.off"
chmod 600 "$work/private.off"
expect 0 "refine over a chmod 600 file" -- "$tools/bpm-refine" "$work/cube.bpm" --levels 1 -o "$work/private.off" -q
ok "it is still mode 600" -- test "$(stat -c %a "$work/private.off")" = 600
cp "$work/cube.bpm" "$work/private.bpm"
chmod 640 "$work/private.bpm"
expect 0 "smooth over a chmod 640 .bpm" -- "$tools/bpm-smooth" "$work/cube.bpm" -o "$work/private.bpm" -q
ok "it is still mode 640" -- test "$(stat -c %a "$work/private.bpm")" = 640
finish
