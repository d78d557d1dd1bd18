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
finish
