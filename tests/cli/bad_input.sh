#!/usr/bin/env bash
# Malformed input through every tool that reads it (issue 7: never crash, hang, lose data
# or write a half file):
#   * every file of tests/data/bad/bpm/ (EXPECTED.tsv there) through bpm-check,
#     bpm-smooth, bpm-refine and bpm-mesh;
#   * every surface file of tests/data/bad/ (EXPECTED.tsv there) through bpm-simplify and
#     bpm-check --surface;
#   * option errors, which must exit 2 before the input is even read.
# For each run: the expected exit code; for an error exactly one line on stderr,
# "TOOL: error: FILE: ..." naming the file, with the expected text; no crash (signal or
# exit 70); no file left behind in the (empty) output directory; memory bounded
# (ulimit -v, or ASan's hard_rss_limit_mb in a sanitized build, where ulimit -v cannot work).
# Usage: bad_input.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"

bad=$src/tests/data/bad
out=$work/out-dir
memory_kb=2000000  # 2 GB of address space: the inputs are a few KB
# GCC links the ASan runtime as libasan.so, clang into the program: look for its entry point.
if grep -qa __asan_init "$tools/bpm-check"; then
    export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}hard_rss_limit_mb=1024"
    memory_kb=unlimited
fi

# fail MESSAGE: one failed check, with the last run's output.
fail() {
    failures=$((failures + 1))
    echo "FAILED: $1"
    sed 's/^/  stdout: /' "$work/stdout" | head -5
    sed 's/^/  stderr: /' "$work/stderr" | head -5
}

# The checks of a run use shell builtins, not grep/ls/wc/head: the script makes about 650
# runs, and on a loaded 2-core machine each helper process cost ~13 ms (2-3 minutes of
# the test's time went to them, more than to the tools).
shopt -s nullglob dotglob
mkdir -p "$out"
# empty_out: makes $out an empty directory (it only has files after a tool wrote some).
empty_out() {
    local left=("$out"/*)
    [ ${#left[@]} -eq 0 ] || rm -rf -- "${left[@]}"
}
# list_out: sets $left to the names of the files in $out, space-separated ("" if none);
# a variable, not output, so that the caller needs no subshell.
list_out() {
    local names=("$out"/*)
    names=("${names[@]##*/}")
    left="${names[*]}"
}

# run_tool CODES FILE TEXT TOOL ARGS...: runs TOOL ARGS (FILE among them) with an empty
# output directory $out and checks the outcome. CODES: allowed exit codes, e.g. "3" or
# "0,5". TEXT: what the error line (exit 2..6) or, for bpm-check's exit 1, the report must
# contain ("*": anything).
run_tool() {
    local codes=$1 file=$2 text=$3 tool=$4
    shift 4
    empty_out
    (ulimit -v "$memory_kb"; exec timeout 120 "$tools/$tool" "$@") >"$work/stdout" 2>"$work/stderr"
    local got=$?
    local what="$tool $* (file ${file##*/})"
    if ! [[ ",$codes," == *",$got,"* ]]; then
        fail "$what: exit $got, expected $codes"
        return
    fi
    passes=$((passes + 1))
    local left
    list_out
    if [ "$got" -ne 0 ] && [ -n "$left" ]; then
        fail "$what: exit $got left files behind: $left"
    elif [ "$got" -eq 0 ] && [[ " $left " == *.tmp* ]]; then
        fail "$what: temporary files left behind: $left"
    fi
    if [ "$got" -eq 0 ] || [ "$got" -eq 1 ] || [ "$got" -eq 5 ]; then
        # 0 and 5 (algorithm) may log; 1 is bpm-check's report on stdout
        if [ "$got" -eq 1 ] && [ "$text" != "*" ]; then
            local report=""
            IFS= read -r -d '' report <"$work/stdout"
            [[ "$report" == *"$text"* ]] || fail "$what: the report does not contain '$text'"
        fi
        return
    fi
    local lines=()
    mapfile -t lines <"$work/stderr"
    local line=${lines[0]-}
    if [ ${#lines[@]} -ne 1 ]; then
        fail "$what: ${#lines[@]} lines on stderr, expected exactly one error line"
    elif [[ "$line" != "$tool: error: $file: "* ]]; then
        fail "$what: the error line does not start with '$tool: error: $file: '"
    elif [ "$text" != "*" ] && [[ "$line" != *"$text"* ]]; then
        fail "$what: the error line does not contain '$text'"
    fi
}

# ---- malformed .bpm files -----------------------------------------------------------------
bpm_files=0
while IFS=$'\t' read -r name check_code other_codes text; do
    case $name in '#'* | '') continue ;; esac
    file=$bad/bpm/$name
    [ -e "$file" ] || { fail "$name is listed in EXPECTED.tsv but missing"; continue; }
    bpm_files=$((bpm_files + 1))
    run_tool "$check_code" "$file" "$text" bpm-check "$file"
    # The other tools: exit 3 with the same message; on files that read but fail a check,
    # they may work or refuse (exit 0 or 5), but never crash.
    other_text=$text
    [ "$check_code" -eq 3 ] || other_text="*"
    run_tool "$other_codes" "$file" "$other_text" bpm-smooth "$file" -o "$out/smooth.bpm" --deterministic -q
    run_tool "$other_codes" "$file" "$other_text" bpm-refine "$file" -o "$out/refined.off" --levels 1 -q
    run_tool "$other_codes" "$file" "$other_text" bpm-mesh "$file" -o "$out/mesh.msh" -q
done <"$bad/bpm/EXPECTED.tsv"
# Every file of the corpus has an expectation.
declare -A expected_bpm=()
while IFS=$'\t' read -r name _; do expected_bpm[$name]=1; done <"$bad/bpm/EXPECTED.tsv"
for file in "$bad"/bpm/*.bpm; do
    [ -n "${expected_bpm[${file##*/}]-}" ] || fail "${file##*/} has no line in EXPECTED.tsv"
done
ok "at least 50 malformed .bpm files" -- test "$bpm_files" -ge 50

# Standard input: the message names <stdin>.
run_stdin() {
    local file=$1 text=$2
    rm -rf "$out"
    mkdir -p "$out"
    (ulimit -v "$memory_kb"; exec timeout 120 "$tools/bpm-smooth" - -o "$out/s.bpm") <"$file" >"$work/stdout" 2>"$work/stderr"
    local got=$?
    if [ "$got" -ne 3 ]; then
        fail "bpm-smooth - <$(basename "$file"): exit $got, expected 3"
    elif [ "$(wc -l <"$work/stderr")" -ne 1 ] || ! grep -qF "bpm-smooth: error: <stdin>: $text" "$work/stderr"; then
        fail "bpm-smooth - <$(basename "$file"): expected the one line 'bpm-smooth: error: <stdin>: $text...'"
    elif [ -n "$(ls -A "$out")" ]; then
        fail "bpm-smooth - <$(basename "$file"): left files behind"
    else
        passes=$((passes + 1))
    fi
}
run_stdin "$bad/bpm/truncated_4k.bpm" "cannot open as HDF5"
run_stdin "$bad/bpm/hdf5_crash_local_heap_size.bpm" "the HDF5 library crashed reading it"
run_stdin "$bad/bpm/empty.bpm" "empty input"

# The crash isolation itself, without relying on one particular HDF5 bug: the test hook
# makes the child that parses the file die from SIGSEGV.
BPM_TEST_ISOLATED_CRASH=11 run_tool 3 "$src/spec/examples/two_triangles.bpm" \
    "the HDF5 library crashed reading it (signal 11" bpm-check "$src/spec/examples/two_triangles.bpm"

# ---- malformed surface files --------------------------------------------------------------
surface_files=0
while IFS=$'\t' read -r name text; do
    case $name in '#'* | '') continue ;; esac
    file=$bad/$name
    surface_files=$((surface_files + 1))
    run_tool 3 "$file" "$text" bpm-simplify "$file" -o "$out/coarse.bpm" --ratio 0.5 -q
    run_tool 3 "$file" "$text" bpm-check --surface "$file"
done <"$bad/EXPECTED.tsv"
ok "at least 100 malformed surface files" -- test "$surface_files" -ge 100

# ---- option errors: exit 2, before the input is read ----------------------------------
# The input is malformed on purpose: a tool that read it before checking its options would
# exit 3, not 2.
garbage=$bad/bpm/garbage.bpm
nan_off=$bad/off_nan.off
usage() {  # usage DESCRIPTION TEXT TOOL ARGS...
    local what=$1 text=$2 tool=$3
    shift 3
    rm -rf "$out"
    mkdir -p "$out"
    timeout 60 "$tools/$tool" "$@" >"$work/stdout" 2>"$work/stderr"
    local got=$?
    if [ "$got" -ne 2 ]; then
        fail "$what: exit $got, expected 2"
    elif ! head -1 "$work/stderr" | grep -qF -- "$tool: error: " || ! head -1 "$work/stderr" | grep -qF -- "$text"; then
        fail "$what: the first stderr line is not '$tool: error: ...$text...'"
    elif [ "$(head -1 "$work/stderr" | wc -c)" -gt 300 ]; then
        fail "$what: the error line is longer than 300 characters"
    elif [ -n "$(ls -A "$out")" ]; then
        fail "$what: left files behind"
    else
        passes=$((passes + 1))
    fi
}
usage "simplify: negative --vertices" "--vertices" bpm-simplify "$nan_off" -o "$out/x.bpm" --vertices -5
usage "simplify: --ratio above 1" "--ratio" bpm-simplify "$nan_off" -o "$out/x.bpm" --ratio 1.5
usage "simplify: no target" "give at least one of" bpm-simplify "$nan_off" -o "$out/x.bpm"
usage "simplify: missing output directory" "directory does not exist" bpm-simplify "$nan_off" -o "$work/no/such/dir/x.bpm" --ratio 0.5
usage "simplify: not a .bpm output" "--output" bpm-simplify "$nan_off" -o "$out/x.off" --ratio 0.5
usage "smooth: negative --iterations" "--iterations" bpm-smooth "$garbage" -o "$out/x.bpm" --iterations -1
usage "smooth: missing output directory" "directory does not exist" bpm-smooth "$garbage" -o "$work/no/such/dir/x.bpm"
usage "smooth: not a .bpm output" "--output" bpm-smooth "$garbage" -o "$out/x.vtu"
usage "refine: negative --levels" "--levels" bpm-refine "$garbage" -o "$out/x.off" --levels -1
usage "refine: negative --max-error" "--max-error" bpm-refine "$garbage" -o "$out/x.off" --max-error -1
usage "refine: unknown output extension" "unknown output format 'xyz'" bpm-refine "$garbage" -o "$out/x.xyz" --levels 1
usage "refine: missing output directory" "directory does not exist" bpm-refine "$garbage" -o "$work/no/such/dir/x.off" --levels 1
usage "refine --volume: surface output" "--output" bpm-refine "$garbage" -o "$out/x.off" --volume --levels 1
usage "mesh: negative --refine" "--refine" bpm-mesh "$garbage" -o "$out/x.msh" --refine -1
usage "mesh: negative --quality" "--quality" bpm-mesh "$garbage" -o "$out/x.msh" --quality -1
usage "mesh: unknown output extension" "cannot tell the format" bpm-mesh "$garbage" -o "$out/x.xyz"
usage "mesh: missing output directory" "directory does not exist" bpm-mesh "$garbage" -o "$work/no/such/dir/x.msh"
usage "check: negative --max-problems" "--max-problems" bpm-check "$garbage" --max-problems -1
usage "check: unknown check" "unknown check" bpm-check "$garbage" --checks format,nonsense
usage "check --surface: unknown format" "--input-format" bpm-check --surface "$nan_off" --input-format xyz

finish
