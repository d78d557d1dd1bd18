#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz/) with clang, ASan and UBSan into build-fuzz/
# (scripts/configure-sanitized.sh: the build scripts/test-sanitized.sh uses too) and runs
# each of them for SECONDS (default 30), two at a time on two cores (one core each: a
# target fuzzes as long as alone).
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]      e.g.  scripts/fuzz.sh 600 fuzz_read_bpm
#
# Targets: fuzz_read_off fuzz_read_obj fuzz_read_stl fuzz_read_ply fuzz_read_msh fuzz_read_vtk
# fuzz_read_bpm fuzz_read_vtk_xml fuzz_read_surf fuzz_read_bpm_outline fuzz_read_nifti
# fuzz_read_nrrd fuzz_read_metaimage (default: all). Seeds: small valid files of every format written by
# bpm-fuzz-seeds, the malformed corpora of tests/data/bad/ and spec/examples/, all
# generated or copied into build-fuzz/seeds/ at run time. What a target finds is kept
# in build-fuzz/corpus/TARGET/ (reused by the next run), crashes in
# build-fuzz/artifacts/TARGET/, the full log in build-fuzz/logs/TARGET.log.
# Prints one line per target with its executions, in the order of the targets; exits 1 if
# any target found a crash, leak, timeout or out-of-memory (reproduce with:
# build-fuzz/fuzz/TARGET ARTIFACT).
#
# Environment: BPM_FUZZ_DIR=DIR builds and runs in DIR instead of build-fuzz/ (CI: the
# build-asan/ that scripts/test-sanitized.sh built, so libbpm is compiled once);
# BPM_FUZZ_JOBS=N runs N targets at a time (default: the cores, at most 2);
# BPM_FUZZ_BUILD=0 runs what the directory already holds.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-30}
shift || true
all=(fuzz_read_off fuzz_read_obj fuzz_read_stl fuzz_read_ply fuzz_read_msh fuzz_read_vtk fuzz_read_bpm)
all+=(fuzz_read_vtk_xml fuzz_read_surf fuzz_read_bpm_outline fuzz_read_nifti)
all+=(fuzz_read_nrrd fuzz_read_metaimage)
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")
case $seconds in '' | *[!0-9]*) echo "fuzz: SECONDS must be a whole number, not '$seconds'" >&2; exit 2 ;; esac

build=${BPM_FUZZ_DIR:-build-fuzz}
jobs=$(nproc 2>/dev/null || echo 2)
[ "$jobs" -le 2 ] || jobs=2   # shared machines: never more than 2 compile jobs or fuzzers
parallel=${BPM_FUZZ_JOBS:-$jobs}
case $parallel in '' | *[!0-9]* | 0) echo "fuzz: BPM_FUZZ_JOBS must be a positive whole number, not '$parallel'" >&2; exit 2 ;; esac
# BPM_FUZZ_BUILD=0 runs what the build directory already holds (long runs on a tree that
# others are editing).
if [ "${BPM_FUZZ_BUILD:-1}" != 0 ]; then
    ./scripts/configure-sanitized.sh "$build"
    cmake --build "$build" -j "$jobs" --target "${targets[@]}" bpm-fuzz-seeds >&2
fi

# ---- seed corpora --------------------------------------------------------------------
seeds=$build/seeds
rm -rf "$seeds"
ASAN_OPTIONS=detect_leaks=0 $build/fuzz/bpm-fuzz-seeds "$seeds" >&2
for ext in off obj stl ply msh vtk surf; do
    cp tests/data/bad/*."$ext" "$seeds/$ext/" 2>/dev/null || true
done
cp spec/examples/*.bpm "$seeds/bpm/"
mkdir -p "$seeds/vtk_xml"
cp tests/data/vtk_xml/*.vt[pu] tests/data/bad/*.vt[pu] "$seeds/vtk_xml/"
cp tests/data/bad/bpm/*.bpm "$seeds/bpm/" 2>/dev/null || true

# ---- runs ----------------------------------------------------------------------------
# Memory: no single allocation above 512 MB and at most 1 GB resident, far beyond what
# the small inputs may need (read_bpm: at most ~1100x the file size). malloc() of more
# returns NULL, as under `ulimit -v`: HDF5 (not instrumented, not ours) then fails
# cleanly, as it does in production, while operator new in our code still aborts with
# a report, so an unbounded allocation of ours remains a finding. handle_abort: a stack
# for SIGABRT, which the .bpm targets send to a child that hangs.
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:symbolize=1:allocator_may_return_null=1:max_allocation_size_mb=512:handle_abort=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/tests/fuzz/lsan.supp:print_suppressions=0
# hdf5-skips: inputs on which HDF5 itself crashed (the .bpm targets only; not our code, see
# tests/fuzz/hdf5_child.cpp), saved in build-fuzz/hdf5-crashes/TARGET/.
run_target() {  # TARGET: fuzzes it for $seconds; its exit status is the fuzzer's
    local target=$1 format=${1#fuzz_read_}
    [ "$format" != bpm_outline ] || format=bpm   # bpm-info's reader: the .bpm seeds and dictionary
    local corpus=$build/corpus/$target artifacts=$build/artifacts/$target
    local hdf5_crashes=$build/hdf5-crashes/$target
    mkdir -p "$corpus" "$artifacts" "$hdf5_crashes"
    local dict=()
    [ -f tests/fuzz/$format.dict ] && dict=(-dict=tests/fuzz/$format.dict)
    # One process (no -jobs: that would fork workers logging to ./fuzz-N.log); -timeout:
    # one input may take at most 20 s (a hang is a finding).
    BPM_FUZZ_HDF5_CRASH_DIR=$hdf5_crashes $build/fuzz/$target "$corpus" "$seeds/$format" "${dict[@]}" -max_total_time="$seconds" \
        -timeout=20 -rss_limit_mb=1024 -print_final_stats=1 -artifact_prefix="$artifacts/" >"$build/logs/$target.log" 2>&1
}
report_target() {  # TARGET STATUS: prints its line, adds it to failed
    local target=$1 status=$2 log=$build/logs/$1.log result
    local execs rate skips
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
    skips=$(grep -c '^HDF5 crash skipped' "$log" || true)
    if [ "$status" -eq 0 ]; then
        result=ok
    else
        result="FAILED (exit $status): $(grep -m1 -E '^==[0-9]+== ?ERROR|runtime error:|fuzz property violated|^SUMMARY' "$log" || echo "see $log")"
        failed+=("$target")
    fi
    printf '%-22s %12s %8s %10s  %s\n' "$target" "${execs:-?}" "${rate:-?}" "$skips" "$result"
}
failed=()
pids=()
# Interrupted (Ctrl-C) or stopped by an error: the fuzzers still running go too.
trap 'kill "${pids[@]}" 2>/dev/null || true' EXIT
trap 'exit 130' INT TERM
mkdir -p "$build/logs"
printf '%-22s %12s %8s %10s  %s\n' target executions exec/s hdf5-skips result
# $parallel targets run at once, each in the background with a log of its own; they are
# waited for (and reported) in the order of the list, so the output does not depend on
# which finishes first. All run the same time, so the next one starts when the earliest
# started one ends (one that stops early, on a finding, leaves its core idle until then).
for i in "${!targets[@]}"; do
    if [ "$i" -ge "$parallel" ]; then
        done_i=$((i - parallel))
        status=0
        wait "${pids[done_i]}" || status=$?
        report_target "${targets[done_i]}" $status
    fi
    run_target "${targets[i]}" &
    pids[i]=$!
done
first=$(( ${#targets[@]} > parallel ? ${#targets[@]} - parallel : 0 ))
for ((i = first; i < ${#targets[@]}; i++)); do
    status=0
    wait "${pids[i]}" || status=$?
    report_target "${targets[i]}" $status
done

if [ ${#failed[@]} -gt 0 ]; then
    echo "fuzz: findings in ${failed[*]}; logs in $build/logs/, inputs in $build/artifacts/" >&2
    for target in "${failed[@]}"; do
        echo "---- $target ($build/logs/$target.log) ----" >&2
        grep -A25 -m1 -E '^==[0-9]+==ERROR|runtime error|fuzz property violated|ALARM|out-of-memory' "$build/logs/$target.log" >&2 || tail -30 "$build/logs/$target.log" >&2
    done
    exit 1
fi
echo "fuzz: ${#targets[@]} targets, ${seconds} s each, no findings"
