#!/usr/bin/env bash
# Each --levels quadruples bpm-refine's output: '--levels 8' on a coarse surface of 564
# triangles is 37 million triangles, minutes of work and gigabytes of memory and output,
# and nothing said so before it started. Now a warning gives the count first. The run is
# then stopped (SIGTERM): it must leave no output file.
# Usage: refine_warns_before_huge_output.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
mesh="$src/.data/meshes/elephant.off"
expect 0 "simplify" -- "$tools/bpm-simplify" "$mesh" -o "$work/e.bpm" --ratio 0.1 -q

"$tools/bpm-refine" "$work/e.bpm" --levels 8 -o "$work/huge.vtu" 2>"$work/huge.err" &
pid=$!
for _ in $(seq 100); do
    grep -q "million triangles" "$work/huge.err" && break
    sleep 0.2
done
kill -TERM "$pid" 2>/dev/null
wait "$pid"
status=$?
contains "$work/huge.err" "--levels 8 makes 37 million triangles (564 coarse triangles, 4^8 each)" \
    "the warning gives the size before the work"
ok "stopped by SIGTERM (exit 143)" -- test "$status" -eq 143
ok "no output file is left" -- test ! -e "$work/huge.vtu"

# Ordinary sizes say nothing.
expect 0 "refine 2 levels" -- "$tools/bpm-refine" "$work/e.bpm" --levels 2 -o "$work/small.off"
ok "no size warning" -- sh -c "! grep -q 'million triangles' '$work/err'"
finish
