#!/usr/bin/env bash
# Benchmark of bpm-mesh (TetGen volume meshing of the coarse surface) and of red
# refinement with boundary vertices moved onto the original surface (tet_refine).
#
# For femur, fandisk, elephant, armadillo (simplified to 10% of their vertices) and the
# two-cubes fixture (two unit cubes sharing a face, 4x4 quads per face, two regions):
#   - bpm-simplify time, coarse triangles
#   - bpm-mesh: vertices, tetrahedra, Steiner points, wall time (TetGen + bpm)
#   - for K = 0..3: tetrahedra, per region the meshed volume vs the volume enclosed by
#     the coarse surface and by the original surface (relative difference), inverted
#     elements, min/max dihedral angle, vertices kept off the surface by the §3.3 remedy.
#     K is skipped when it would exceed $BPM_BENCH_MAX_TETS tetrahedra (default 20 million).
#
# Usage: bench/tetmesh.sh [TOOL_DIR] [WORK_DIR]
#   TOOL_DIR  directory with bpm-simplify and bpm-mesh (default: build-mesh/bin, then build/bin)
#   WORK_DIR  scratch directory (default: a new temporary directory, removed at the end)
# Needs: tetgen on PATH, /usr/bin/python3 (for the tables).
set -euo pipefail

here="$(cd "$(dirname "$0")/.." && pwd)"
tools="${1:-}"
if [[ -z "$tools" ]]; then
    for d in "$here/build-mesh/bin" "$here/build/bin"; do
        [[ -x "$d/bpm-mesh" ]] && { tools="$d"; break; }
    done
fi
[[ -x "$tools/bpm-mesh" && -x "$tools/bpm-simplify" ]] || { echo "tetmesh.sh: no bpm-mesh/bpm-simplify in '$tools'" >&2; exit 2; }
command -v tetgen >/dev/null || { echo "tetmesh.sh: tetgen not on PATH (Debian package 'tetgen')" >&2; exit 6; }
work="${2:-}"
cleanup=0
if [[ -z "$work" ]]; then work="$(mktemp -d)"; cleanup=1; fi
mkdir -p "$work"
meshes="$here/.data/meshes"
max_tets="${BPM_BENCH_MAX_TETS:-20000000}"
py=/usr/bin/python3

# The two-cubes fixture (tests/unit/fixtures_surfaces.cpp: two_cubes(4)) as OBJ with
# patch groups: patch 1 = cube 1 outside, 2 = cube 2 outside, 102 = the shared square.
"$py" - "$work/two_cubes.obj" <<'PY'
import sys
res = 4
labels = {(0, 0, 0): 1, (1, 0, 0): 2}
def label(c): return labels.get(tuple(c), 0)
verts, index, faces = [], {}, []
def vertex(g):
    if g not in index:
        index[g] = len(verts); verts.append(tuple(x / res for x in g))
    return index[g]
n = (2, 1, 1)
for d in range(3):
    d1, d2 = (d + 1) % 3, (d + 2) % 3
    for cd in range(-1, n[d]):
        for c1 in range(n[d1]):
            for c2 in range(n[d2]):
                c = [0, 0, 0]; c[d], c[d1], c[d2] = cd, c1, c2
                e = list(c); e[d] += 1
                la, lb = label(c), label(e)
                if la == lb: continue
                patch = min(la, lb) * 100 + max(la, lb)
                for a in range(res):
                    for b in range(res):
                        q = []
                        for (u, v) in ((a, b), (a + 1, b), (a + 1, b + 1), (a, b + 1)):
                            g = [0, 0, 0]; g[d] = (c[d] + 1) * res; g[d1] = c[d1] * res + u; g[d2] = c[d2] * res + v
                            q.append(vertex(tuple(g)))
                        if la < lb: q[1], q[3] = q[3], q[1]
                        faces.append((patch, (q[0], q[1], q[2]))); faces.append((patch, (q[0], q[2], q[3])))
with open(sys.argv[1], "w") as f:
    for v in verts: f.write("v %.17g %.17g %.17g\n" % v)
    last = None
    for patch, t in faces:
        if patch != last: f.write("g patch_%d\n" % patch); last = patch
        f.write("f %d %d %d\n" % tuple(i + 1 for i in t))
PY

declare -a inputs=("$meshes/femur.off" "$meshes/fandisk.off" "$meshes/elephant.off" "$meshes/armadillo.off" "$work/two_cubes.obj")
now() { date +%s.%N; }
results="$work/results.jsonl"
: > "$results"
for input in "${inputs[@]}"; do
    name="$(basename "${input%.*}")"
    t0=$(now)
    "$tools/bpm-simplify" "$input" -o "$work/$name.bpm" --ratio 0.1 --deterministic -q
    t1=$(now)
    simplify_s=$(echo "$t1 - $t0" | bc)
    "$tools/bpm-mesh" "$work/$name.bpm" -o "$work/$name.mesh0.bpm" --json -q --deterministic > "$work/$name.k0.json"
    t2=$(now)
    tool_s=$(echo "$t2 - $t1" | bc)
    tets0=$("$py" -c 'import json,sys; print(json.load(open(sys.argv[1]))["tetrahedra"])' "$work/$name.k0.json")
    "$py" -c 'import json,sys; d=json.load(open(sys.argv[1])); d.update(name=sys.argv[2], K=0, simplify_seconds=float(sys.argv[3]), tool_seconds=float(sys.argv[4])); print(json.dumps(d))' \
        "$work/$name.k0.json" "$name" "$simplify_s" "$tool_s" >> "$results"
    for K in 1 2 3; do
        if (( tets0 * (1 << (3 * K)) > max_tets )); then
            echo "{\"name\": \"$name\", \"K\": $K, \"skipped\": true}" >> "$results"
            continue
        fi
        t3=$(now)
        "$tools/bpm-mesh" "$work/$name.mesh0.bpm" --existing --refine $K -o "$work/$name.k$K.bpm" --json -q --deterministic > "$work/$name.k$K.json"
        t4=$(now)
        "$py" -c 'import json,sys; d=json.load(open(sys.argv[1])); d.update(name=sys.argv[2], K=int(sys.argv[3]), tool_seconds=float(sys.argv[4])); print(json.dumps(d))' \
            "$work/$name.k$K.json" "$name" "$K" "$(echo "$(now) - $t3" | bc)" >> "$results"
        rm -f "$work/$name.k$K.bpm"
    done
done

"$py" - "$results" <<'PY'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
print("bpm-mesh (TetGen -pYzA -q1.414, surface kept exactly), inputs simplified to 10% of their vertices\n")
print("%-10s %8s %8s %9s %8s %9s %10s %9s" % ("mesh", "coarse_T", "tet_V", "tets", "steiner", "tetgen_s", "bpm-mesh_s", "simplify_s"))
for r in rows:
    if r["K"] != 0: continue
    print("%-10s %8d %8d %9d %8d %9.3f %10.3f %9.2f" % (r["name"], r["coarse_triangles"], r["vertices"], r["tetrahedra"],
          r["steiner_points"], r["tetgen_seconds"], r["mesh_seconds"], r["simplify_seconds"]))
print("\nred refinement, new boundary vertices moved to phi (lambda remedy, min volume fraction 0.1)\n")
print("%-10s %2s %9s %3s %12s %9s %9s %8s %9s %9s %8s %8s" % ("mesh", "K", "tets", "reg", "volume", "vs_coarse", "vs_orig",
      "inverted", "min_dih", "max_dih", "remedied", "refine_s"))
for r in rows:
    if r.get("skipped"):
        print("%-10s %2d   skipped (more than the tetrahedron limit)" % (r["name"], r["K"])); continue
    for g in r["regions"]:
        rel = lambda a: (g["volume"] - a) / a if a else float("nan")
        print("%-10s %2d %9d %3d %12.6g %+9.2e %+9.2e %8d %9.4f %9.4f %8d %8.2f" % (r["name"], r["K"], r["tetrahedra"], g["id"],
              g["volume"], rel(g["coarse_volume"]), rel(g["original_volume"]), r["inverted"], r["min_dihedral_degrees"],
              r["max_dihedral_degrees"], r["remedied_vertices"], r["refine_seconds"] or 0))
PY
if (( cleanup )); then rm -rf "$work"; fi
