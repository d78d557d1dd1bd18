#!/usr/bin/env bash
# Benchmark of bpm-mesh (TetGen volume meshing of the coarse surface) and of red refinement
# with the boundary vertices moved onto the original surface (bpm/tet_refine.h), with and
# without interior smoothing (bpm/tetmesh_smooth.h).
#
# For femur, fandisk, elephant, armadillo (.data/meshes) and the two-cubes fixture of the
# unit tests (two materials; bench/make_two_cubes.py), each simplified to 10% of its
# vertices with bpm-simplify:
#   - bpm-mesh: vertices, tetrahedra, Steiner points, TetGen and bpm-mesh times;
#   - for K = 0..3 refinement levels (bpm-mesh --existing --refine K on the level-0 mesh):
#     per region the meshed volume against the volume enclosed by the original surface
#     (relative error; the targets: it falls monotonically and at least 8x from K=0 to
#     K=3), inverted elements (target 0), the smallest dihedral angle, the tetrahedra
#     below 1, 5 and 10 degrees, the boundary vertices the lambda remedy keeps off the
#     surface and their largest distance to it (relative to the bounding-box diagonal of
#     the original), times.
#   - the same with smoothing off and the remedy's angle bound off (`bpm-mesh --no-smooth`,
#     `--refine K --no-smooth --remedy-min-dihedral 0`: positive volumes and the volume
#     fraction only, as before smoothing existed), for comparison (--no-compare skips it).
# A K is skipped when it would exceed $BPM_BENCH_MAX_TETS tetrahedra (default 20 million;
# --max-tets overrides).
#
# Usage: bench/tetmesh.sh [--no-build] [--build-dir DIR] [--work-dir DIR] [--results-dir DIR]
#                         [--meshes femur,fandisk,...] [--targets r10,v1000] [--max-tets N] [--no-compare]
#   --build-dir DIR    Release build with bpm-simplify, bpm-mesh, bpm-refine, bpm-check in DIR/bin (default build-bench);
#                      without --no-build: cmake -S . -B DIR -DCMAKE_BUILD_TYPE=Release -DBPM_BUILD_TESTS=OFF
#                      and cmake --build DIR -j2 --target bpm-simplify bpm-mesh bpm-refine bpm-check first
#   --work-dir DIR     scratch files (default DIR/bench-work/tetmesh; kept, outputs of big runs deleted)
#   --results-dir DIR  where tetmesh.md and tetmesh.json go (default bench/results)
#   --targets LIST     coarse sizes: r10 (bpm-simplify --ratio 0.1, rows named after the mesh) and
#                      v1000 (--vertices 1000, rows "NAME 1000 V"; not for two_cubes); default r10,v1000
# Relative paths are taken from the repository root. Non-interactive; progress on stderr.
# Exit status: 0 when every run finished (whether the targets were met is in the tables),
# 1 when a run failed, 2 on a usage error, 6 when tetgen is missing.
# Needs: tetgen on PATH (Debian package tetgen), /usr/bin/python3, /usr/bin/time.
set -euo pipefail

here="$(cd "$(dirname "$0")/.." && pwd)"
cd "$here"
build_dir=build-bench
no_build=0
work=""
results_dir=bench/results
meshes="femur,fandisk,elephant,armadillo,two_cubes"
max_tets="${BPM_BENCH_MAX_TETS:-20000000}"
compare=1
targets=r10,v1000
usage() { sed -n '/^# Usage:/,/^# Needs:/p' "$0" | sed 's/^# \{0,1\}//'; }
while (($#)); do
    case "$1" in
        --no-build) no_build=1 ;;
        --build-dir) build_dir="${2:?--build-dir needs a directory}"; shift ;;
        --build-dir=*) build_dir="${1#*=}" ;;
        --work-dir) work="${2:?--work-dir needs a directory}"; shift ;;
        --work-dir=*) work="${1#*=}" ;;
        --results-dir) results_dir="${2:?--results-dir needs a directory}"; shift ;;
        --results-dir=*) results_dir="${1#*=}" ;;
        --meshes) meshes="${2:?--meshes needs a list}"; shift ;;
        --meshes=*) meshes="${1#*=}" ;;
        --max-tets) max_tets="${2:?--max-tets needs a number}"; shift ;;
        --max-tets=*) max_tets="${1#*=}" ;;
        --no-compare) compare=0 ;;
        --targets) targets="${2:?--targets needs a list}"; shift ;;
        --targets=*) targets="${1#*=}" ;;
        -h|--help) usage; exit 0 ;;
        *) echo "tetmesh.sh: unknown argument '$1'" >&2; usage >&2; exit 2 ;;
    esac
    shift
done
[[ "$max_tets" =~ ^[0-9]+$ ]] || { echo "tetmesh.sh: --max-tets needs a number" >&2; exit 2; }
py=/usr/bin/python3
log() { echo "tetmesh.sh: $*" >&2; }
command -v tetgen >/dev/null || { log "tetgen not on PATH (Debian package 'tetgen')"; exit 6; }

if ((!no_build)); then
    log "building bpm-simplify and bpm-mesh in $build_dir (Release)"
    cmake -S "$here" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DBPM_BUILD_TESTS=OFF >&2
    cmake --build "$build_dir" -j2 --target bpm-simplify bpm-mesh bpm-refine bpm-check >&2
fi
bin="$(cd "$build_dir" && pwd)/bin"
for tool in bpm-simplify bpm-mesh bpm-refine bpm-check; do
    [[ -x "$bin/$tool" ]] || { log "no $tool in $bin (drop --no-build?)"; exit 2; }
done
[[ -n "$work" ]] || work="$build_dir/bench-work/tetmesh"
mkdir -p "$work" "$results_dir"
work="$(cd "$work" && pwd)"
results_dir="$(cd "$results_dir" && pwd)"
rows="$work/rows.jsonl"
: > "$rows"
load_start="$(cut -d' ' -f1-3 /proc/loadavg)"
started="$(date -u +%Y-%m-%dT%H:%M:%SZ)"
failed=0

# Runs a command under /usr/bin/time; sets wall, cpu (user + system) and rss (KiB).
timed() {
    local tfile="$work/time.txt"
    if /usr/bin/time -f "%e %U %S %M" -o "$tfile" "$@"; then
        read -r wall user sys rss < "$tfile"
        cpu=$(awk -v u="$user" -v s="$sys" 'BEGIN { printf "%.2f", u + s }')
        return 0
    fi
    return 1
}
# 1 if bpm-check's independent tetmesh check passes on FILE (orientation, conformity,
# faces on S covering every coarse triangle), 0 otherwise. Not timed.
tetmesh_check() {
    "$bin/bpm-check" "$1" --checks tetmesh -q > "$1.check.txt" 2>&1 && echo 1 || echo 0
}
# Appends the JSON report of a bpm-mesh run with the bench's own fields.
record() {  # name config K json [key value]...
    local name=$1 config=$2 K=$3 json=$4
    shift 4
    "$py" - "$json" "$name" "$config" "$K" "$wall" "$cpu" "$rss" "$@" >> "$rows" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d.update(name=sys.argv[2], config=sys.argv[3], K=int(sys.argv[4]), wall_seconds=float(sys.argv[5]),
         cpu_seconds=float(sys.argv[6]), rss_kib=int(sys.argv[7]))
extra = sys.argv[8:]
for k, v in zip(extra[::2], extra[1::2]):
    d[k] = float(v)
print(json.dumps(d))
PY
}

IFS=, read -r -a names <<< "$meshes"
for name in "${names[@]}"; do
    if [[ "$name" == two_cubes ]]; then
        input="$work/two_cubes.obj"
        "$py" "$here/bench/make_two_cubes.py" "$input" 4
    else
        input="$here/.data/meshes/$name.off"
        [[ -f "$input" ]] || { log "$input is missing (scripts/setup.sh unpacks the meshes)"; failed=1; continue; }
    fi
    counts=$("$py" - "$input" <<'PY'
import sys
p = sys.argv[1]
if p.endswith(".obj"):
    v = f = 0
    for line in open(p):
        v += line.startswith("v ")
        f += line.startswith("f ")
    print(v, f)
else:
    words = [w for line in open(p) for w in line.split("#")[0].split()][:3]
    print(words[1], words[2])
PY
)
    read -r orig_v orig_t <<< "$counts"
    IFS=, read -r -a target_list <<< "$targets"
    mesh=$name
    for target in "${target_list[@]}"; do
    case "$target" in
        r10) name=$mesh simplify_flags=(--ratio 0.1) ;;
        v1000) [[ "$mesh" == two_cubes ]] && continue
               name="$mesh 1000 V" simplify_flags=(--vertices 1000) ;;
        *) log "unknown target '$target' (r10, v1000)"; exit 2 ;;
    esac
    stem=${name// /-}
    log "$name: bpm-simplify ${simplify_flags[*]}"
    if ! timed "$bin/bpm-simplify" "$input" -o "$work/$stem.bpm" "${simplify_flags[@]}" --deterministic -q; then
        log "$name: bpm-simplify failed"; failed=1; continue
    fi
    simplify_wall=$wall simplify_cpu=$cpu
    # The volume enclosed when every boundary vertex of level K is on S0: bpm-refine's
    # surface refinement has the same parameter positions (one-region meshes only).
    surface_volumes=()
    for K in 0 1 2 3; do
        if "$bin/bpm-refine" "$work/$stem.bpm" --levels "$K" -o "$work/$stem.surface$K.off" -q; then
            surface_volumes+=(surface_volume_k$K "$("$py" - "$work/$stem.surface$K.off" <<'PY'
import sys
words = [w for line in open(sys.argv[1]) for w in line.split("#")[0].split()]
nv, nf = int(words[1]), int(words[2])
x = [float(w) for w in words[4:4 + 3 * nv]]
p = [(x[3 * i], x[3 * i + 1], x[3 * i + 2]) for i in range(nv)]
f = words[4 + 3 * nv:]
total = 0.0
for k in range(nf):
    a, b, c = (p[int(f[4 * k + j])] for j in (1, 2, 3))
    total += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]))
print(repr(total / 6))
PY
)")
            rm -f "$work/$stem.surface$K.off"
        fi
    done
    configs=(smooth)
    ((compare)) && configs+=(off)
    for config in "${configs[@]}"; do
        flags=()
        [[ $config == off ]] && flags=(--no-smooth)
        log "$name ($config): bpm-mesh"
        if ! timed "$bin/bpm-mesh" "$work/$stem.bpm" -o "$work/$stem.$config.k0.bpm" --json -q --deterministic \
                "${flags[@]}" > "$work/$stem.$config.k0.json"; then
            log "$name: bpm-mesh failed"; failed=1; continue
        fi
        record "$name" "$config" 0 "$work/$stem.$config.k0.json" simplify_wall "$simplify_wall" simplify_cpu "$simplify_cpu" \
            original_vertices "$orig_v" original_triangles "$orig_t" "${surface_volumes[@]}" \
            tetmesh_check_passed "$(tetmesh_check "$work/$stem.$config.k0.bpm")"
        tets0=$("$py" -c 'import json,sys; print(json.load(open(sys.argv[1]))["tetrahedra"])' "$work/$stem.$config.k0.json")
        for K in 1 2 3; do
            if ((tets0 * (1 << (3 * K)) > max_tets)); then
                echo "{\"name\": \"$name\", \"config\": \"$config\", \"K\": $K, \"skipped\": true}" >> "$rows"
                continue
            fi
            rflags=()
            [[ $config == off ]] && rflags=(--no-smooth --remedy-min-dihedral 0)
            log "$name ($config): refine K=$K"
            if ! timed "$bin/bpm-mesh" "$work/$stem.$config.k0.bpm" --existing --refine "$K" -o "$work/$stem.$config.k$K.bpm" \
                    --json -q --deterministic "${rflags[@]}" > "$work/$stem.$config.k$K.json"; then
                log "$name: refinement K=$K failed"; failed=1; continue
            fi
            record "$name" "$config" "$K" "$work/$stem.$config.k$K.json" \
                tetmesh_check_passed "$(tetmesh_check "$work/$stem.$config.k$K.bpm")"
            rm -f "$work/$stem.$config.k$K.bpm"
        done
    done
done  # targets
done

load_end="$(cut -d' ' -f1-3 /proc/loadavg)"
tetgen_version="$(dpkg-query -W -f '${Version}' tetgen 2>/dev/null || echo unknown)"
"$py" - "$rows" "$results_dir" "$started" "$load_start" "$load_end" "$tetgen_version" "$max_tets" "$(nproc)" <<'PY'
import json, sys, os, platform
rows = [json.loads(l) for l in open(sys.argv[1])]
out_dir, started, load_start, load_end, tetgen, max_tets, cores = sys.argv[2:9]
json.dump({"started": started, "load_average_start": load_start, "load_average_end": load_end, "tetgen": tetgen,
           "max_tets": int(max_tets), "rows": rows}, open(os.path.join(out_dir, "tetmesh.json"), "w"), indent=1)

def get(name, config, K):
    for r in rows:
        if r["name"] == name and r["config"] == config and r["K"] == K:
            return r
    return None

names = []
for r in rows:
    if r["name"] not in names:
        names.append(r["name"])
configs = [c for c in ("smooth", "off") if any(r["config"] == c for r in rows)]
L = []
w = L.append
w("# bpm-mesh and tetrahedral refinement (bench/tetmesh.sh)\n")
w("Started %s on %s cores (%s), load average %s at the start and %s at the end (the machine may be shared: "
  "CPU seconds are the steadier number). TetGen %s. Inputs simplified to 10%% of their vertices with "
  "`bpm-simplify --ratio 0.1 --deterministic` (rows named after the mesh) and to 1000 vertices with "
  "`--vertices 1000` (rows \"NAME 1000 V\"); `bpm-mesh` runs TetGen with `-pYzA -q1.414`; refinement is "
  "`bpm-mesh LEVEL0.bpm --existing --refine K`, each K from the level-0 mesh. Runs above %s tetrahedra are "
  "skipped.\n" % (started, cores, platform.machine(), load_start, load_end, tetgen, max_tets))
w("**smooth** is the default: TetGen's Steiner points are smoothed, and after every refinement level the "
  "interior vertices (bpm/tetmesh_smooth.h); boundary vertices stop short of phi where a tetrahedron would "
  "invert, keep less than 10% of its plain-refinement volume, or drop below an 8 degree dihedral angle, and "
  "are retried after smoothing. **off** is `--no-smooth --remedy-min-dihedral 0` (positive volume and the "
  "volume fraction only, no smoothing).\n")

w("## bpm-mesh\n")
w("| mesh | original V / T | coarse T | tet V | tets | Steiner | regions | min dihedral | TetGen s | bpm-mesh wall s | bpm-mesh CPU s | simplify wall s |")
w("|---|---|---|---|---|---|---|---|---|---|---|---|")
for n in names:
    r = get(n, "smooth", 0)
    if not r:
        continue
    w("| %s | %d / %d | %d | %d | %d | %d | %d | %.2f | %.2f | %.2f | %.2f | %.1f |" % (
        n, r["original_vertices"], r["original_triangles"], r["coarse_triangles"], r["vertices"], r["tetrahedra"],
        r["steiner_points"], len(r["regions"]), r["min_dihedral_degrees"], r["tetgen_seconds"], r["wall_seconds"],
        r["cpu_seconds"], r["simplify_wall"]))
w("")

def rel(g):
    return (g["volume"] - g["original_volume"]) / g["original_volume"] if g["original_volume"] else float("nan")

targets = []
for config in configs:
    w("## Refinement, %s\n" % config)
    w("Volume error = (meshed volume - volume enclosed by the original surface) / the latter, per region; "
      "reduction = error at K=0 / error at K. Error, all on S0: the same for the volume enclosed if every boundary "
      "vertex of level K were on the original surface (the surface refinement `bpm-refine --levels K`, one-region "
      "meshes): vertices held back outside a concave part add volume that cancels part of the chordal deficit of the "
      "convex parts, so a smaller volume error does not always mean a boundary closer to S0. Off S0: boundary "
      "vertices the lambda remedy keeps off the original surface, and their largest distance to it over the "
      "bounding-box diagonal.\n")
    w("| mesh | K | tets | region | volume error | reduction | error, all on S0 | inverted | min dihedral | < 1° | < 5° | < 10° | off S0 | max distance | refine s | wall s | CPU s | peak MiB |")
    w("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for n in names:
        base = get(n, config, 0)
        for K in range(4):
            r = get(n, config, K)
            if r is None:
                continue
            if r.get("skipped"):
                w("| %s | %d | skipped (above %s tetrahedra) |" % (n, K, max_tets) + " |" * 15)
                continue
            for i, g in enumerate(r["regions"]):
                e = rel(g)
                e0 = rel(base["regions"][i]) if base else float("nan")
                first = i == 0
                ideal = base.get("surface_volume_k%d" % K) if base and len(r["regions"]) == 1 else None
                w("| %s | %d | %s | %d | %+.3e | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                    n, K, r["tetrahedra"] if first else "", g["id"], e,
                    ("%.1fx" % (e0 / e) if e else "exact") if K else "",
                    "%+.3e" % ((ideal - g["original_volume"]) / g["original_volume"]) if ideal is not None else "",
                    r["inverted"] if first else "", "%.3f" % r["min_dihedral_degrees"] if first else "",
                    r.get("below_1_degree", "") if first else "", r.get("below_5_degrees", "") if first else "",
                    r.get("below_10_degrees", "") if first else "", r["remedied_vertices"] if first else "",
                    "%.2e" % (r["max_remedy_distance_relative"] or 0) if first else "",
                    "%.2f" % (r["refine_seconds"] or 0) if first and K else "",
                    "%.2f" % r["wall_seconds"] if first else "", "%.2f" % r["cpu_seconds"] if first else "",
                    "%.0f" % (r["rss_kib"] / 1024) if first else ""))
        # targets per region
        done = [get(n, config, K) for K in range(4)]
        if any(d is None or d.get("skipped") for d in done):
            targets.append((config, n, None, "not all of K=0..3 ran", None, None))
            continue
        inverted = sum(d["inverted"] for d in done)
        for i in range(len(done[0]["regions"])):
            errs = [abs(rel(d["regions"][i])) for d in done]
            # A level whose volume is exact (a polyhedral region such as two_cubes, where
            # the coarse surface is the original) cannot fall further: staying exact counts.
            monotone = all(errs[k + 1] < errs[k] or errs[k + 1] == errs[k] == 0 for k in range(3))
            factor = errs[0] / errs[3] if errs[3] else float("inf")
            targets.append((config, n, done[0]["regions"][i]["id"], monotone, factor, inverted))
    w("")

w("## Targets (K = 0..3)\n")
w("| config | mesh | region | error falls monotonically | reduction K=0→3 (≥ 8x) | inverted elements (0) | met |")
w("|---|---|---|---|---|---|---|")
for config, n, reg, monotone, factor, inverted in targets:
    if reg is None:
        w("| %s | %s | | %s | | | no |" % (config, n, monotone))
        continue
    ok = monotone and factor >= 8 and inverted == 0
    w("| %s | %s | %d | %s | %s | %d | %s |" % (config, n, reg, "yes" if monotone else "**no**",
                                              "exact" if factor == float("inf") else "%.1fx" % factor, inverted,
                                              "yes" if ok else "**no**"))
w("")

# Issue 19, "tets without slivers": the default configuration.
w("## Targets, dihedral angles (issue 19: min dihedral >= 5 degrees at K = 0 and >= 3 at K = 1..3, 0 inverted)\n")
w("*bpm-check*: levels whose file passes `bpm-check --checks tetmesh` (positive by exact orient3d, conforming, "
  "the faces on S covering every coarse triangle), out of those made.\n")
w("| mesh | K = 0 | K = 1 | K = 2 | K = 3 | inverted | bpm-check | met |")
w("|---|---|---|---|---|---|---|---|")
angle_met = []
for n in names:
    done = [get(n, "smooth", K) for K in range(4)]
    cells, ok = [], True
    for K, d in enumerate(done):
        if d is None or d.get("skipped"):
            cells.append("—")
            ok = False
            continue
        a = d["min_dihedral_degrees"]
        good = a >= (5 if K == 0 else 3)
        ok = ok and good
        cells.append("%.2f" % a if good else "**%.2f**" % a)
    inverted = sum(d["inverted"] for d in done if d and not d.get("skipped"))
    made = [d for d in done if d and not d.get("skipped")]
    checked = sum(1 for d in made if d.get("tetmesh_check_passed") == 1)
    ok = ok and inverted == 0 and checked == len(made)
    angle_met.append(ok)
    w("| %s | %s | %d | %s | %s |" % (n, " | ".join(cells), inverted,
                                      "%d / %d" % (checked, len(made)) if checked == len(made)
                                      else "**%d / %d**" % (checked, len(made)), "yes" if ok else "**no**"))
w("")
w("Met on %d of %d rows." % (sum(angle_met), len(angle_met)))
w("")
open(os.path.join(out_dir, "tetmesh.md"), "w").write("\n".join(L))
print("\n".join(L))
PY
log "wrote $results_dir/tetmesh.md and tetmesh.json"
exit "$failed"
