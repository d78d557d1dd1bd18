#!/usr/bin/env bash
# With --json, a tool that stops with an error must still print a JSON report on stdout
# (passed/ok false and the error's file, message and exit code), not empty output that
# crashes the CI job parsing it (spec/check-report.md, "Errors").
# Usage: json_report_on_bad_input.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"

# is_error_report FILE KEY CODE ERRORFILE: stdout is one JSON object with KEY false and
# error = {file: ERRORFILE (or null for ""), message non-empty, exit_code: CODE}.
is_error_report() {
    /usr/bin/python3 - "$@" <<'PY'
import json, sys
path, key, code, errfile = sys.argv[1:5]
r = json.load(open(path))
assert r[key] is False, r
e = r["error"]
assert e["exit_code"] == int(code), e
assert e["file"] == (errfile or None), e
assert e["message"], e
PY
}

printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$work/tet.off"
expect 0 "simplify a tetrahedron" -- "$tools/bpm-simplify" "$work/tet.off" -o "$work/tet.bpm" --vertices 4 -q
head -c 3000 "$work/tet.bpm" >"$work/truncated.bpm"

expect 3 "bpm-check --json on a missing file" -- "$tools/bpm-check" "$work/missing.bpm" --json
ok "missing file: JSON report with passed false and the error" -- is_error_report "$work/out" passed 3 "$work/missing.bpm"
contains "$work/err" "cannot open" "the error also goes to stderr"
expect 3 "bpm-check --json on a truncated file" -- "$tools/bpm-check" "$work/truncated.bpm" --json
ok "truncated file: JSON report" -- is_error_report "$work/out" passed 3 "$work/truncated.bpm"
expect 3 "bpm-check --json on a surface file without --surface" -- "$tools/bpm-check" "$work/tet.off" --json
ok "not HDF5: JSON report" -- is_error_report "$work/out" passed 3 "$work/tet.off"
expect 2 "bpm-check --json with an unknown check" -- "$tools/bpm-check" "$work/tet.bpm" --json --checks nonsense
ok "unknown check: JSON report, file null" -- is_error_report "$work/out" passed 2 ""

expect 3 "bpm-info --json on a missing file" -- "$tools/bpm-info" "$work/missing.bpm" --json
ok "bpm-info, missing file: JSON report with ok false and the error" -- is_error_report "$work/out" ok 3 "$work/missing.bpm"
expect 3 "bpm-info --json on a truncated file" -- "$tools/bpm-info" "$work/truncated.bpm" --json
ok "bpm-info, truncated file: JSON report" -- is_error_report "$work/out" ok 3 "$work/truncated.bpm"
expect 3 "bpm-info --json on a surface file" -- "$tools/bpm-info" "$work/tet.off" --json
ok "bpm-info, not HDF5: JSON report" -- is_error_report "$work/out" ok 3 "$work/tet.off"
expect 2 "bpm-info --json with an unknown option" -- "$tools/bpm-info" "$work/tet.bpm" --json --nonsense
ok "bpm-info, unknown option: JSON report, file null" -- is_error_report "$work/out" ok 2 ""
expect 2 "bpm-check --json with an unknown option" -- "$tools/bpm-check" "$work/tet.bpm" --json --nonsense
ok "unknown option: JSON report" -- is_error_report "$work/out" passed 2 ""
expect 0 "bpm-check --json on a good file" -- "$tools/bpm-check" "$work/tet.bpm" --json
ok "good file: no error key, passed true" -- /usr/bin/python3 -c '
import json, sys; r = json.load(open(sys.argv[1])); assert r["passed"] is True and "error" not in r, r' "$work/out"
# (--max-aspect 2: the right triangles of this corner have R/r 2.41; below 2 is refused, exit 2)
expect 1 "bpm-check without --json: a failed check" -- "$tools/bpm-check" "$work/tet.bpm" --max-aspect 2
expect 3 "bpm-check without --json: nothing on stdout" -- "$tools/bpm-check" "$work/missing.bpm"
ok "no JSON without --json" -- test ! -s "$work/out"

expect 3 "bpm-mesh --json on a missing file" -- "$tools/bpm-mesh" "$work/missing.bpm" -o "$work/x.msh" --json
ok "bpm-mesh: JSON report with ok false and the error" -- is_error_report "$work/out" ok 3 "$work/missing.bpm"
expect 2 "bpm-mesh --json with a refused setting" -- "$tools/bpm-mesh" "$work/tet.bpm" -o "$work/x.msh" --json --min-dihedral 40
ok "bpm-mesh refused setting: JSON report" -- is_error_report "$work/out" ok 2 ""
if command -v tetgen >/dev/null; then
    expect 0 "bpm-mesh --json on a good file" -- "$tools/bpm-mesh" "$work/tet.bpm" -o "$work/x.msh" --json -q
    ok "bpm-mesh success: ok true" -- /usr/bin/python3 -c '
import json, sys; r = json.load(open(sys.argv[1])); assert r["ok"] is True and "error" not in r, r' "$work/out"
fi
finish
