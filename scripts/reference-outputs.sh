#!/usr/bin/env bash
# Writes 18 deterministic outputs of the tools, for proving a refactor leaves them unchanged:
# the 5 benchmark meshes simplified to 10 % and to 1000 vertices, the two_cubes fixture
# (two materials), bpm-smooth, bpm-refine (uniform and adaptive) and bpm-mesh (level 0,
# a refined level, two materials) outputs, and OUTDIR/SHA256SUMS.
#
#   scripts/reference-outputs.sh BUILD_DIR OUTDIR     (tools from BUILD_DIR/bin)
#   scripts/reference-outputs.sh build-old old && scripts/reference-outputs.sh build new
#   diff old/SHA256SUMS new/SHA256SUMS                 (no output: byte-identical)
#
# Each .bpm stores its command line, so the tools run by bare name with relative input and
# output names (the meshes through OUTDIR/meshes, a link to the checkout's .data/meshes): the
# bytes do not depend on where the checkout, the build or OUTDIR is (a worktree gives the
# same bytes as the main checkout). Files written by a
# different writer (e.g. other HDF5 filter settings) can differ in bytes with the same
# content: compare those with `h5diff -c OLD NEW`.
set -euo pipefail
[ $# -eq 2 ] || { sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "$1" && pwd)
for tool in bpm-simplify bpm-smooth bpm-refine bpm-mesh; do
    [ -x "$build/bin/$tool" ] || { echo "reference-outputs.sh: no $build/bin/$tool (build it first)" >&2; exit 2; }
done
meshes=$root/.data/meshes
[ -f "$meshes/femur.off" ] || { echo "reference-outputs.sh: no $meshes/femur.off (scripts/setup.sh unpacks the meshes)" >&2; exit 2; }
mkdir -p "$2"
cd "$2"
ln -sfn "$meshes" meshes
export PATH="$build/bin:$PATH"
for m in femur fandisk elephant armadillo mech-holes-shark; do
    bpm-simplify "meshes/$m.off" -o "$m-10.bpm" --ratio 0.1 --deterministic -q &
    bpm-simplify "meshes/$m.off" -o "$m-1000.bpm" --vertices 1000 --deterministic -q
    wait
done
/usr/bin/python3 "$root/bench/make_two_cubes.py" two_cubes.obj 4 >/dev/null
bpm-simplify two_cubes.obj -o two_cubes.bpm --ratio 0.3 --deterministic -q
bpm-smooth femur-10.bpm -o femur-10.smooth.bpm --deterministic -q
bpm-refine femur-10.smooth.bpm --levels 1 -o femur-10.r1.bpm --deterministic -q
bpm-refine fandisk-10.bpm --tolerance 0.003 -o fandisk-10.t3.bpm --deterministic -q
bpm-mesh femur-10.bpm -o femur-10.tets.bpm --deterministic -q
bpm-mesh armadillo-1000.bpm -o armadillo-1000.tets.bpm --deterministic -q
bpm-mesh femur-10.tets.bpm --existing --refine 1 -o femur-10.tets1.bpm --deterministic -q
bpm-mesh two_cubes.bpm -o two_cubes.tets.bpm --deterministic -q
sha256sum ./*.bpm > SHA256SUMS
echo "reference-outputs.sh: $(wc -l < SHA256SUMS) outputs in $(pwd)"
