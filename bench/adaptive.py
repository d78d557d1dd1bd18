#!/usr/bin/python3
"""Adaptive refinement: is the error bound met, and at how many triangles (issue 19, bench/README.md).

    /usr/bin/python3 bench/adaptive.py [--no-build] [--build-dir DIR] [--results-dir DIR] [--work-dir DIR]
                                       [--meshes a,b,c] [--tolerances 0.003,0.001,0.0003] [options]

For every mesh (default femur, fandisk, elephant, armadillo, mech-holes-shark from .data/meshes), both
coarse sizes (10 % of the input vertices and 1000 vertices) and every tolerance T:

  bpm-simplify IN.off -o COARSE.bpm (--ratio 0.1 | --vertices 1000) --deterministic
  bpm-refine COARSE.bpm --max-error T -o OUT.off --json > OUT.json     (default options: new vertices held
                                                                       back where they would make the surface
                                                                       intersect itself)
  bpm-bench-metrics IN.off OUT.off --samples N                         (an independent sampled two-sided
                                                                       Hausdorff distance / diagonal, CGAL AABB
                                                                       tree, and OUT's self-intersections)

and writes RESULTS_DIR/adaptive.md and adaptive.json (default bench/results), rewritten after every run.
Work files go to WORK_DIR (default BUILD_DIR/bench-work/adaptive), never into the source tree.

Target (issue 19): the measured Hausdorff distance is at most T on every row for T = 0.003, 0.001, 0.0003;
the triangle count needed for T = 0.001, as a multiple of the original's, is in the table (aim: <= 4x).
"""
import argparse
import json
import os
import shlex
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run import (binary_line, cpu_model, git_commit, load_average, memory_gib, read_off_header, rel,  # noqa: E402
                 utcnow, write_atomic)
from refine import Runner, load_json  # noqa: E402  (the timed command runner of bench/refine.py; logs as refine.py)

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)
MESHES = os.path.join(ROOT, ".data", "meshes")
RESULTS = os.path.join(BENCH, "results")
DEFAULT_MESHES = ["femur", "fandisk", "elephant", "armadillo", "mech-holes-shark"]
TARGETS = [("10%", "r10", ["--ratio", "0.1"]), ("1000 V", "v1000", ["--vertices", "1000"])]
BUILD_TARGETS = ["bpm-simplify", "bpm-refine", "bpm-bench-metrics"]
TRIANGLE_AIM = 4.0      # triangles for T = 0.001 / original triangles (the aim)
AIM_TOLERANCE = 0.001


def log(msg):
    sys.stderr.write(f"[{utcnow():%H:%M:%S}] adaptive.py: {msg}\n")
    sys.stderr.flush()


def build(build_dir, jobs):
    import subprocess
    configure = ["cmake", "-S", ROOT, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release"]
    compile_ = ["cmake", "--build", build_dir, f"-j{jobs}", "--target"] + BUILD_TARGETS
    log(f"building in {build_dir} (Release): {' '.join(BUILD_TARGETS)}")
    subprocess.run(configure, check=True, stdout=subprocess.DEVNULL)
    subprocess.run(compile_, check=True, stdout=subprocess.DEVNULL)
    return [configure, compile_]


def run_row(args, bins, runner, mesh, label, tag, sim_opts):
    inp = os.path.join(MESHES, mesh + ".off")
    stem = f"{mesh}-{tag}"
    coarse = os.path.join(args.work_dir, stem + ".bpm")
    row = {"mesh": mesh, "target": label, "tag": tag, "input": rel(inp), "runs": []}
    row["original_vertices"], row["original_triangles"] = read_off_header(inp)
    row["simplify"] = runner.run([bins["bpm-simplify"], inp, "-o", coarse] + sim_opts + ["--deterministic"],
                                 stem + "-simplify")
    if row["simplify"]["status"] != "ok":
        return row
    for t in args.tolerances:
        run = {"tolerance": t}
        out = os.path.join(args.work_dir, f"{stem}.T{t:g}.off")
        report = os.path.join(args.work_dir, f"{stem}.T{t:g}.json")
        r = runner.run([bins["bpm-refine"], coarse, "--max-error", f"{t:g}", "-o", out, "--json"],
                       f"{stem}-T{t:g}-refine", stdout_path=report)
        run["refine"] = r
        run["report"] = load_json(report)
        if r["status"] == "ok":
            metrics = os.path.join(args.work_dir, f"{stem}.T{t:g}.metrics.json")
            m = runner.run([bins["bpm-bench-metrics"], inp, out, "--samples", str(args.samples),
                            "--min-per-triangle", str(args.min_per_triangle)],
                           f"{stem}-T{t:g}-metrics", stdout_path=metrics)
            run["metrics_run"] = m
            run["metrics"] = load_json(metrics) if m["status"] == "ok" else None
        row["runs"].append(run)
    return row


def measured(run):
    d = ((run.get("metrics") or {}).get("distance") or {})
    return d.get("hausdorff_relative")


def self_intersections(run):
    m = run.get("metrics") or {}
    c = m.get("coarse") or {}
    return c.get("self_intersecting_pairs")


def met(run):
    """The issue's target: the measured (sampled) Hausdorff distance is at most T."""
    h = measured(run)
    return None if h is None else h <= run["tolerance"]


def bound_met(run):
    """bpm-refine proved it: its bound is at most T (stricter; a fold of phi can keep it above)."""
    rep = run.get("report") or {}
    return None if "hausdorff_bound" not in rep else rep["hausdorff_bound"] <= run["tolerance"]


def f(v, spec):
    return "—" if v is None else format(v, spec)


def markdown(header, rows):
    out = ["# Adaptive refinement: error bound and triangle count (issue 19)", "",
           f"Generated by `{header['invocation']}` on {header['started']} UTC, commit {header['commit']}, "
           f"{header['cpu']} ({header['cores']} cores, load {header['load_start'][0]:.1f} at the start; CPU seconds "
           f"are user + system of /usr/bin/time), binaries `{header['binary']}`.", "",
           "Per row: `bpm-simplify IN.off --ratio 0.1 | --vertices 1000 --deterministic`, then per tolerance T "
           "`bpm-refine COARSE.bpm --max-error T -o OUT.off --json` (default options) and "
           f"`bpm-bench-metrics IN.off OUT.off --samples {header['samples']} --min-per-triangle "
           f"{header['min_per_triangle']}` (sampled two-sided Hausdorff distance ÷ the original's bounding-box "
           "diagonal, CGAL AABB tree; independent of bpm-refine's bound). *bound* = the proven two-sided "
           "Hausdorff bound bpm-refine reports (max over every refined triangle of |flat − φ| over its overlay with "
           "φ's pieces, held-back vertices where they are); *held back* = vertices kept short of φ so that the "
           "surface does not intersect itself, and the farthest one's distance from φ ÷ diagonal; *unmet* = "
           "triangles whose bound is above T (at --max-level, or after the last pass of refining around held-back "
           "vertices); *self-int.* = intersecting triangle pairs of OUT.off "
           "(bpm-bench-metrics). **met** = measured ≤ T (the issue's target); *proved* = bound ≤ T.", "",
           "| mesh | target | T | triangles | ÷ original | level | bound | held back (n / max) | unmet | "
           "measured H | self-int. | met | proved | CPU s |",
           "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---:|"]
    summary = []
    for row in rows:
        for run in row["runs"]:
            rep = run.get("report") or {}
            tri = rep.get("triangles")
            ratio = tri / row["original_triangles"] if tri and row.get("original_triangles") else None
            m = met(run)
            cpu = (run.get("refine") or {}).get("cpu_seconds")
            held = f"{rep['held_back_vertices']} / {rep['max_held_back']:.2e}" if rep.get(
                "held_back_vertices") else ("0" if rep else "—")
            out.append(f"| {row['mesh']} | {row['target']} | {run['tolerance']:g} | {f(tri, 'd')} | {f(ratio, '.2f')}x | "
                       f"{f(rep.get('max_level'), 'd')} | {f(rep.get('hausdorff_bound'), '.3e')} | {held} | "
                       f"{f(rep.get('triangles_above_max_error'), 'd')} | {f(measured(run), '.3e')} | "
                       f"{f(self_intersections(run), 'd')} | "
                       f"{'—' if m is None else ('met' if m else '**not met**')} | "
                       f"{'—' if bound_met(run) is None else ('yes' if bound_met(run) else 'no')} | {f(cpu, '.2f')} |")
            if m is not None:
                summary.append(m)
            if run["tolerance"] == AIM_TOLERANCE and ratio is not None:
                row["aim_ratio"] = ratio
    proved = [bound_met(run) for row in rows for run in row["runs"] if bound_met(run) is not None]
    out += ["", f"Measured distance at most T on {sum(summary)} of {len(summary)} runs; bound at most T (proved) on "
                f"{sum(proved)} of {len(proved)}."]
    aims = [(r["mesh"], r["target"], r["aim_ratio"]) for r in rows if "aim_ratio" in r]
    if aims:
        over = [f"{m} {t} {x:.2f}x" for m, t, x in aims if x > TRIANGLE_AIM]
        out.append(f"Triangles for T = {AIM_TOLERANCE:g} ÷ original: {min(a[2] for a in aims):.2f}x to "
                   f"{max(a[2] for a in aims):.2f}x; above the aim of {TRIANGLE_AIM:g}x: "
                   f"{', '.join(over) if over else 'none'}.")
    notes = []
    for row in rows:
        for run in row["runs"]:
            rep = run.get("report") or {}
            for u in (rep.get("above_max_error") or [])[:3]:
                notes.append(f"- {row['mesh']} {row['target']} T = {run['tolerance']:g}: refined triangle "
                             f"{u['triangle']} (coarse triangle {u['coarse_triangle']}, level {u['level']}) at "
                             f"({', '.join(f'{x:.4g}' for x in u['at'])}): bound {u['bound']:.3e}")
    if notes:
        out += ["", "Where the bound stays above T at --max-level (the worst three per run, from bpm-refine "
                    "--json):", ""] + notes
    failures = [(row, run) for row in rows for run in row["runs"] if (run.get("refine") or {}).get("status") != "ok"]
    failures += [(row, None) for row in rows if (row.get("simplify") or {}).get("status") != "ok"]
    if failures:
        out += ["", "Runs that failed:", ""]
        for row, run in failures:
            r = run["refine"] if run else row["simplify"]
            out.append(f"- {row['mesh']} {row['target']}{' T = %g' % run['tolerance'] if run else ''}: "
                       f"{r.get('message', r.get('status'))} (log `{rel(r['log'])}`)")
    return "\n".join(out) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build-dir", default=os.path.join(ROOT, "build-bench"))
    ap.add_argument("--no-build", action="store_true", help="use the binaries already in BUILD_DIR/bin")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--results-dir", default=RESULTS, help="where adaptive.md / adaptive.json go (default bench/results)")
    ap.add_argument("--work-dir", help="scratch files (default BUILD_DIR/bench-work/adaptive)")
    ap.add_argument("--meshes", default=",".join(DEFAULT_MESHES), help="comma-separated names in .data/meshes")
    ap.add_argument("--targets", default="r10,v1000", help="coarse sizes: r10 (10 %%), v1000 (1000 vertices)")
    ap.add_argument("--tolerances", default="0.003,0.001,0.0003", help="bpm-refine --max-error values")
    ap.add_argument("--samples", type=int, default=500000, help="bpm-bench-metrics --samples")
    ap.add_argument("--min-per-triangle", type=int, default=1, help="bpm-bench-metrics --min-per-triangle")
    ap.add_argument("--timeout", type=int, default=1800, help="seconds per command")
    args = ap.parse_args()
    invocation = shlex.join(["/usr/bin/python3", "bench/adaptive.py"] + sys.argv[1:])
    args.build_dir = os.path.abspath(args.build_dir)
    args.results_dir = os.path.abspath(args.results_dir)
    args.work_dir = os.path.abspath(args.work_dir or os.path.join(args.build_dir, "bench-work", "adaptive"))
    args.meshes = [m for m in args.meshes.split(",") if m]
    args.tolerances = [float(x) for x in args.tolerances.split(",") if x]
    targets = [t for t in TARGETS if t[1] in args.targets.split(",")]
    missing = [m for m in args.meshes if not os.path.exists(os.path.join(MESHES, m + ".off"))]
    if missing:
        sys.exit(f"adaptive.py: error: not in {rel(MESHES)}: {', '.join(m + '.off' for m in missing)} "
                 "(scripts/setup.sh unpacks them)")
    os.makedirs(args.work_dir, exist_ok=True)
    os.makedirs(args.results_dir, exist_ok=True)

    t_start = time.monotonic()
    header = {"started": f"{utcnow():%Y-%m-%d %H:%M}", "load_start": list(load_average()), "cpu": cpu_model(),
              "cores": os.cpu_count(), "memory_gib": memory_gib(), "commit": git_commit(), "invocation": invocation,
              "build_dir": args.build_dir, "tolerances": args.tolerances, "samples": args.samples,
              "min_per_triangle": args.min_per_triangle, "timeout": args.timeout}
    header["build"] = None if args.no_build else build(args.build_dir, args.jobs)
    bins = {t: os.path.join(args.build_dir, "bin", t) for t in BUILD_TARGETS}
    for t, p in bins.items():
        if not os.access(p, os.X_OK):
            sys.exit(f"adaptive.py: error: {p} missing (build first, or leave out --no-build)")
    header["binary"] = binary_line(bins["bpm-refine"])
    runner = Runner(args.work_dir, args.timeout)
    header["commands"] = runner.commands
    md_path, json_path = os.path.join(args.results_dir, "adaptive.md"), os.path.join(args.results_dir, "adaptive.json")
    rows = []

    def write():
        write_atomic(md_path, markdown(header, rows))
        write_atomic(json_path, json.dumps({"header": header, "rows": rows}, indent=1, default=str) + "\n")

    for mesh in args.meshes:
        for label, tag, opts in targets:
            rows.append(run_row(args, bins, runner, mesh, label, tag, opts))
            write()
    header["finished"] = f"{utcnow():%Y-%m-%d %H:%M}"
    header["minutes"] = (time.monotonic() - t_start) / 60.0
    header["load_end"] = list(load_average())
    write()
    log(f"wrote {rel(md_path)} and {rel(json_path)}")
    failed = [r for r in rows if (r.get("simplify") or {}).get("status") != "ok" or any(
        (x.get("refine") or {}).get("status") != "ok" for x in r["runs"])]
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
