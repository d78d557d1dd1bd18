#!/usr/bin/env bash
# bpm-simplify --record-steps, then bpm-check --replay and --max-distance on real meshes.
# Usage: replay_check.sh TOOL_DIR SOURCE_DIR WORK_DIR
source "$(dirname "$0")/lib/harness.bash"
simplify=$tools/bpm-simplify
check=$tools/bpm-check
smooth=$tools/bpm-smooth
meshes=$src/.data/meshes
femur=$meshes/femur.off
shark=$meshes/mech-holes-shark.off   # 4 boundary loops: removals of half-disks on the boundary

expect 0 "help" -- "$check" --help
contains "$work/out" "--replay" "help mentions --replay"
contains "$work/out" "--max-distance" "help mentions --max-distance"
expect 0 "simplify help" -- "$simplify" --help
contains "$work/out" "--record-steps" "bpm-simplify help mentions --record-steps"

example=$src/spec/examples/two_triangles.bpm
expect 1 "a file without a record fails --replay" -- "$check" --replay "$example"
contains "$work/out" "FAIL replay  1 problem; first: not checked: the file has no recorded simplification steps" \
    "replay refuses a file without a record"
expect 2 "--replay with --surface is a usage error" -- "$check" --surface --replay "$example"
expect 2 "--max-distance with --surface is a usage error" -- "$check" --surface --max-distance 0.1 "$example"
expect 2 "--checks accepts replay, not nonsense" -- "$check" --checks replay,nonsense "$example"
expect 2 "negative --max-distance" -- "$check" --max-distance -1 "$example"

if [ ! -f "$femur" ]; then
    echo "SKIPPED: $femur missing (scripts/setup.sh unpacks libcgal-demo's meshes)"
    finish
    exit $?
fi

expect 0 "simplify femur with --record-steps" -- \
    "$simplify" "$femur" -o "$work/femur.bpm" --ratio 0.1 --record-steps --deterministic
expect 0 "femur replays clean" -- "$check" --replay "$work/femur.bpm"
contains "$work/out" "PASS replay  replayed " "replay line"
contains "$work/out" "the result is the coarse surface" "replay reaches the coarse surface"
contains "$work/out" "PASS bijectivity  " "the other checks still run"

expect 0 "replay only, every step fully checked, JSON" -- \
    "$check" --checks replay --replay-interval 200 --json "$work/femur.bpm"
cp "$work/out" "$work/replay.json"
if command -v python3 >/dev/null; then
    ok "replay JSON" -- python3 -c "
import json
r = json.load(open('$work/replay.json'))
assert r['passed'] and [c['name'] for c in r['checks']] == ['replay'], r
c = r['checks'][0]['counts']
assert c['steps'] > 3000 and c['replayed_steps'] == c['steps'] and c['mismatched_triangles'] == 0, c
assert c['full_topology_checks'] == (c['steps'] + 199) // 200, c
"
fi

if /usr/bin/python3 -c "import h5py" 2>/dev/null; then
    ok "spec §10.1 replayed independently with h5py gives /coarse" -- /usr/bin/python3 -c "
import h5py
f = h5py.File('$work/femur.bpm', 'r')
assert list(f.attrs['format_version']) == [2, 1]
g = f['simplification_steps']
vertex, offsets = g['vertex'][()], g['triangle_offsets'][()]
tris, patches = g['triangles'][()], g['triangle_patches'][()]
alive = {}
for t, p in zip(f['original/triangles'][()], f['original/patches'][()]):
    alive[frozenset(int(x) for x in t)] = int(p)
for r, v in enumerate(vertex):
    alive = {k: p for k, p in alive.items() if int(v) not in k}
    for j in range(offsets[r], offsets[r + 1]):
        alive[frozenset(int(x) for x in tris[j])] = int(patches[j])
origin = f['coarse/vertex_origin'][()]
coarse = {frozenset(int(origin[x]) for x in t): int(p) for t, p in zip(f['coarse/triangles'][()], f['coarse/patches'][()])}
assert alive == coarse, (len(alive), len(coarse))
"
fi

expect 0 "distance gate passes at 5%" -- "$check" --checks format --max-distance 0.05 --json "$work/femur.bpm"
cp "$work/out" "$work/distance.json"
if command -v python3 >/dev/null; then
    ok "distance JSON: measures, bound above the sampled S -> S0" -- python3 -c "
import json
r = json.load(open('$work/distance.json'))
d = [c for c in r['checks'] if c['name'] == 'distance'][0]
assert d['passed'], d
m = {x['name']: x for x in d['measures']}
assert set(m) >= {'coarse_hausdorff', 'coarse_to_original', 'original_to_coarse', 'coarse_to_original_bound',
                  'image_hausdorff', 'image_to_original', 'original_to_image', 'sample_spacing'}, m
assert m['coarse_to_original']['value'] <= m['coarse_to_original_bound']['value'] * (1 + 1e-9)
assert 1e-4 < m['coarse_hausdorff']['value'] < 0.05
assert m['image_hausdorff']['value'] < 1e-10
assert d['worst']['name'] == 'coarse_hausdorff' and 'coarse_triangle' in d['worst']['ids']
"
fi
expect 1 "distance gate fails below the error" -- "$check" --checks format --max-distance 0.0005 "$work/femur.bpm"
contains "$work/out" "FAIL distance  1 problem; first: " "distance line"
contains "$work/out" "the coarse surface is " "distance message"

expect 0 "bpm-smooth keeps the record" -- "$smooth" "$work/femur.bpm" -o "$work/femur.smooth.bpm" --deterministic
expect 0 "the smoothed file replays clean" -- "$check" --checks replay "$work/femur.smooth.bpm"

expect 0 "simplify femur without --record-steps" -- \
    "$simplify" "$femur" -o "$work/plain.bpm" --ratio 0.1 --deterministic
expect 1 "... then --replay fails" -- "$check" --checks replay "$work/plain.bpm"

if [ -f "$shark" ]; then
    expect 0 "simplify a mesh with boundaries with --record-steps" -- \
        "$simplify" "$shark" -o "$work/shark.bpm" --ratio 0.1 --record-steps --deterministic
    expect 0 "it replays clean, with half-disk removals on the boundary" -- \
        "$check" --replay --max-distance 0.05 --json "$work/shark.bpm"
    cp "$work/out" "$work/shark.json"
    if command -v python3 >/dev/null; then
        ok "shark: feature-line removals replayed" -- python3 -c "
import json
r = json.load(open('$work/shark.json'))
assert r['passed']
c = [c for c in r['checks'] if c['name'] == 'replay'][0]['counts']
assert c['feature_line_removals'] > 0 and c['disk_removals'] > 0, c
"
    fi
fi

finish
