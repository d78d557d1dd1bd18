#!/usr/bin/env bash
# Benchmark of the repair a solver applies after refining its own grid
# (bpm::repair_boundary, bpm/boundary_repair.h).
#
# For each mesh (default femur; .data/meshes), simplified to 10% with bpm-simplify and
# meshed with bpm-mesh, bpm-bench-repair refines the tet mesh flat (red refinement, new
# boundary vertices at their edge midpoints, no smoothing) K times, to about 1 M
# tetrahedra for femur at K = 3, and times repair_boundary with its default options on it,
# 3 times on fresh copies: CPU seconds and wall seconds, the median of the 3, and the
# repair's report (boundary vertices held back short of phi, largest distance over the
# diagonal, smallest dihedral angle, inverted tetrahedra before/after). Two modes:
#   flat    all K levels flat, one repair at the end (every new boundary vertex at once);
#   solver  levels 1..K-1 each refined flat and repaired, then level K flat, and the timed
#           repair on it (what a solver does after each adapt step).
#
# Usage: bench/repair.sh [--no-build] [--build-dir DIR] [--work-dir DIR] [--results-dir DIR]
#                        [--meshes femur,...] [--levels K] [--repeat R]
#   --build-dir DIR    Release build with bpm-simplify, bpm-mesh, bpm-bench-repair in DIR/bin (default
#                      build-bench); without --no-build: cmake -S . -B DIR -DCMAKE_BUILD_TYPE=Release
#                      -DBPM_BUILD_TESTS=OFF and cmake --build DIR -j2 --target bpm-simplify bpm-mesh bpm-bench-repair
#   --work-dir DIR     scratch files (default DIR/bench-work/repair)
#   --results-dir DIR  where repair.md and repair.json go (default bench/results)
# Relative paths are taken from the repository root. Non-interactive; progress on stderr.
# Exit status: 0 when every run finished, 1 when a run failed, 2 on a usage error, 6 when
# tetgen is missing.
# Needs: tetgen on PATH (Debian package tetgen), /usr/bin/python3.
set -euo pipefail

here="$(cd "$(dirname "$0")/.." && pwd)"
cd "$here"
build_dir=build-bench
no_build=0
work=""
results_dir=bench/results
meshes="femur"
levels=3
repeat=3
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
        --levels) levels="${2:?--levels needs a number}"; shift ;;
        --repeat) repeat="${2:?--repeat needs a number}"; shift ;;
        -h|--help) usage; exit 0 ;;
        *) echo "repair.sh: unknown argument '$1'" >&2; usage >&2; exit 2 ;;
    esac
    shift
done
[[ "$levels" =~ ^[1-9]$ && "$repeat" =~ ^[1-9][0-9]*$ ]] || { echo "repair.sh: --levels 1..9, --repeat >= 1" >&2; exit 2; }
py=/usr/bin/python3
log() { echo "repair.sh: $*" >&2; }
command -v tetgen >/dev/null || { log "tetgen not on PATH (Debian package 'tetgen')"; exit 6; }

if ((!no_build)); then
    log "building bpm-simplify, bpm-mesh and bpm-bench-repair in $build_dir (Release)"
    cmake -S "$here" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DBPM_BUILD_TESTS=OFF >&2
    cmake --build "$build_dir" -j2 --target bpm-simplify bpm-mesh bpm-bench-repair >&2
fi
bin="$(cd "$build_dir" && pwd)/bin"
for tool in bpm-simplify bpm-mesh bpm-bench-repair; do
    [[ -x "$bin/$tool" ]] || { log "no $tool in $bin (drop --no-build?)"; exit 2; }
done
[[ -n "$work" ]] || work="$build_dir/bench-work/repair"
mkdir -p "$work" "$results_dir"
work="$(cd "$work" && pwd)"
results_dir="$(cd "$results_dir" && pwd)"
rows="$work/rows.jsonl"
: > "$rows"
load_start="$(cut -d' ' -f1-3 /proc/loadavg)"
started="$(date -u +%Y-%m-%dT%H:%M:%SZ)"
failed=0

IFS=, read -r -a names <<< "$meshes"
for name in "${names[@]}"; do
    input="$here/.data/meshes/$name.off"
    [[ -f "$input" ]] || { log "$input is missing (scripts/setup.sh unpacks the meshes)"; failed=1; continue; }
    log "$name: bpm-simplify --ratio 0.1, bpm-mesh"
    if ! "$bin/bpm-simplify" "$input" -o "$work/$name.bpm" --ratio 0.1 --deterministic -q ||
       ! "$bin/bpm-mesh" "$work/$name.bpm" -o "$work/$name.tet.bpm" --deterministic -q; then
        log "$name: bpm-simplify or bpm-mesh failed"; failed=1; continue
    fi
    for mode in flat solver; do
        log "$name: repair after $levels flat levels ($mode), $repeat runs"
        if ! "$bin/bpm-bench-repair" "$work/$name.tet.bpm" --levels "$levels" --mode "$mode" --repeat "$repeat" \
                > "$work/$name.$mode.json"; then
            log "$name: bpm-bench-repair failed"; failed=1; continue
        fi
        "$py" -c 'import json, sys; d = json.load(open(sys.argv[1])); d["name"] = sys.argv[2]; print(json.dumps(d))' \
            "$work/$name.$mode.json" "$name" >> "$rows"
    done
done

load_end="$(cut -d' ' -f1-3 /proc/loadavg)"
"$py" - "$rows" "$results_dir" "$started" "$load_start" "$load_end" "$levels" "$repeat" "$(nproc)" <<'PY'
import json, os, platform, subprocess, sys
rows_path, results_dir, started, load_start, load_end, levels, repeat, cores = sys.argv[1:9]
rows = [json.loads(line) for line in open(rows_path) if line.strip()]
cpu = "unknown"
for line in open("/proc/cpuinfo"):
    if line.startswith("model name"):
        cpu = line.split(":", 1)[1].strip()
        break
try:
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    # (the results themselves do not count: RESULTS.md may be edited while this runs)
    if subprocess.run(["git", "--no-optional-locks", "status", "--porcelain", "--untracked-files=no", "--", ".",
                       ":!bench/RESULTS.md", ":!bench/results"],
                      capture_output=True, text=True).stdout.strip():
        commit += " with uncommitted changes"
except OSError:
    commit = "unknown"
meta = dict(started=started, load_start=load_start, load_end=load_end, levels=int(levels), repeat=int(repeat),
            cpu=cpu, cores=int(cores), commit=commit or "unknown", system=platform.platform())
json.dump(dict(meta=meta, rows=rows), open(os.path.join(results_dir, "repair.json"), "w"), indent=1)
out = ["# Repair after a solver refines (bench/repair.sh)", "",
       f"Measured {started}, {cpu}, {cores} cores, load average at start {load_start} (end {load_end}); bpm commit "
       f"{meta['commit']}. Generated by `bench/repair.sh`.", "",
       f"Each mesh is simplified to 10 % (`bpm-simplify --ratio 0.1`), meshed (`bpm-mesh`), red-refined {levels} times "
       "without phi (new boundary vertices at their edge midpoints, as a solver's own refinement leaves them; no "
       "smoothing), and `bpm::repair_boundary` with its default options (bisection 30 steps, volume fraction 0.1, "
       "dihedral guard 5 degrees, 4 retry passes, interior smoothing) moves the boundary vertices towards phi. "
       "**flat**: all levels flat, one repair at the end; **solver**: levels 1.."
       f"{int(levels) - 1} each refined flat and repaired, then level {levels} flat and the timed repair (what a "
       "solver does after each adapt step). Times: the repair call alone (single-threaded), "
       f"median of {repeat} runs on fresh copies; CPU = process CPU time. Held back: boundary vertices left short of "
       "phi (the §3.3 remedy), with the largest distance to phi over the bounding-box diagonal of the mesh.", "",
       "| mesh | mode | tetrahedra | vertices | boundary vertices | moved (not at phi before) | held back | max distance / diagonal | min dihedral (degrees) | inverted before / after | CPU s (median) | wall s (median) | of which smoothing, wall s | CPU s (runs) |",
       "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
for r in rows:
    out.append("| {} | {} | {:,} | {:,} | {:,} | {:,} | {:,} | {:.3g} | {:.3g} | {} / {} | {:.2f} | {:.2f} | {:.2f} | {} |".format(
        r["name"], r["mode"], r["tetrahedra"], r["vertices"], r["boundary_vertices"],
        r["boundary_vertices"] - r["at_phi_before"], r["held_back"], r["max_distance_relative"],
        r["min_dihedral_degrees"], r["inverted_before"], r["inverted_after"], r["cpu_seconds_median"],
        r["wall_seconds_median"], r["smoothing_wall_seconds_median"], ", ".join("%.2f" % c for c in r["cpu_seconds"])))
open(os.path.join(results_dir, "repair.md"), "w").write("\n".join(out) + "\n")
print("\n".join(out))
PY
exit $failed
