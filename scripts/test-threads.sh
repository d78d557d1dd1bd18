#!/usr/bin/env bash
# bpm-simplify built with ThreadSanitizer (in build-tsan/), run on real meshes with 2 and
# 3 threads: no data race may be reported, and the output must equal the one-thread
# output dataset by dataset (the thread count only changes who plans what). CI runs it
# after scripts/test-sanitized.sh; about 5 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
jobs=$(nproc 2>/dev/null || echo 2)
# -g1: line tables are enough for the race reports, and compile faster.
cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DBPM_BUILD_TESTS=OFF -DBPM_BUILD_BENCH=OFF \
    -DCMAKE_CXX_FLAGS="-fsanitize=thread" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread" >/dev/null
cmake --build build-tsan --target bpm-simplify -j "$jobs" >&2
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
export TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1
status=0
for run in "femur --ratio 0.1" "fandisk --vertices 1000" "mech-holes-shark --ratio 0.1"; do
    set -- $run
    mesh=$1
    shift
    for threads in 1 2 3; do
        build-tsan/bin/bpm-simplify ".data/meshes/$mesh.off" -o "$out/$mesh-$threads.bpm" "$@" \
            --threads "$threads" --deterministic -q
    done
    for threads in 2 3; do
        # Every dataset but the recorded command line (it names the thread count).
        if ! /usr/bin/python3 - "$out/$mesh-1.bpm" "$out/$mesh-$threads.bpm" <<'EOF'; then
import sys
import h5py
import numpy as np
a, b = h5py.File(sys.argv[1], "r"), h5py.File(sys.argv[2], "r")
names = []
a.visit(lambda n: names.append(n) if isinstance(a[n], h5py.Dataset) else None)
differ = [n for n in names if n != "provenance/arguments" and
          (n not in b or not np.array_equal(a[n][()], b[n][()], equal_nan=a[n].dtype.kind == "f"))]
if differ:
    print("differ: " + ", ".join(differ))
    sys.exit(1)
EOF
            echo "test-threads: $mesh: --threads $threads differs from --threads 1" >&2
            status=1
        fi
    done
    echo "test-threads: $mesh $*: threads 1, 2, 3 agree, no race reported" >&2
done
exit $status
