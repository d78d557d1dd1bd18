#!/usr/bin/env bash
# On a terminal the tools draw progress as "\rstage  42%" on stderr. A stage that ended
# short of 100 % left that line open, and the next output continued it: bpm-check printed
# "distortion of phi   0%PASS format ..." (its report on stdout, the same terminal), and
# warnings were glued to the progress line likewise. Now the open line is erased first.
# Runs the tools under script(1), which gives them a terminal.
# Usage: progress_line_ends_before_output.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
if ! command -v script >/dev/null; then
    echo "skipped: needs script(1) (util-linux)"
    exit 1
fi
mesh="$src/.data/meshes/elephant.off"
expect 0 "simplify" -- "$tools/bpm-simplify" "$mesh" -o "$work/e.bpm" --ratio 0.2 -q

# The terminal's bytes, each "\r" a line break: a progress line and what follows it are
# then on separate lines unless they were glued together.
on_terminal() {
    script -qec "$1" /dev/null | tr '\r' '\n' >"$work/tty"
}
on_terminal "'$tools/bpm-check' '$work/e.bpm'"
contains "$work/tty" "PASS format" "bpm-check's report reached the terminal"
ok "the report starts a line of its own" -- sh -c "! grep -aq '%PASS' '$work/tty'"
ok "every report line starts at the start of a line" -- sh -c \
    "grep -a 'PASS' '$work/tty' | grep -av '^PASS' | grep -q . && exit 1 || exit 0"
on_terminal "'$tools/bpm-info' --distortion '$work/e.bpm'"
ok "bpm-info's report starts a line of its own" -- sh -c "grep -aq '^$work/e.bpm: bpm format' '$work/tty'"
on_terminal "'$tools/bpm-check' '$work/e.bpm' --json"
ok "bpm-check --json: the JSON starts a line of its own" -- sh -c "grep -aq '^{' '$work/tty'"
# bpm-mesh: after TetGen the level-0 improvement (flips, vertices in slivers, surface-corner
# splits, smoothing) took most of the time on noisy label images (noisy 32^3: 13 of 16 s),
# with "reading the tetrahedral mesh  80%" standing still; it reports its stages now.
if command -v tetgen >/dev/null; then
    on_terminal "'$tools/bpm-mesh' '$work/e.bpm' -o '$work/e.tet.bpm'"
    contains "$work/tty" "improving the mesh: flips" "the flips are a stage of their own"
    contains "$work/tty" "improving the mesh: vertices in slivers" "so is the insertion into slivers"
    contains "$work/tty" "smoothing interior vertices" "and the smoothing"
    ok "the smoothing's progress comes after the improvement's (95-99 %, not from 0 %)" -- sh -c \
        "grep -a 'smoothing' '$work/tty' | grep -aqv ' 9[5-9]%' && exit 1 || exit 0"
    ok "bpm-mesh's summary starts a line of its own" -- sh -c "grep -aq '^bpm-mesh: [0-9]* vertices' '$work/tty'"
fi
finish
