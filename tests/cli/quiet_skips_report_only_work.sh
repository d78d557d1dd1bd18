#!/usr/bin/env bash
# -q shows no info line, so bpm-simplify does not measure what only its summary line says
# (phi's distortion: bpm-check's distortion check over every piece, ~1 % of a run). With
# -q -v the phase times (debug lines) still show which phases ran: "distortion of phi
# (report)" is not among them, while without -q it is, and the summary line says it. The
# listing leaves out phases under 0.5 ms: armadillo with its 52k pieces (0.014 s for the
# check, 0.4 s for the run; 1000 vertices removed) shows it far above that, eight.off does not.
# Usage: quiet_skips_report_only_work.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"

mesh=$src/.data/meshes/armadillo.off
if [ ! -f "$mesh" ]; then
    echo "skipped: needs .data/meshes/armadillo.off (scripts/fetch_meshes.sh)"
    exit 1
fi
simplify() { "$tools/bpm-simplify" "$mesh" -o "$work/out.bpm" --vertices 25000 --deterministic "$@"; }

expect 0 "simplify -q" -- simplify -q
ok "-q prints nothing on standard error" -- test ! -s "$work/err"

expect 0 "simplify -q -v" -- simplify -q -v
# If -q ever hides the phase times too, this test no longer sees the phases: say so.
contains "$work/err" "time: total (from reading)" "-q -v lists the phase times"
ok "-q: phi's distortion is not measured for the summary line nobody sees" -- \
    bash -c '! grep -qF "distortion of phi (report)" "$1"' _ "$work/err"

expect 0 "simplify -v" -- simplify -v
contains "$work/err" "distortion of phi (report)" "without -q the summary's distortion is measured"
contains "$work/err" "phi turns pieces by up to" "and the summary line reports it"
# "(136 > 90)" read as a comparison; the count says what it counts.
ok "the summary counts the pieces turned over 90 degrees in words" -- \
    grep -qE "phi turns pieces by up to [0-9.e+-]+ degrees \([0-9]+ pieces over 90\)" "$work/err"
finish
