#!/usr/bin/env bash
# Faults (issue 7: never lose data or write a half file):
#   (a) SIGKILL: bpm-simplify on a large input (femur, Loop-subdivided once) writing over a
#       valid previous result is killed early, mid-way, while the output is being written
#       (caught by watching the bytes it has written) and late. Afterwards the output is byte for
#       byte either the previous file or the complete new one. Nothing else may appear
#       but, in the instant between naming and renaming it, the temporary file
#       .NAME.tmpXXXXXXXX (hidden, never *.bpm; libbpm/src/core/file_util.h), removed here.
#   (b) Unwritable output, for every tool that writes (bpm-simplify, bpm-smooth, bpm-refine
#       to .bpm/.off/.vtu, bpm-mesh to .bpm/.msh): a read-only directory (a read-only tmpfs
#       when root, else a chmod 555 directory), a full disk (an LD_PRELOAD shim that fails
#       write() with ENOSPC, tests/cli/lib/enospc.c, and when root also a tiny tmpfs) and
#       a directory as output: exit 4, one error line naming the output, the previous
#       output untouched, nothing else left behind.
#   (c) Determinism: the same input and options give byte-identical output, twice, for
#       every tool and output format.
# Usage: faults.sh TOOL_DIR SOURCE_DIR WORK_DIR
for m in "$3"/ro "$3"/tiny; do mountpoint -q "$m" 2>/dev/null && umount "$m"; done
source "$(dirname "$0")/lib/harness.bash"

meshes=$src/.data/meshes
example=$src/spec/examples/two_triangles.bpm
mounted=()
cleanup() {
    for m in "${mounted[@]}"; do umount "$m" 2>/dev/null; done
}
trap cleanup EXIT

fail() {
    failures=$((failures + 1))
    echo "FAILED: $1"
}

if [ ! -f "$meshes/femur.off" ] || [ ! -f "$meshes/eight.off" ]; then
    echo "SKIPPED: no test meshes in $meshes (scripts/setup.sh unpacks them)"
    finish
    exit
fi

# Small inputs for (b) and (c): a closed surface and its parametrization.
small_off=$meshes/eight.off
small=$work/eight.bpm
expect 0 "make the small input" -- "$tools/bpm-simplify" "$small_off" -o "$small" --ratio 0.4 --deterministic -q

# ---- (a) SIGKILL -------------------------------------------------------------------------
big=$work/femur1.off
if /usr/bin/python3 "$src/bench/make_subdivided.py" "$meshes/femur.off" 1 "$big" >/dev/null 2>&1; then
    k=$work/kill
    mkdir -p "$k"
    args=(--ratio 0.8 --deterministic -q)
    # The complete new result (deterministic, so every finished run writes these bytes),
    # made under the same output name as the killed runs (the name is in the provenance).
    t0=$(date +%s%N)
    "$tools/bpm-simplify" "$big" -o "$k/out.bpm" "${args[@]}"
    t1=$(date +%s%N)
    mv "$k/out.bpm" "$work/new.bpm"
    full_ms=$(((t1 - t0) / 1000000))
    echo "reference run: $full_ms ms, $(stat -c %s "$work/new.bpm") bytes"
    expect 0 "the new result passes bpm-check" -- "$tools/bpm-check" "$work/new.bpm"

    # kill_run WHEN: WHEN is a delay in ms, or "write" (kill as soon as the temporary file
    # appears). Checks what is left in $k.
    kill_run() {
        local when=$1
        cp "$example" "$k/out.bpm"  # the previous result
        "$tools/bpm-simplify" "$big" -o "$k/out.bpm" "${args[@]}" &
        local pid=$! caught=""
        if [ "$when" = write ]; then
            # Sleep through half of the run, then watch the bytes it has written
            # (/proc/PID/io, read with builtins only, so the loop is fast): with -q the
            # tool writes nothing but its output, so it is killed right after the write()
            # of the output, while it flushes it to disk and renames it into place.
            sleep "$(awk -v ms="$full_ms" 'BEGIN { printf "%.3f", ms * 0.5 / 1000 }')"
            local io=()
            while kill -0 "$pid" 2>/dev/null && mapfile -t io <"/proc/$pid/io" 2>/dev/null; do
                if [[ ${io[1]:-} == "wchar: "* ]] && [ "${io[1]#wchar: }" -gt 0 ]; then
                    kill -9 "$pid" 2>/dev/null
                    caught=yes
                    break
                fi
            done
        else
            sleep "$(awk -v ms="$when" 'BEGIN { printf "%.3f", ms / 1000 }')"
            kill -9 "$pid" 2>/dev/null
        fi
        wait "$pid" 2>/dev/null
        local status=$? result
        if cmp -s "$k/out.bpm" "$example"; then
            result="the previous file"
        elif cmp -s "$k/out.bpm" "$work/new.bpm"; then
            result="the complete new file"
        else
            fail "killed at $when: $k/out.bpm is neither the previous nor the complete new file"
            result="BROKEN"
        fi
        local leftovers=0 other=""
        for f in "$k"/.[!.]* "$k"/*; do
            [ -e "$f" ] || continue
            case $(basename "$f") in
                out.bpm) ;;
                .out.bpm.tmp[0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f]) leftovers=$((leftovers + 1)); rm -f "$f" ;;
                *) other="$other $(basename "$f")" ;;
            esac
        done
        [ -z "$other" ] || fail "killed at $when: unexpected files left:$other"
        [ "$result" = BROKEN ] || [ -n "$other" ] || passes=$((passes + 1))
        echo "killed at $when${caught:+ (while writing its output)} (exit $status): output is $result; $leftovers temporary file(s) left"
        [ "$when" != write ] || [ -n "$caught" ] || echo "  (the run finished before it was seen writing)"
    }
    kill_run 30                        # reading the input
    kill_run $((full_ms * 2 / 10))     # simplifying
    kill_run $((full_ms * 6 / 10))
    kill_run write                     # writing
    kill_run $((full_ms * 97 / 100))   # around the rename
else
    echo "SKIPPED (a): cannot make the subdivided femur (needs /usr/bin/python3 with numpy)"
fi

# ---- (b) unwritable output ---------------------------------------------------------------
# writers DIR: the command lines of every tool that writes, output into DIR.
writers() {
    local d=$1
    printf '%s\n' \
        "bpm-simplify $small_off -o $d/out.bpm --ratio 0.4 -q" \
        "bpm-smooth $small -o $d/out.bpm -q" \
        "bpm-refine $small -o $d/out.bpm --levels 1 -q" \
        "bpm-refine $small -o $d/out.off --levels 1 -q" \
        "bpm-refine $small -o $d/out.vtu --levels 1 -q" \
        "bpm-mesh $small -o $d/out.bpm -q" \
        "bpm-mesh $small -o $d/out.msh -q"
}

# unwritable KIND DIR [PREFIX...]: every writer into DIR (which is unwritable in some
# way) exits 4 with one error line naming its output, and DIR is unchanged afterwards.
# PREFIX: a command to run the tool with (env, setpriv).
unwritable() {
    local kind=$1 d=$2
    shift 2
    local before line tool
    while read -r line; do
        tool=${line%% *}
        local outfile
        outfile=$(awk '{ for (i = 1; i < NF; ++i) if ($i == "-o") print $(i + 1) }' <<<"$line")
        before=$(cd "$d" && ls -A | sort | xargs -r md5sum 2>/dev/null; ls -A "$d")
        # shellcheck disable=SC2086
        "$@" "$tools/"$line >"$work/stdout" 2>"$work/stderr"
        local got=$?
        local after
        after=$(cd "$d" && ls -A | sort | xargs -r md5sum 2>/dev/null; ls -A "$d")
        if [ "$got" -ne 4 ]; then
            fail "$kind: $line: exit $got, expected 4"
            sed 's/^/  stderr: /' "$work/stderr" | head -3
        elif [ "$(wc -l <"$work/stderr")" -ne 1 ] || ! grep -qF "$tool: error: $outfile: " "$work/stderr"; then
            fail "$kind: $line: expected one line '$tool: error: $outfile: ...'"
            sed 's/^/  stderr: /' "$work/stderr" | head -3
        elif [ "$before" != "$after" ]; then
            fail "$kind: $line: the output directory changed: $(ls -A "$d" | tr '\n' ' ')"
        else
            passes=$((passes + 1))
        fi
    done < <(writers "$d")
}

# Read-only directory.
ro=$work/ro
mkdir -p "$ro"
if [ "$(id -u)" -eq 0 ] && mount -t tmpfs -o ro,size=1m tmpfs "$ro" 2>/dev/null; then
    mounted+=("$ro")
    echo "read-only output directory: a read-only tmpfs"
    unwritable "read-only tmpfs" "$ro"
elif [ "$(id -u)" -ne 0 ]; then
    chmod 555 "$ro"
    echo "read-only output directory: chmod 555"
    unwritable "read-only directory" "$ro"
    chmod 755 "$ro"
elif command -v setpriv >/dev/null && setpriv --reuid=65534 --regid=65534 --clear-groups true 2>/dev/null; then
    chmod 555 "$ro"
    echo "read-only output directory: chmod 555, tools run as uid 65534 (setpriv)"
    unwritable "read-only directory" "$ro" setpriv --reuid=65534 --regid=65534 --clear-groups
else
    echo "SKIPPED: read-only directory (root without mount or setpriv: chmod does not stop root)"
fi

# Full disk through the LD_PRELOAD shim, with a previous output in place.
shim=$work/enospc.so
if command -v cc >/dev/null && cc -shared -fPIC -o "$shim" "$src/tests/cli/lib/enospc.c" -ldl 2>"$work/cc.err"; then
    full=$work/full
    mkdir -p "$full"
    for ext in bpm off vtu msh; do cp "$example" "$full/out.$ext"; done  # "previous outputs"
    echo "full disk: LD_PRELOAD shim (write() fails with ENOSPC after 4096 bytes)"
    unwritable "full disk (shim)" "$full" env LD_PRELOAD="$shim" BPM_TEST_ENOSPC_DIR="$full" \
        ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0"
    grep -q "No space left on device" "$work/stderr" || fail "full disk (shim): the message does not say 'No space left on device'"
else
    echo "SKIPPED: full disk through the shim (cannot compile tests/cli/lib/enospc.c: $(head -1 "$work/cc.err" 2>/dev/null))"
fi

# Full disk for real: a 16 KB tmpfs (root only).
tiny=$work/tiny
mkdir -p "$tiny"
if [ "$(id -u)" -eq 0 ] && mount -t tmpfs -o size=16k tmpfs "$tiny" 2>/dev/null; then
    mounted+=("$tiny")
    printf 'previous\n' >"$tiny/out.bpm"
    echo "full disk: a 16 KB tmpfs"
    unwritable "full tmpfs" "$tiny"
else
    echo "SKIPPED: full disk on a tiny tmpfs (needs root and mount)"
fi

# A directory where the output file should go.
mkdir -p "$work/isdir/out.bpm"
expect 4 "output is a directory" -- "$tools/bpm-smooth" "$small" -o "$work/isdir/out.bpm"
contains "$work/err" "bpm-smooth: error: $work/isdir/out.bpm: is a directory" "directory output message"

# ---- (c) determinism ---------------------------------------------------------------------
det=$work/det
mkdir -p "$det"
twice() {  # twice OUTPUT TOOL ARGS...: two runs to the same name give the same bytes
    local output=$1 tool=$2
    shift 2
    if ! "$tools/$tool" "$@" -o "$output" --deterministic -q 2>"$work/stderr"; then
        fail "determinism: $tool $* -o $output failed: $(head -1 "$work/stderr")"
        return
    fi
    mv "$output" "$output.first"
    "$tools/$tool" "$@" -o "$output" --deterministic -q 2>"$work/stderr"
    if cmp -s "$output" "$output.first"; then
        passes=$((passes + 1))
    else
        fail "determinism: $tool $* -o $output: two runs differ ($(cmp "$output" "$output.first" | head -1))"
    fi
}
twice "$det/simplify.bpm" bpm-simplify "$small_off" --ratio 0.4
twice "$det/steps.bpm" bpm-simplify "$small_off" --ratio 0.4 --record-steps
twice "$det/smooth.bpm" bpm-smooth "$small"
twice "$det/refine.bpm" bpm-refine "$small" --levels 1
twice "$det/refine.off" bpm-refine "$small" --levels 2
twice "$det/refine.vtu" bpm-refine "$small" --max-error 0.001 --data
twice "$det/mesh.bpm" bpm-mesh "$small"
twice "$det/mesh.msh" bpm-mesh "$small" --refine 1
twice "$det/volume.vtu" bpm-refine "$det/mesh.bpm" --volume --levels 1

finish
