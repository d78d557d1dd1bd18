#!/usr/bin/env bash
# "Feature lines" meant two things: on a box, bpm-check's topology line said "0 feature
# vertices, 0 feature lines" while bpm-info said "features 12 lines, 8 vertices" for the
# same file (bpm-check counted only boundary, non-manifold and patch-border edges; bpm-info
# creases too), and both JSON reports had a key feature_lines with those two values. Now
# one definition (spec/check-report.md): feature lines include creases, and bpm-check's
# are called what they are, topological feature lines, which bpm-info reports too.
# Usage: feature_lines_mean_one_thing.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"

# The unit cube, each face a 4 x 4 grid of squares split in two (OFF), closed; and the same
# without its top face (x = 1), open along a square loop.
/usr/bin/python3 - "$work" "$(dirname "$0")/lib" <<'PY'
import sys
sys.path.insert(0, sys.argv[2])
from grid_cube import cube_triangles
work, n = sys.argv[1], 4
def cube(skip_top):
    tris = cube_triangles(n, (0, 1) if skip_top else None)
    index = {}
    for t in tris:
        for v in t: index.setdefault(v, len(index))
    lines = ["OFF", "%d %d 0" % (len(index), len(tris))]
    lines += ["%r %r %r" % v for v in index]
    lines += ["3 %d %d %d" % tuple(index[v] for v in t) for t in tris]
    return "\n".join(lines) + "\n"
open(work + "/box.off", "w").write(cube(False))
open(work + "/open.off", "w").write(cube(True))
PY
py=/usr/bin/python3
for f in box open; do
    expect 0 "$f: simplified" -- "$tools/bpm-simplify" "$work/$f.off" -o "$work/$f.bpm" --ratio 0.5
done

expect 0 "bpm-check on the box" -- "$tools/bpm-check" "$work/box.bpm" --checks topology
contains "$work/out" "0 topological feature vertices, 0 topological feature lines (of boundaries, patch borders, non-manifold edges; creases are geometry, not counted)" \
    "bpm-check says its feature lines are the topological ones, without creases"
expect 0 "bpm-info on the box" -- "$tools/bpm-info" "$work/box.bpm"
contains "$work/out" "features    12 lines, 8 vertices of the coarse surface" "bpm-info: the 12 edges of the box, creases"
contains "$work/out" "without the creases 0 topological feature lines and 0 topological feature vertices (bpm-check's)" \
    "bpm-info gives bpm-check's numbers under the same name"

# The open box: the top's rim is a boundary loop, a topological feature line; the JSON
# reports of both tools give the same topological counts under the same keys.
expect 0 "bpm-check --json on the open box" -- "$tools/bpm-check" "$work/open.bpm" --checks topology --json
cp "$work/out" "$work/check.json"
expect 0 "bpm-info --json on the open box" -- "$tools/bpm-info" "$work/open.bpm" --json
cp "$work/out" "$work/info.json"
ok "the topological counts agree between the tools (1 line, 0 vertices)" -- $py -c "
import json, sys
check = json.load(open('$work/check.json'))['checks'][0]['counts']
info = json.load(open('$work/info.json'))['features']
print(check, info)
ok = all(check['topological_feature_' + k] == info['topological_feature_' + k] for k in ('lines', 'vertices'))
ok = ok and info['topological_feature_lines'] == 1 and info['feature_lines'] > info['topological_feature_lines']
# the 0.1 keys of bpm-check keep their values until 0.2
ok = ok and check['feature_lines'] == check['topological_feature_lines']
sys.exit(0 if ok else 1)"

for t in bpm-check bpm-info; do
    expect 0 "$t --help" -- "$tools/$t" --help
    contains "$work/out" "topological" "$t --help names the topological feature lines"
    contains "$work/out" "creases" "$t --help says creases are feature lines too"
done
ok "the spec defines the words once" -- grep -q "### Feature lines: one definition" "$src/spec/check-report.md"
finish
