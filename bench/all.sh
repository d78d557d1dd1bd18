#!/bin/sh
# The one benchmark command (bench/README.md): builds every tool once in Release in
# build-bench/, runs every suite (simplify vs psurface vs CGAL, scaling, check speed,
# refinement, adaptive refinement's error bound, tet meshes, the whole corpus) and writes
# bench/RESULTS.md.
#   bench/all.sh                 the full run (quiet 2-core machine: about 20 minutes)
#   bench/all.sh --quick         a short trial; writes build-bench/bench-quick/RESULTS.md
#   bench/all.sh --help          every option (they are bench/run.py's)
BPM_BENCH_VIA_ALL_SH=1 exec /usr/bin/python3 "$(dirname "$0")/run.py" all "$@"
