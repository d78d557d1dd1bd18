#!/usr/bin/env bash
# bpm-mesh stopped from outside (SIGTERM, SIGINT, timeout, SIGKILL) must leave no TetGen
# process and (except after SIGKILL) no bpm-tetgen-* temporary directory behind; settings
# TetGen does not terminate for are refused up front, and --time-limit stops TetGen with
# a clear error. A stand-in tetgen (a shell script that starts a child and waits) makes the
# timing deterministic; the real tetgen is killed mid-run as well when installed.
# Usage: mesh_killed_leaves_no_tetgen.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
mkdir -p "$work/tmp" "$work/pids"
export TMPDIR=$work/tmp  # where bpm-mesh makes its bpm-tetgen-XXXXXX directory

# A tetrahedron as input: tiny, valid, meshable.
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$work/tet.off"
expect 0 "simplify a tetrahedron" -- "$tools/bpm-simplify" "$work/tet.off" -o "$work/tet.bpm" --vertices 4 -q

# Stand-in tetgen: records its pid and its child's, then waits for the child.
cat >"$work/slow-tetgen" <<SCRIPT
#!/bin/sh
echo \$\$ >"$work/pids/shell.\$\$"
sleep 300 &
echo \$! >"$work/pids/child.\$\$"
wait
SCRIPT
# Stand-in that becomes the long-running process itself (for SIGKILL: PR_SET_PDEATHSIG).
cat >"$work/exec-tetgen" <<SCRIPT
#!/bin/sh
echo \$\$ >"$work/pids/exec.\$\$"
exec sleep 300
SCRIPT
chmod +x "$work/slow-tetgen" "$work/exec-tetgen"

# Waits (up to 10 s) until a stand-in has written a pid file matching $1.
wait_for_pid_file() {
    for _ in $(seq 100); do
        ls "$work/pids/"$1* >/dev/null 2>&1 && return 0
        sleep 0.1
    done
    return 1
}
# A process that exists and is not a zombie (a killed orphan may wait a moment for init).
alive() {
    local state
    state=$(sed 's/^[^)]*) \(.\).*/\1/' "/proc/$1/stat" 2>/dev/null) || return 1
    [ -n "$state" ] && [ "$state" != Z ]
}
# Within 3 s: no recorded pid is alive, and no process has its working directory in $TMPDIR.
no_process_left() {
    local left
    for _ in $(seq 30); do
        left=
        for f in "$work"/pids/*; do
            [ -e "$f" ] && alive "$(cat "$f")" && left="process $(cat "$f") ($(basename "$f"))"
        done
        for p in $(find /proc/[0-9]*/cwd -maxdepth 0 -lname "$work/tmp/*" 2>/dev/null); do
            p=${p#/proc/}
            alive "${p%/cwd}" && left="process ${p%/cwd} running in $work/tmp"
        done
        [ -z "$left" ] && return 0
        sleep 0.1
    done
    echo "  $left still alive"
    return 1
}
no_directory_left() {
    ! ls -d "$work"/tmp/bpm-tetgen-* >/dev/null 2>&1
}
clean() { rm -rf "$work"/pids/* "$work"/tmp/*; }

for sig in TERM HUP; do
    clean
    "$tools/bpm-mesh" "$work/tet.bpm" -o "$work/x.msh" --tetgen "$work/slow-tetgen" 2>"$work/err" &
    mesh=$!
    ok "SIG$sig: the stand-in tetgen started" -- wait_for_pid_file child
    kill -"$sig" "$mesh"
    wait "$mesh"
    status=$?
    ok "SIG$sig: bpm-mesh dies of the signal (status $status)" -- test "$status" -eq $((128 + $(kill -l "$sig")))
    contains "$work/err" "interrupted by SIG$sig" "SIG$sig: the message says why it stopped"
    ok "SIG$sig: no tetgen process left (nor its child)" -- no_process_left
    ok "SIG$sig: no bpm-tetgen-* directory left" -- no_directory_left
done

# The issue's own command: `timeout 4 bpm-mesh ...` (SIGTERM), and Ctrl-C (SIGINT; a
# foreground timeout passes it on, a background job of a script would ignore it).
for sig in TERM INT; do
    clean
    expect 124 "timeout -s $sig stops bpm-mesh" -- timeout -s "$sig" 2 "$tools/bpm-mesh" "$work/tet.bpm" -o "$work/x.msh" --tetgen "$work/slow-tetgen"
    ok "timeout -s $sig: no tetgen process left" -- no_process_left
    ok "timeout -s $sig: no bpm-tetgen-* directory left" -- no_directory_left
done

# SIGKILL cannot be caught: the kernel kills TetGen with its parent (PR_SET_PDEATHSIG).
clean
"$tools/bpm-mesh" "$work/tet.bpm" -o "$work/x.msh" --tetgen "$work/exec-tetgen" 2>/dev/null &
mesh=$!
ok "SIGKILL: the stand-in tetgen started" -- wait_for_pid_file exec
kill -KILL "$mesh"
wait "$mesh" 2>/dev/null
ok "SIGKILL: the tetgen process died with bpm-mesh" -- no_process_left
clean

# --time-limit: TetGen stopped, exit 6, the message names the limit; nothing left behind.
expect 6 "--time-limit stops a TetGen run that takes too long" -- "$tools/bpm-mesh" "$work/tet.bpm" -o "$work/x.msh" --tetgen "$work/slow-tetgen" --time-limit 1
contains "$work/err" "time limit of 1 s" "the error names the time limit"
ok "--time-limit: no tetgen process left" -- no_process_left
ok "--time-limit: no bpm-tetgen-* directory left" -- no_directory_left
ok "no output after the time limit" -- test ! -e "$work/x.msh"
clean

# Non-terminating settings are refused before TetGen runs (it ran for > 9 minutes).
expect 2 "--min-dihedral 30 is refused up front" -- timeout 20 "$tools/bpm-mesh" "$work/tet.bpm" -o "$work/x.msh" --min-dihedral 30 --tetgen "$work/slow-tetgen"
contains "$work/err" "limit of 18 degrees" "the refusal names the limit"
ok "--min-dihedral 30: TetGen never started" -- test -z "$(ls "$work/pids")"
expect 0 "--help shows the dihedral limit and --time-limit" -- "$tools/bpm-mesh" --help
contains "$work/out" "--time-limit" "--help lists --time-limit"
contains "$work/out" "at most 18" "--help names the dihedral limit"

# The real TetGen, killed mid-run (a fine volume bound keeps it busy for many seconds).
elephant=$src/.data/meshes/elephant.off
if command -v tetgen >/dev/null && [ -f "$elephant" ]; then
    expect 0 "simplify elephant" -- "$tools/bpm-simplify" "$elephant" -o "$work/e.bpm" --ratio 0.1 -q
    expect 124 "timeout stops bpm-mesh running the real tetgen" -- timeout 3 "$tools/bpm-mesh" "$work/e.bpm" -o "$work/x.msh" --max-volume 1e-9
    ok "real tetgen: no process left" -- no_process_left
    ok "real tetgen: no bpm-tetgen-* directory left" -- no_directory_left
else
    echo "note: real-tetgen part skipped (needs tetgen and $elephant)"
fi
finish
