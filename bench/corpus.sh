#!/usr/bin/env bash
# The whole real corpus: bpm-simplify --ratio 0.1 and then bpm-check on every mesh of
# Debian's libcgal-demo data (.data/meshes). Every mesh must end in a valid file or in a
# clear refusal. A mesh refused with a message that names a repair (duplicate or unused
# vertices, polygon faces, self-intersections) is tried once more with bpm-simplify's four
# input repairs, and that second outcome is reported too. Writes bench/results/corpus.md.
#   bench/corpus.sh [BUILD_DIR]   (default: build; run scripts/build.sh first)
set -u
cd "$(dirname "$0")/.."
bin=${1:-build}/bin
work=${TMPDIR:-/tmp}/bpm-corpus
mkdir -p "$work" bench/results
out=bench/results/corpus.md
valid=0
repaired=0
refused=0
broken=0
rows=""
for mesh in .data/meshes/*; do
    name=$(basename "$mesh")
    case "$name" in *.off|*.obj|*.stl|*.ply|*.msh) ;; *) continue ;; esac
    start=$(date +%s.%N)
    timeout 600 "$bin/bpm-simplify" "$mesh" -o "$work/$name.bpm" --ratio 0.1 -q 2>"$work/err"
    code=$?
    seconds=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
    reason=$(head -c 300 "$work/err" | tr '\n|' '  ')
    if [ $code -eq 0 ]; then
        "$bin/bpm-check" "$work/$name.bpm" >"$work/check" 2>&1
        if [ $? -eq 0 ]; then
            valid=$((valid + 1))
            verdict="valid"
        else
            broken=$((broken + 1))
            verdict="**CHECK FAILED**"
            reason=$(grep FAIL "$work/check" | head -2 | tr '\n|' '  ')
        fi
    elif { [ $code -eq 3 ] || [ $code -eq 5 ]; } && grep -q "repair" "$work/err"; then
        # The message names a repair: try the input repairs.
        timeout 600 "$bin/bpm-simplify" "$mesh" -o "$work/$name.bpm" --ratio 0.1 -q --merge-duplicate-vertices \
            --drop-unreferenced-vertices --triangulate-polygons --repair-self-intersections 2>"$work/err2"
        code2=$?
        if [ $code2 -eq 0 ] && "$bin/bpm-check" "$work/$name.bpm" >"$work/check" 2>&1; then
            repaired=$((repaired + 1))
            verdict="valid with the input repairs (refused without: exit $code)"
        elif [ $code2 -eq 0 ]; then
            broken=$((broken + 1))
            verdict="**CHECK FAILED** (with the input repairs)"
            reason=$(grep FAIL "$work/check" | head -2 | tr '\n|' '  ')
        elif [ $code2 -eq 3 ] || [ $code2 -eq 5 ]; then
            refused=$((refused + 1))
            verdict="refused (exit $code; with the input repairs: exit $code2)"
            reason="$reason; with the input repairs: $(head -c 300 "$work/err2" | tr '\n|' '  ')"
        else
            broken=$((broken + 1))
            verdict="**exit $code2** (with the input repairs)"
        fi
    elif [ $code -eq 3 ] || [ $code -eq 5 ]; then
        refused=$((refused + 1))
        verdict="refused (exit $code)"
    else
        broken=$((broken + 1))
        verdict="**exit $code**"
    fi
    rows+="| $name | $verdict | $seconds | $reason |"$'\n'
    rm -f "$work/$name.bpm"
done
{
    echo "# The whole libcgal-demo corpus through bpm-simplify --ratio 0.1 and bpm-check"
    echo
    echo "Run $(date -u +%Y-%m-%dT%H:%MZ) by bench/corpus.sh on $(nproc) cores."
    echo "Valid: $valid; valid with the input repairs (\`--merge-duplicate-vertices --drop-unreferenced-vertices"
    echo "--triangulate-polygons --repair-self-intersections\`, tried when the refusal names a repair): $repaired;"
    echo "refused with a reason: $refused;"
    echo "broken (crash, internal error or failed check): $broken."
    echo
    echo "| mesh | result | seconds | reason |"
    echo "|---|---|---:|---|"
    printf "%s" "$rows"
} >"$out"
echo "valid $valid, valid with repairs $repaired, refused $refused, broken $broken (see $out)"
[ "$broken" -eq 0 ]
