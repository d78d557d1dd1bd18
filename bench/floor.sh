#!/usr/bin/env bash
# The floor of bpm-simplify (issue 21): --ratio 1 --threads 1 (read, set-up, first ranking,
# input intersection check, write) against CGAL's edge collapse with nothing to collapse
# (read + write), CPU seconds (user + sys) and peak RSS, median of N alternated runs; and
# the .bpm size at --ratio 0.1 against the input OFF. The fair floor (issue 21) leaves out the
# two phases CGAL's reference does not have, the first ranking of every vertex and the exact
# input self-intersection check (their CPU seconds from bpm-simplify -v): read + set-up +
# export + write <= 1.5x CGAL's read + write.
#   bench/floor.sh BUILD_DIR [N] [MESH.off ...]   (default: armadillo and its 1x Loop subdivision)
# Takes about N x 10 s per mesh of 208k triangles on a busy 2-core machine.
set -euo pipefail
build=${1:?usage: bench/floor.sh BUILD_DIR [N] [MESH.off ...]}; n=${2:-3}; shift $(( $# < 2 ? $# : 2 ))
here=$(cd "$(dirname "$0")" && pwd); work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
meshes=("$@")
if [ ${#meshes[@]} -eq 0 ]; then
  /usr/bin/python3 "$here/make_subdivided.py" "$here/../.data/meshes/armadillo.off" 1 "$work/armadillo-loop1.off" >/dev/null
  meshes=("$here/../.data/meshes/armadillo.off" "$work/armadillo-loop1.off")
fi
median() { sort -g | awk '{a[NR]=$1} END{print a[int((NR+1)/2)]}'; }
printf '| input | OFF MB | bpm floor s | first ranking s | input check s | fair floor s | CGAL read+write s | floor ÷ CGAL | fair ÷ CGAL | bpm peak MB | CGAL peak MB | .bpm at 10 %% MB | .bpm ÷ OFF |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n'
# CPU seconds of a phase in bpm-simplify -v's "time:" lines (0 if absent).
phase() { awk -v p="$1" 'index($0, "time: " p) { for (i = 1; i < NF; ++i) if ($(i + 1) == "s" && $(i + 2) == "CPU") v = $i } END { print v + 0 }' "$work/log"; }
for m in "${meshes[@]}"; do
  : > "$work/b"; : > "$work/c"; : > "$work/bm"; : > "$work/cm"; : > "$work/r"; : > "$work/x"; : > "$work/f"
  for _ in $(seq "$n"); do
    /usr/bin/time -f '%U %S %M' -o "$work/t" "$build/bin/bpm-simplify" "$m" --ratio 1 --threads 1 -v -o "$work/o.bpm" 2> "$work/log"
    awk '{print $1+$2 >> "'"$work/b"'"; print $3/1024 >> "'"$work/bm"'"}' "$work/t"
    r=$(phase "first ranking"); x=$(phase "input intersection check")
    echo "$r" >> "$work/r"; echo "$x" >> "$work/x"; echo "$(tail -1 "$work/b") - $r - $x" | bc -l >> "$work/f"
    /usr/bin/time -f '%U %S %M' -o "$work/t" "$build/bin/bpm-bench-cgal-decimate" "$m" -o "$work/o.off" --ratio 1 2>/dev/null
    awk '{print $1+$2 >> "'"$work/c"'"; print $3/1024 >> "'"$work/cm"'"}' "$work/t"
  done
  "$build/bin/bpm-simplify" "$m" --ratio 0.1 -q -o "$work/d.bpm"
  b=$(median < "$work/b"); c=$(median < "$work/c"); f=$(median < "$work/f"); off=$(stat -c %s "$m"); bpm=$(stat -c %s "$work/d.bpm")
  printf '| %s | %.1f | %s | %.2f | %.2f | %.2f | %s | %.2f | %.2f | %.0f | %.0f | %.1f | %.2f |\n' "$(basename "$m")" "$(echo "$off/1000000" | bc -l)" \
    "$b" "$(median < "$work/r")" "$(median < "$work/x")" "$f" "$c" "$(echo "$b/$c" | bc -l)" "$(echo "$f/$c" | bc -l)" \
    "$(median < "$work/bm")" "$(median < "$work/cm")" \
    "$(echo "$bpm/1000000" | bc -l)" "$(echo "$bpm/$off" | bc -l)"
done
