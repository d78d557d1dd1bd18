#!/usr/bin/env bash
# φ inside a real solver: DUNE's UGGrid refines a tet mesh of a coarse surface and puts its
# new boundary vertices on the original surface through φ (examples/dune/bpm-torsion).
# Solves the torsion problem -Δu = 1, u = 0 on the boundary, on levels 0..K, once with the
# boundary refined flat and once through φ, and prints J = ∫u per level for both.
#   scripts/demo-solver.sh [SURFACE] [RATIO] [LEVELS]
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
./scripts/build.sh >&2
input=${1:-.data/meshes/femur.off}
ratio=${2:-0.1}
levels=${3:-2}
bin=build/bin
if [ ! -x "$bin/bpm-torsion" ]; then
  echo "demo-solver: build/bin/bpm-torsion was not built (DUNE 2.9 with UG not found by CMake)" >&2
  exit 1
fi
out=out
mkdir -p "$out"
name=$(basename "${input%.*}")
echo "== bpm-simplify $input --ratio $ratio" >&2
"$bin/bpm-simplify" "$input" -o "$out/$name.bpm" --ratio "$ratio" -q
echo "== bpm-mesh" >&2
"$bin/bpm-mesh" "$out/$name.bpm" -o "$out/$name.tets.bpm" -q
for mode in flat phi; do
  flag=""
  [ "$mode" = flat ] && flag="--flat"
  echo "== bpm-torsion $out/$name.tets.bpm --levels $levels $flag" >&2
  "$bin/bpm-torsion" "$out/$name.tets.bpm" --levels "$levels" $flag --json > "$out/$name.torsion-$mode.json"
done
/usr/bin/python3 - "$out/$name.torsion-flat.json" "$out/$name.torsion-phi.json" <<'PY'
import json, sys
flat, phi = (json.load(open(p)) for p in sys.argv[1:3])
print(f"{'level':>5} {'tets':>9} {'J flat':>12} {'J phi':>12} {'volume flat':>12} {'volume phi':>12} {'inverted phi':>12}")
for a, b in zip(flat["levels"], phi["levels"]):
    print(f"{a['level']:>5} {a['tets']:>9} {a['J']:>12.5g} {b['J']:>12.5g} {a['volume']:>12.5g} {b['volume']:>12.5g} {b['inverted']:>12}")
print(f"volume enclosed by the original surface: {phi['original_region_volumes']}")
PY
