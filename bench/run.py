#!/usr/bin/python3
"""bpm benchmark driver (bench/README.md).

    /usr/bin/python3 bench/run.py [simplify | scaling | check | all] [--quick] [options]
    bench/all.sh [--quick] [options]          (= run.py all)

simplify  bpm-simplify vs psurface-simplify vs CGAL's edge-collapse decimation (a plain
          decimation without a parametrization, the reference) on real meshes at 10 % of
          the input vertices and at 1000 vertices: time, peak memory, bpm-bench-metrics on
          every output, bpm-check on bpm's output -> results/simplify.{md,json}
scaling   bpm-simplify (2 threads and 1 thread) and CGAL's edge collapse to 10,000 vertices on
          armadillo after 0, 1, 2, 3 Loop subdivisions (52k / 208k / 832k / 3.3 M triangles)
          -> results/scaling.{md,json}
check     bpm-check on the scaling suite's outputs (52k / 208k / 832k original triangles):
          all four checks together and each alone, seconds and triangles / pieces per
          second -> results/check.{md,json}
all       the one command: builds every tool once in Release, runs simplify, scaling and
          check (each as `run.py SUITE --no-build ...`), then bench/refine.py (refinement
          convergence, shape, phi throughput; if present), bench/adaptive.py (adaptive
          refinement: bound met, triangles; if present), bench/tetmesh.sh (tet meshes),
          bench/repair.sh (the repair call on a 1 M-tet mesh; if present) and
          bench/corpus.sh (the whole libcgal-demo corpus), and writes bench/RESULTS.md:
          machine, date, commit, every command run, every table, then the sections written
          by hand (bench/results/manual/*.md, in the order of MANUAL_SECTIONS). The run
          itself (machine, commands, exit codes, times) is recorded in results/all.json.

--assemble  (all only) rewrites RESULTS.md from results/all.json, the results/*.md it
          names and the hand-written sections, without building or running anything: for
          after editing a section by hand or a results file.

--quick   fewer meshes, fewer subdivision levels, fewer samples, shorter timeouts, for
          trying it out. Its tables go to BUILD_DIR/bench-quick/ (RESULTS.md and results/),
          never over bench/results; see bench/README.md for the external scripts.

A single suite builds only the tools it needs in Release first (--no-build skips that).
Everything generated besides the results (converted meshes, subdivided meshes, .bpm / .vtu /
.off outputs, logs) goes to BUILD_DIR/bench-work, never into the source tree. Results are
rewritten after every run, so an interrupted run leaves what it measured.
"""
import argparse
import datetime
import glob
import json
import math
import os
import platform
import shlex
import shutil
import signal
import statistics
import subprocess
import sys
import threading
import time

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)
MESHES = os.path.join(ROOT, ".data", "meshes")
RESULTS = os.path.join(BENCH, "results")
PYTHON = "/usr/bin/python3"
DEFAULT_MESHES = ["femur", "fandisk", "elephant", "armadillo", "mech-holes-shark"]
TOOLS = ("bpm", "psurface", "cgal")
TOOL_LABEL = {"bpm": "bpm", "psurface": "psurface", "cgal": "CGAL (no φ)"}
RATIO_LABEL = {"psurface": "psurface", "cgal": "CGAL"}
CHECKS = ("format", "intersections", "topology", "bijectivity")
SUITE_TARGETS = {
    "simplify": ["bpm-simplify", "bpm-check", "bpm-bench-metrics", "bpm-bench-cgal-decimate"],
    "scaling": ["bpm-simplify", "bpm-bench-cgal-decimate"],
    "check": ["bpm-simplify", "bpm-check"],
}

# Values of the options that --quick changes, full run first. None in argparse means "not given".
PROFILES = {
    "meshes": (",".join(DEFAULT_MESHES), "femur,elephant"),
    "timeout": (900, 300),
    "samples": (500000, 100000),
    "levels": ("0,1,2,3", "0,1"),
    "scaling_repeats": (3, 1),
    "scaling_timeout": (900, 300),
    "check_levels": ("0,1,2", "0,1"),
    "check_timeout": (900, 300),
    "check_repeats": (3, 1),
    "repeats": (3, 1),
    "external_timeout": (7200, 1800),
}
# The sections of RESULTS.md written by hand (measurements run by hand, analyses), one file
# each in bench/results/manual/, appended after the generated ones in this order; and
# remarks written by hand on a step's tables, manual/after-STEP.md, appended to the section
# of step STEP (the `name` of its step in all_suites). Edit them there: RESULTS.md is
# regenerated. A file in that folder that is neither listed here nor after-STEP.md, or a
# listed one that is missing, is an error, so that no section is silently dropped.
MANUAL = os.path.join(RESULTS, "manual")
MANUAL_SECTIONS = [
    "solvers-dune-torsion.md",
    "solvers-adaptive-ug-and-interfaces.md",
    "solvers-adaptive-ug-one-adapt-per-level.md",
    "inverse-phi-throughput.md",
    "floor-bpm-size-and-memory.md",
    "floor4.md",
    "simplifier-structure-perf.md",
    "tets-without-slivers-and-phi-distortion.md",
    "convergence-limits-and-distortion-weight.md",
    "adaptive-bound-and-triangles.md",
    "output-formats.md",
    "input-slivers-first.md",
    "tet-refinement-best-diagonal.md",
    "coarse-ridges.md",
    "folds-and-convergence.md",
    "input-slivers-d2.md",
    "planar-regions-drift.md",
    "feature-angle-and-convergence.md",
    "crease-chains.md",
    "adaptive-fold-splitting.md",
    "loop4.md",
    "morton.md",
    "nodeimage.md",
    "cad-fans.md",
    "self-intersection-repair.md",
]
RUN_RECORD = "all.json"  # in the results folder: what `all` ran, for --assemble
QUICK_REFINE_MESHES = "femur"
QUICK_TETMESH_MESHES = "femur,two_cubes"
QUICK_MAX_TETS = "2000000"


def log(msg):
    sys.stderr.write(f"[{utcnow():%H:%M:%S}] {msg}\n")
    sys.stderr.flush()


def utcnow():
    return datetime.datetime.now(datetime.timezone.utc)


# ---------------------------------------------------------------- helpers

def build(build_dir, jobs, targets=None):
    """Release build in build_dir: the given targets, or the default target (every tool and bench tool)."""
    configure = ["cmake", "-S", ROOT, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release", "-DBPM_BUILD_TESTS=OFF"]
    compile_ = ["cmake", "--build", build_dir, f"-j{jobs}"] + (["--target"] + targets if targets else [])
    log(f"building in {build_dir} (Release): {' '.join(targets) if targets else 'all targets'}")
    subprocess.run(configure, check=True, stdout=subprocess.DEVNULL)
    subprocess.run(compile_, check=True, stdout=subprocess.DEVNULL)
    return [configure, compile_]


def read_off_header(path):
    with open(path) as f:
        tokens = []
        for line in f:
            tokens.extend(line.split("#", 1)[0].split())
            if len(tokens) >= 3:
                break
    return int(tokens[1]), int(tokens[2])


def off_to_msh22(off_path, msh_path):
    """Gmsh 2.2 ASCII copy of an OFF triangle mesh (coordinates copied as text, exactly)."""
    if os.path.exists(msh_path) and os.path.getmtime(msh_path) >= os.path.getmtime(off_path):
        return
    with open(off_path) as f:
        tokens = []
        for line in f:
            tokens.extend(line.split("#", 1)[0].split())
    nv, nf = int(tokens[1]), int(tokens[2])
    at = 4
    tmp = msh_path + ".tmp"
    with open(tmp, "w") as o:
        o.write(f"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n{nv}\n")
        for i in range(nv):
            o.write(f"{i + 1} {tokens[at]} {tokens[at + 1]} {tokens[at + 2]}\n")
            at += 3
        o.write(f"$EndNodes\n$Elements\n{nf}\n")
        for i in range(nf):
            if tokens[at] != "3":
                raise ValueError(f"{off_path}: face {i} is not a triangle")
            a, b, c = (int(t) + 1 for t in tokens[at + 1:at + 4])
            o.write(f"{i + 1} 2 2 0 0 {a} {b} {c}\n")
            at += 4
        o.write("$EndElements\n")
    os.replace(tmp, msh_path)


def timed(cmd, log_path, timeout, cwd=None, stdout_path=None):
    """Runs cmd under `timeout` and /usr/bin/time; returns dict(status, seconds (wall), cpu_seconds (user + system),
    peak_mb (maximum resident set size), exit, message). Standard output goes to stdout_path when given, else to the
    log with standard error."""
    time_file = log_path + ".time"
    if os.path.exists(time_file):
        os.remove(time_file)
    full = ["/usr/bin/time", "-f", "%e %M %U %S", "-o", time_file, "timeout", "--kill-after=10", str(timeout)] + cmd
    with open(log_path, "w") as lf:
        lf.write("$ " + " ".join(cmd) + "\n")
        lf.flush()
        out = open(stdout_path, "w") if stdout_path else lf
        try:
            start = time.monotonic()
            proc = subprocess.run(full, stdout=out, stderr=lf, cwd=cwd)
            wall = time.monotonic() - start
        finally:
            if stdout_path:
                out.close()
    r = {"exit": proc.returncode, "seconds": None, "cpu_seconds": None, "peak_mb": None, "message": ""}
    try:
        with open(time_file) as tf:
            line = [l for l in tf.read().splitlines() if l.strip()][-1].split()
            r["seconds"], r["peak_mb"] = float(line[0]), float(line[1]) / 1024.0
            r["cpu_seconds"] = float(line[2]) + float(line[3])
    except (OSError, IndexError, ValueError):
        r["seconds"] = wall
    if proc.returncode == 0:
        r["status"] = "ok"
    elif proc.returncode in (124, 137):
        r["status"] = "timeout"
        r["message"] = f"no result after {timeout} s"
    else:
        r["status"] = "failed"
        with open(log_path, errors="replace") as lf:
            lines = [l.strip() for l in lf.read().splitlines()[1:] if l.strip() and not l.startswith("Command ")]
        errors = [l for l in lines if "error" in l.lower()]
        r["message"] = f"exit {proc.returncode}: " + ((errors or lines or [""])[-1])[:200]
    return r


def run_json(cmd, timeout):
    """Runs a command that prints JSON; returns (exit code, parsed JSON or None, stderr tail)."""
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, None, f"timeout after {timeout} s"
    try:
        data = json.loads(p.stdout) if p.stdout.strip() else None
    except json.JSONDecodeError:
        data = None
    return p.returncode, data, p.stderr.strip()[-300:]


def fmt(v, spec):
    return "—" if v is None else format(v, spec)


def write_atomic(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def rel(path):
    """A path as it is typed from the repository root (commands are run there)."""
    p = os.path.relpath(path, ROOT)
    return path if p.startswith("..") else p


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def memory_gib():
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemTotal:"):
                    return int(line.split()[1]) / 1024.0 / 1024.0
    except (OSError, ValueError):
        pass
    return None


def load_average():
    try:
        return os.getloadavg()
    except OSError:
        return (float("nan"),) * 3


def machine_line():
    load = load_average()[0]
    mem = memory_gib()
    return (f"{utcnow():%Y-%m-%d %H:%M} UTC, {cpu_model()}, {os.cpu_count()} cores"
            f"{'' if mem is None else f', {mem:.1f} GiB'}, load average at start {load:.1f}")


def binary_line(path):
    """'bpm-simplify 0.1.0 (bpm format 1.0), built 2026-11-22 04:13 UTC' for the results header."""
    try:
        version = subprocess.run([path, "--version"], capture_output=True, text=True).stdout.strip()
        built = datetime.datetime.fromtimestamp(os.path.getmtime(path), datetime.timezone.utc)
        return f"{version}, built {built:%Y-%m-%d %H:%M} UTC"
    except OSError:
        return "unknown"


def git_commit():
    """Short commit of the working tree, read-only (--no-optional-locks: never writes the index)."""
    try:
        git = ["git", "--no-optional-locks", "-C", ROOT]
        c = subprocess.run(git + ["rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
        # The results this very run rewrites do not count as changes to what is measured.
        dirty = subprocess.run(git + ["status", "--porcelain", "--untracked-files=no", "--", ".",
                                      ":(exclude)bench/results", ":(exclude)bench/RESULTS.md"],
                               capture_output=True, text=True).stdout.strip()
        return (c or "unknown") + (" (with uncommitted changes)" if dirty else "")
    except OSError:
        return "unknown"


def subdivided_mesh(level, work):
    """armadillo.off (level 0) or its Loop subdivision, made by make_subdivided.py when missing or stale."""
    base = os.path.join(MESHES, "armadillo.off")
    if level == 0:
        return base
    path = os.path.join(work, f"armadillo-loop{level}.off")
    if not os.path.exists(path) or os.path.getmtime(path) < os.path.getmtime(base):
        log(f"Loop subdivision level {level} -> {path}")
        subprocess.run([PYTHON, os.path.join(BENCH, "make_subdivided.py"), base, str(level), path], check=True)
    return path


def scaling_output(work, level, target):
    return os.path.join(work, f"armadillo-loop{level}-{target}.bpm")


def level_label(level):
    return "armadillo.off" if level == 0 else f"armadillo + {level}x Loop"


# ---------------------------------------------------------------- simplify suite

def metrics_cell(m):
    """Short quality fields of a bpm-bench-metrics JSON (or None)."""
    if not m:
        return None
    c = m["coarse"]
    return {
        "vertices": c["vertices"], "triangles": c["triangles"],
        "hausdorff_relative": m["distance"]["hausdorff_relative"],
        "mean_relative": m["distance"]["mean_two_sided_relative"],
        "aspect_max": c["aspect_ratio"]["max"], "aspect_mean": c["aspect_ratio"]["mean"],
        "self_intersecting_pairs": c["self_intersecting_pairs"],
        "topology_preserved": m["topology_preserved"],
    }


def simplify_suite(args, bins, work):
    rows = []
    json_path = os.path.join(args.results_dir, f"simplify{args.suffix}.json")
    md_path = os.path.join(args.results_dir, f"simplify{args.suffix}.md")
    header = {"date": machine_line(), "commit": git_commit(), "binary": binary_line(bins["bpm-simplify"]),
              "timeout_s": args.timeout, "tools": args.tools,
              "metrics_samples": args.samples, "psurface_flags": args.psurface_flags, "bpm_flags": args.bpm_flags,
              "repeats": args.repeats}
    for name in args.meshes:
        off = os.path.join(MESHES, name + ".off")
        if not os.path.exists(off):
            rows.append({"mesh": name, "error": f"{off} not found (run scripts/setup.sh)"})
            continue
        nv, nt = read_off_header(off)
        msh = os.path.join(work, name + ".msh")
        if "psurface" in args.tools:
            off_to_msh22(off, msh)
        for label, target in (("10%", max(4, round(0.1 * nv))), ("1000", 1000)):
            row = {"mesh": name, "input_vertices": nv, "input_triangles": nt, "target_label": label,
                   "target_vertices": target}
            stem = os.path.join(work, f"{name}-{target}{args.suffix}")
            if target >= nv:
                row["error"] = f"target {target} >= input vertices {nv}"
                rows.append(row)
                continue
            outputs = {"bpm": stem + ".bpm", "psurface": stem + "-psurface.vtu", "cgal": stem + "-cgal.off"}
            # Only the tools asked for: the others' binaries may not have been built.
            commands = {
                "bpm": lambda: ([bins["bpm-simplify"], off, "-o", outputs["bpm"], "--vertices", str(target)]
                                + args.bpm_flags.split(), None),
                "psurface": lambda: (["psurface-simplify", "-i", msh, "-o", outputs["psurface"], "-c",
                                      str(nv - target)] + args.psurface_flags.split(), work),
                "cgal": lambda: ([bins["bpm-bench-cgal-decimate"], off, "-o", outputs["cgal"], "--vertices",
                                  str(target)], None),
            }
            # Each tool args.repeats times, the tools taking turns (so that a slow spell of the shared
            # machine hits them alike); the run with the median wall time is reported.
            runs = {tool: [] for tool in args.tools}
            for repeat in range(args.repeats):
                for tool in args.tools:
                    if runs[tool] and runs[tool][-1]["status"] != "ok":
                        continue  # a failure is reported as it is, not repeated
                    log(f"{name} -> {target} vertices: {tool}" + (f" (run {repeat + 1} of {args.repeats})"
                                                                  if args.repeats > 1 else ""))
                    for p in (outputs[tool], stem + "-psurface-graph.vtu" if tool == "psurface" else None):
                        if p and os.path.exists(p):
                            os.remove(p)
                    cmd, cwd = commands[tool]()
                    res = timed(cmd, f"{stem}-{tool}.log", args.timeout, cwd=cwd)
                    res["command"] = " ".join(rel(c) for c in cmd)
                    if res["status"] == "ok" and not os.path.exists(outputs[tool]):
                        res["status"], res["message"] = "failed", "exit 0 but no output file"
                    log(f"  {tool}: {res['status']} {fmt(res['seconds'], '.2f')} s {fmt(res['peak_mb'], '.0f')} MB "
                        f"{res['message']}")
                    runs[tool].append(res)
            for tool in args.tools:
                done = runs[tool]
                if done[-1]["status"] != "ok":
                    row[tool] = done[-1]
                    continue
                by_wall = sorted(done, key=lambda r: r["seconds"])
                res = dict(by_wall[(len(by_wall) - 1) // 2])
                res["wall_runs"] = [r["seconds"] for r in done]
                row[tool] = res
            for tool in args.tools:
                res = row[tool]
                if res["status"] != "ok":
                    continue
                code, data, err = run_json([bins["bpm-bench-metrics"], off, outputs[tool], "--samples", str(args.samples)],
                                           args.timeout)
                res["metrics"] = data
                if data is None:
                    res["metrics_error"] = f"bpm-bench-metrics exit {code}: {err}"
            bpm = row.get("bpm")
            if bpm and bpm["status"] == "ok":
                code, data, err = run_json([bins["bpm-check"], "--json", outputs["bpm"]], args.timeout)
                bpm["check_exit"] = code
                bpm["check"] = data
                if data:
                    bpm["check_failed"] = [c["name"] for c in data.get("checks", []) if not c.get("passed", False)]
                else:
                    bpm["check_failed"] = [f"no report ({err})"]
            rows.append(row)
            write_atomic(json_path, json.dumps({"run": header, "rows": rows}, indent=1) + "\n")
            write_atomic(md_path, simplify_markdown(header, rows))
    write_atomic(json_path, json.dumps({"run": header, "rows": rows}, indent=1) + "\n")
    write_atomic(md_path, simplify_markdown(header, rows))
    log(f"wrote {md_path}")


def ratio(rows, tool, key):
    """Per row: tool's time / bpm's time (None unless both finished); > 1 means bpm is faster."""
    out = []
    for r in rows:
        b, o = r.get("bpm"), r.get(tool)
        if b and o and b["status"] == o["status"] == "ok" and b.get(key) is not None and o.get(key) is not None:
            out.append(o[key] / max(b[key], 0.01))
        else:
            out.append(None)
    return out


def simplify_markdown(header, rows):
    tools = header.get("tools", ["bpm", "psurface"])
    psurface_flags = (f"with flags `{header['psurface_flags']}`" if header['psurface_flags'] else "with default flags")
    bpm_flags = header.get("bpm_flags", "")
    bpm_command = "bpm-simplify IN.off -o OUT.bpm --vertices N" + (f" {bpm_flags}" if bpm_flags else "")
    one_thread = "--threads=1" in bpm_flags.split() or "--threads 1" in bpm_flags
    threads_note = ("here bpm runs on one thread (`--threads 1`), like the other two, so CPU ≈ wall on an idle machine"
                    if one_thread else
                    "psurface and CGAL are single-threaded; bpm runs on 2 threads unless every core is busy (its "
                    "default `--threads 0`), and then takes about 1.9x as much CPU time as wall time (about 1.5x the CPU "
                    "time of one thread): the second thread "
                    "spins between the short planning rounds. `simplify-1thread.md` has bpm with `--threads 1`")
    out = ["# bpm-simplify vs psurface-simplify, with CGAL's edge collapse as a plain-decimation reference", "",
           f"Measured {header['date']}; bpm commit {header['commit']}; {header.get('binary', '')}. "
           "Generated by `bench/run.py simplify`; see bench/README.md for what each column means.", "",
           "Every tool gets the same target vertex count:", "",
           f"- **bpm**: `{bpm_command}` — coarse surface and the bijective map φ, "
           "no self-intersections, topology kept;",
           f"- **psurface**: `psurface-simplify -i IN.msh -o OUT.vtu -c <input vertices - N>` {psurface_flags} — "
           "coarse surface and its parametrization (the original implementation of the method);",
           "- **CGAL (no φ)**: `bpm-bench-cgal-decimate IN.off -o OUT.off --vertices N` — CGAL's "
           "`Surface_mesh_simplification::edge_collapse` on a `Surface_mesh` with the default Lindstrom-Turk cost and "
           "placement. **A plain decimation without a parametrization** (no φ, no intersection test): the reference "
           "for the quality and the speed of a tool that does less than the other two.", "",
           "Memory = peak resident set (MB), times from `/usr/bin/time -f \"%e %M %U %S\"` (the whole process: "
           f"reading, simplifying, writing); timeout {header['timeout_s']} s per run. The machine is shared, so times "
           "carry noise" + (f": each tool ran {header['repeats']} times per row, the tools taking turns, and the "
                            "run with the median wall time is reported (all wall times are in the .json)."
                            if header.get("repeats", 1) > 1 else "."), "",
           "## Time and memory", "",
           "Wall = elapsed seconds; CPU = user + system seconds (less sensitive to other load on the machine; "
           f"{threads_note}). Ratios are the other tool's time over bpm's: > 1 means bpm is faster.", ""]
    head = "| mesh | input V | target V |"
    rule = "|---|---:|---:|"
    for t in tools:
        head += f" {TOOL_LABEL[t]} wall s | {TOOL_LABEL[t]} CPU s | {TOOL_LABEL[t]} MB |"
        rule += "---:|---:|---:|"
    others = [t for t in tools if t != "bpm"] if "bpm" in tools else []
    for t in others:
        head += f" {RATIO_LABEL[t]}/bpm wall | {RATIO_LABEL[t]}/bpm CPU |"
        rule += "---:|---:|"
    out += [head, rule]
    wall_ratios = {t: ratio(rows, t, "seconds") for t in others}
    cpu_ratios = {t: ratio(rows, t, "cpu_seconds") for t in others}
    for i, r in enumerate(rows):
        if not any(t in r for t in tools):
            out.append(f"| {r['mesh']} | {r.get('input_vertices', '—')} | {r.get('target_vertices', '—')} | "
                       f"{r.get('error', 'not run')} |" + " |" * (3 * len(tools) + 2 * len(others) - 1))
            continue
        line = f"| {r['mesh']} | {r['input_vertices']} | {r['target_vertices']} ({r['target_label']}) |"
        for t in tools:
            res = r.get(t)
            if res is None:
                line += " not run | | |"
            elif res["status"] == "ok":
                line += f" {fmt(res['seconds'], '.2f')} | {fmt(res.get('cpu_seconds'), '.2f')} | {fmt(res['peak_mb'], '.0f')} |"
            else:
                line += f" **{res['status']}** | **{res['status']}** | — |"
        for t in others:
            line += f" {fmt(wall_ratios[t][i], '.2f')} | {fmt(cpu_ratios[t][i], '.2f')} |"
        out.append(line)
    out.append("")
    for t in others:
        w = [x for x in wall_ratios[t] if x is not None]
        c = [x for x in cpu_ratios[t] if x is not None]
        what = ("> 1 means bpm is faster" if t == "psurface" else
                "< 1 means the plain decimation is faster, i.e. what φ, the intersection tests and the topology "
                "condition cost")
        out.append(f"Median time ratio {RATIO_LABEL[t]}/bpm over the {len(w)} rows where both finished: "
                   f"**{fmt(statistics.median(w) if w else None, '.2f')}** (wall), "
                   f"**{fmt(statistics.median(c) if c else None, '.2f')}** (CPU); {what}.")
        out.append("")
    failures = [f"- {r['mesh']} → {r['target_vertices']}, {t}: {r[t]['status']} — {r[t]['message']}"
                for r in rows for t in tools if t in r and r[t]["status"] != "ok"]
    if failures:
        out += ["Runs that did not finish:", ""] + failures + [""]

    out += ["## Quality of the coarse surfaces", "",
            "Hausdorff = two-sided sampled Hausdorff distance / bounding-box diagonal of the original; mean = mean of the "
            "two one-sided mean distances / diagonal; R/r = circumradius / inradius (2 = equilateral); "
            "self-int. = self-intersecting triangle pairs (`bpm::check_intersections`); topology = Euler characteristic, "
            "components, boundary loops, Betti numbers, orientability, manifoldness equal to the original's "
            "(`bpm::compare_topology`); bpm-check = format, intersections, topology, bijectivity of the .bpm "
            "(psurface's parametrization is not checked; CGAL makes none).", "",
            "| mesh | target V | tool | V | T | Hausdorff | mean | max R/r | mean R/r | self-int. | topology | bpm-check |",
            "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---|---|"]
    for r in rows:
        for tool in tools:
            res = r.get(tool)
            if res is None:
                continue
            label = TOOL_LABEL[tool]
            if res["status"] != "ok":
                out.append(f"| {r['mesh']} | {r['target_vertices']} | {label} | **{res['status']}**: {res['message']} "
                           "| | | | | | | | |")
                continue
            q = metrics_cell(res.get("metrics"))
            if q is None:
                out.append(f"| {r['mesh']} | {r['target_vertices']} | {label} | metrics failed: "
                           f"{res.get('metrics_error', '')[:120]} | | | | | | | | |")
                continue
            if tool == "bpm":
                failed = res.get("check_failed", [])
                check = "pass" if res.get("check_exit") == 0 else ("**fail**: " + ", ".join(failed) if failed
                                                                   else f"exit {res.get('check_exit')}")
            else:
                check = "n/a" if tool == "psurface" else "n/a (no φ)"
            amax = fmt(q["aspect_max"], ".1f") if q["aspect_max"] is not None else "∞"
            out.append(f"| {r['mesh']} | {r['target_vertices']} | {label} | {q['vertices']} | {q['triangles']} | "
                       f"{q['hausdorff_relative']:.5f} | {q['mean_relative']:.6f} | {amax} | {q['aspect_mean']:.2f} | "
                       f"{q['self_intersecting_pairs']} | {'yes' if q['topology_preserved'] else '**no**'} | {check} |")
    notes = []
    for r in rows:
        for tool in tools:
            res = r.get(tool)
            if not res:
                continue
            m = res.get("metrics")
            if m and m["coarse"]["vertices"] != r["target_vertices"]:
                notes.append(f"- {r['mesh']} → {r['target_vertices']}, {tool}: stopped at {m['coarse']['vertices']} "
                             "vertices, not the target (its time is for less work)")
            if m and not m["topology_preserved"]:
                notes.append(f"- {r['mesh']} → {r['target_vertices']}, {tool}: topology differs: "
                             + "; ".join(m["topology_differences"][:3]))
    if notes:
        out += ["", "Notes:", ""] + notes
    if "psurface" in tools:
        out += ["", "psurface writes Float32 coordinates to its .vtu; its coarse vertices are therefore rounded to "
                    "single precision before they are measured."]
    out.append("")
    return "\n".join(out)


# ---------------------------------------------------------------- scaling suite

def scaling_suite(args, bins, work):
    """Issue 21's scaling table: per subdivision level, bpm-simplify with its default threads (the output the check
    suite reads), bpm-simplify --threads 1 and CGAL's edge collapse (no phi), run in turn `repeats` times (once from
    3.3 M triangles on: a run takes minutes there), medians of CPU seconds, wall seconds and peak memory."""
    rows = []
    json_path = os.path.join(args.results_dir, f"scaling{args.suffix}.json")
    md_path = os.path.join(args.results_dir, f"scaling{args.suffix}.md")
    header = {"date": machine_line(), "commit": git_commit(), "binary": binary_line(bins["bpm-simplify"]),
              "timeout_s": args.scaling_timeout, "repeats": args.scaling_repeats,
              "target_vertices": args.scaling_target}
    for level in args.levels:
        path = subdivided_mesh(level, work)
        nv, nt = read_off_header(path)
        repeats = args.scaling_repeats if nt < 3000000 else 1
        log(f"scaling: armadillo level {level} ({nt} triangles) -> {args.scaling_target} vertices, {repeats} x 3 runs")
        out = scaling_output(work, level, args.scaling_target)
        one = os.path.join(work, f"armadillo-loop{level}-{args.scaling_target}-1thread.bpm")
        cgal_out = os.path.join(work, f"armadillo-loop{level}-{args.scaling_target}-cgal.off")
        target = ["--vertices", str(args.scaling_target)]
        cmds = {"bpm": [bins["bpm-simplify"], path, "-o", out] + target,
                "bpm1": [bins["bpm-simplify"], path, "-o", one, "--threads", "1"] + target,
                "cgal": [bins["bpm-bench-cgal-decimate"], path, "-o", cgal_out] + target}
        runs = {k: [] for k in cmds}
        load_before = load_average()[0]
        for i in range(repeats):
            for k, cmd in cmds.items():
                res = timed(cmd, os.path.join(work, f"scaling-loop{level}-{k}.log"), args.scaling_timeout)
                log(f"  {k}: {res['status']} {fmt(res['seconds'], '.1f')} s wall, {fmt(res['cpu_seconds'], '.1f')} s "
                    f"CPU, {fmt(res['peak_mb'], '.0f')} MB {res['message']}")
                runs[k].append(res)
        row = {"level": level, "input": rel(path) if level == 0 else level_label(level), "vertices": nv,
               "triangles": nt, "repeats": repeats, "load_before": load_before, "load_after": load_average()[0],
               "commands": {k: " ".join(rel(c) for c in cmd) for k, cmd in cmds.items()}}
        for k, rs in runs.items():
            ok = [r for r in rs if r["status"] == "ok"]
            bad = [r for r in rs if r["status"] != "ok"]
            row[k] = {"status": "ok" if not bad else bad[0]["status"], "message": bad[0]["message"] if bad else "",
                      "seconds": median_of(ok, "seconds"), "cpu_seconds": median_of(ok, "cpu_seconds"),
                      "peak_mb": median_of(ok, "peak_mb"),
                      "runs": [{x: r[x] for x in ("status", "seconds", "cpu_seconds", "peak_mb")} for r in rs]}
        rows.append(row)
        write_atomic(json_path, json.dumps({"run": header, "rows": rows}, indent=1) + "\n")
        write_atomic(md_path, scaling_markdown(header, rows))
    log(f"wrote {md_path}")


def times(n):
    return "once" if n == 1 else "twice" if n == 2 else f"{n} times"


def median_of(runs, key):
    values = [r[key] for r in runs if r.get(key) is not None]
    return statistics.median(values) if values else None


def quotient(a, b):
    return a / b if a is not None and b else None


def scaling_markdown(header, rows):
    out = ["# bpm-simplify scaling", "",
           f"Measured {header['date']}; bpm commit {header['commit']}; {header.get('binary', '')}. "
           "Generated by `bench/run.py scaling`.", "",
           f"armadillo.off (52k triangles) and its Loop subdivisions (1, 2 and 3 levels: 208k, 832k, 3.3 M triangles, "
           f"made by `bench/make_subdivided.py`), each simplified to {header['target_vertices']} vertices by "
           f"**bpm** (`bpm-simplify --vertices {header['target_vertices']}`: 2 threads unless every core is busy), "
           f"**bpm, 1 thread** (the same with `--threads 1`) and **CGAL** (`bpm-bench-cgal-decimate --vertices "
           f"{header['target_vertices']}`: CGAL's edge collapse, a plain decimation without φ, single-threaded). The "
           f"three run in turn, {times(header.get('repeats', 1))} per row (once from 3.3 M triangles on); medians of "
           f"wall seconds, CPU seconds (user + system) and peak resident set, all from `/usr/bin/time`; timeout "
           f"{header['timeout_s']} s per run. The load average before and after each row is given: wall times are "
           "only comparable on an idle machine, CPU seconds and ratios are the steadier numbers. The last column is "
           "bpm's one-thread CPU / (n log2 n), normalised to 1 on the first row (≈ 1 on every row means O(n log n)).",
           "",
           "Targets (issue 21): one-thread CPU ≤ 1.5× CGAL's and peak memory ≤ 2.5× CGAL's on every row; 832k "
           "triangles in ≤ 15 s wall on an idle machine; 3.3 M triangles in ≤ 90 s and ≤ 3 GB; with 2 threads wall ≤ "
           "0.6× and CPU ≤ 1.15× the one-thread run.", "",
           "| input | T (n) | load before / after | bpm wall s | bpm CPU s | bpm 1 thread wall s | bpm 1 thread CPU s "
           "| CGAL CPU s | 1 thread ÷ CGAL (CPU) | 2 ÷ 1 thread wall | 2 ÷ 1 thread CPU | bpm 1 thread peak MB "
           "| CGAL peak MB | peak ÷ CGAL | CPU/(n log n), normalised |",
           "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    ref = None
    for r in rows:
        b1 = r.get("bpm1", {})
        if b1.get("status") == "ok" and b1.get("cpu_seconds"):
            ref = b1["cpu_seconds"] / (r["triangles"] * math.log2(r["triangles"]))
            break

    def cell(run, key, spec):
        if run.get("status") != "ok":
            return f"**{run.get('status', '—')}**"
        return fmt(run.get(key), spec)

    for r in rows:
        b, b1, c = r["bpm"], r["bpm1"], r["cgal"]
        okb1 = b1["status"] == "ok"
        norm = (b1["cpu_seconds"] / (r["triangles"] * math.log2(r["triangles"])) / ref) if okb1 and ref else None
        out.append(f"| {r['input']} | {r['triangles']} | {r['load_before']:.1f} / {r['load_after']:.1f} "
                   f"| {cell(b, 'seconds', '.1f')} | {cell(b, 'cpu_seconds', '.1f')} | {cell(b1, 'seconds', '.1f')} "
                   f"| {cell(b1, 'cpu_seconds', '.1f')} | {cell(c, 'cpu_seconds', '.1f')} "
                   f"| {fmt(quotient(b1['cpu_seconds'], c['cpu_seconds']), '.2f')} "
                   f"| {fmt(quotient(b['seconds'], b1['seconds']), '.2f')} "
                   f"| {fmt(quotient(b['cpu_seconds'], b1['cpu_seconds']), '.2f')} "
                   f"| {cell(b1, 'peak_mb', '.0f')} | {cell(c, 'peak_mb', '.0f')} "
                   f"| {fmt(quotient(b1['peak_mb'], c['peak_mb']), '.2f')} | {fmt(norm, '.2f')} |")
    notes = []
    for r in rows:
        b, b1 = r["bpm"], r["bpm1"]
        if 800000 < r["triangles"] < 900000 and b["status"] == "ok":
            notes.append(f"832k triangles: {b['seconds']:.1f} s wall with 2 threads (load {r['load_before']:.1f} "
                         f"before) — ≤ 15 s on an idle machine: {'met' if b['seconds'] <= 15 else '**not met**'}.")
        if r["triangles"] > 3000000:
            if b["status"] == "ok":
                ok = b["seconds"] <= 90 and b["peak_mb"] <= 3072
                notes.append(f"3.3 M triangles: {b['seconds']:.1f} s wall, {b['peak_mb']:.0f} MB with 2 threads; "
                             f"1 thread {fmt(b1.get('seconds'), '.1f')} s, {fmt(b1.get('peak_mb'), '.0f')} MB — ≤ 90 s "
                             f"and ≤ 3 GB: {'met' if ok else '**not met**'}.")
            else:
                notes.append(f"3.3 M triangles: {b['status']} {b['message']} — target **not met**.")
    failed = [f"{r['input']} {k}: {r[k]['status']} {r[k]['message']}" for r in rows for k in ("bpm", "bpm1", "cgal")
              if r[k]["status"] != "ok"]
    out += [""] + [f"- {n}" for n in notes + [f"failed: {f}" for f in failed]]
    out.append("")
    return "\n".join(out)


# ---------------------------------------------------------------- check suite

def check_counts(report):
    """Counts of a bpm-check JSON report: original/coarse triangles, nodes, pieces (from whichever check has them)."""
    counts = {}
    for c in (report or {}).get("checks", []):
        for k in ("original_vertices", "original_triangles", "coarse_vertices", "coarse_triangles", "nodes", "pieces"):
            if k in c.get("counts", {}) and k not in counts:
                counts[k] = c["counts"][k]
    return counts


def timed_check(bins, path, checks, log_stem, args):
    """bpm-check --json [--checks C] PATH, args.check_repeats times; the run with the least CPU time (all checks: the
    least wall time, what the issue's target is about; they run on two threads), with its report.
    Exit 1 (a check failed) still counts as a measurement: the report says what failed."""
    key = "cpu_seconds" if checks else "seconds"
    best = None
    cmd = [bins["bpm-check"], "--json"] + (["--checks", checks] if checks else []) + [path]
    for i in range(args.check_repeats):
        res = timed(cmd, log_stem + ".log", args.check_timeout, stdout_path=log_stem + ".json")
        try:
            with open(log_stem + ".json") as f:
                res["report"] = json.load(f)
        except (OSError, json.JSONDecodeError):
            res["report"] = None
        if res["exit"] in (0, 1) and res["report"] is not None:
            res["status"], res["message"] = "ok", ""
            res["passed"] = bool(res["report"].get("passed"))
            res["failed_checks"] = [c["name"] for c in res["report"].get("checks", []) if not c.get("passed")]
        if best is None or (res["status"] == "ok" and (best["status"] != "ok" or
                                                        (res[key] or 1e30) < (best[key] or 1e30))):
            best = res
        if res["status"] != "ok":
            break
    best["command"] = " ".join(rel(c) for c in cmd)
    return best


def check_suite(args, bins, work):
    rows = []
    json_path = os.path.join(args.results_dir, f"check{args.suffix}.json")
    md_path = os.path.join(args.results_dir, f"check{args.suffix}.md")
    header = {"date": machine_line(), "commit": git_commit(), "binary": binary_line(bins["bpm-check"]),
              "timeout_s": args.check_timeout, "repeats": args.check_repeats, "target_vertices": args.scaling_target}
    simplify_built = os.path.getmtime(bins["bpm-simplify"])
    for level in args.check_levels:
        path = scaling_output(work, level, args.scaling_target)
        row = {"level": level, "input": f"{level_label(level)} → {args.scaling_target} vertices", "file": rel(path)}
        if not os.path.exists(path) or os.path.getmtime(path) < simplify_built:
            source = subdivided_mesh(level, work)
            log(f"check: making {path} (no up-to-date scaling output)")
            made = timed([bins["bpm-simplify"], source, "-o", path, "--vertices", str(args.scaling_target)],
                         os.path.join(work, f"check-make-loop{level}.log"), args.scaling_timeout)
            row["made_here"] = True
            if made["status"] != "ok":
                row["error"] = f"bpm-simplify {made['status']}: {made['message']}"
                rows.append(row)
                write_atomic(md_path, check_markdown(header, rows))
                continue
        row["file_mb"] = os.path.getsize(path) / 1e6
        stem = os.path.join(work, f"check-loop{level}")
        log(f"check: {path} ({row['file_mb']:.0f} MB): all checks")
        row["all"] = timed_check(bins, path, None, stem + "-all", args)
        row["counts"] = check_counts(row["all"].get("report"))
        log(f"  {row['all']['status']} {fmt(row['all']['seconds'], '.2f')} s {fmt(row['all']['peak_mb'], '.0f')} MB")
        for c in CHECKS:
            row[c] = timed_check(bins, path, c, f"{stem}-{c}", args)
            log(f"  {c}: {row[c]['status']} {fmt(row[c]['seconds'], '.2f')} s")
            row[c].pop("report", None)
        row["all"].pop("report", None)
        rows.append(row)
        write_atomic(json_path, json.dumps({"run": header, "rows": rows}, indent=1) + "\n")
        write_atomic(md_path, check_markdown(header, rows))
    write_atomic(json_path, json.dumps({"run": header, "rows": rows}, indent=1) + "\n")
    write_atomic(md_path, check_markdown(header, rows))
    log(f"wrote {md_path}")


def per_second(count, seconds):
    return count / seconds if count is not None and seconds else None


def kilo(v):
    return "—" if v is None else f"{v / 1000.0:,.0f}k"


def check_markdown(header, rows):
    out = ["# bpm-check speed", "",
           f"Measured {header['date']}; bpm commit {header['commit']}; {header.get('binary', '')}. "
           "Generated by `bench/run.py check`.", "",
           f"Inputs: the scaling suite's outputs, armadillo.off and its Loop subdivisions simplified by "
           f"`bpm-simplify --vertices {header['target_vertices']}` (made here when missing or older than bpm-simplify). "
           "Each run is `bpm-check --json FILE` (all four checks: format, intersections, topology, bijectivity) or "
           "`bpm-check --json --checks C FILE` (one check), under `/usr/bin/time`: wall and CPU (user + system) "
           "seconds of the whole process, reading the .bpm included. bpm-check runs the structural checks (format, "
           "intersections, topology) on a second thread next to bijectivity (its default `--threads 0`: up to 2), so "
           "with all checks CPU can exceed wall; one check alone runs on one thread. "
           f"{'Best of ' + str(header['repeats']) + ' runs (all checks: by wall time, the target; one check: by CPU time); ' if header['repeats'] > 1 else ''}"
           f"timeout {header['timeout_s']} s per run. The machine is shared, so wall times carry noise; CPU time is "
           "the steadier number.", "",
           "## All four checks", "",
           "| input | original T | coarse T | pieces | nodes | file MB | wall s | CPU s | peak MB "
           "| original T / s (CPU) | pieces / s (CPU) | result |",
           "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    for r in rows:
        if "error" in r:
            out.append(f"| {r['input']} | | | | | | **{r['error']}** | | | | | |")
            continue
        a, n = r["all"], r.get("counts", {})
        if a["status"] != "ok":
            out.append(f"| {r['input']} | | | | | {r['file_mb']:.0f} | **{a['status']}** {a['message']} | | | | | |")
            continue
        result = "pass" if a.get("passed") else "**fail**: " + ", ".join(a.get("failed_checks", []))
        out.append(f"| {r['input']} | {n.get('original_triangles', '—')} | {n.get('coarse_triangles', '—')} | "
                   f"{n.get('pieces', '—')} | {n.get('nodes', '—')} | {r['file_mb']:.0f} | {fmt(a['seconds'], '.2f')} | "
                   f"{fmt(a['cpu_seconds'], '.2f')} | {fmt(a['peak_mb'], '.0f')} | "
                   f"{kilo(per_second(n.get('original_triangles'), a['cpu_seconds']))} | "
                   f"{kilo(per_second(n.get('pieces'), a['cpu_seconds']))} | {result} |")
    # The issue's target, on the largest input that was checked.
    done = [r for r in rows if "error" not in r and r["all"]["status"] == "ok" and r["all"].get("seconds")
            and r.get("counts", {}).get("original_triangles")]
    if done:
        big = max(done, key=lambda r: r["counts"]["original_triangles"])
        t, wall = big["counts"]["original_triangles"], big["all"]["seconds"]
        per_million = wall * 1e6 / t
        out += ["", f"Target (issue 4): a file whose original has ~1 M triangles fully checked in ≤ 10 s on the 2-core "
                    f"machine. Largest input here: {t / 1e3:,.0f}k original triangles in {wall:.2f} s wall, i.e. "
                    f"{per_million:.1f} s per million original triangles (time is linear in the size: see the "
                    f"throughput column) — target **{'met' if per_million <= 10 else 'not met'}**."]
    out += ["", "## Each check alone", "",
            "CPU seconds of `bpm-check --checks C` (one process per check, each reading the file). The `format` run "
            "is reading + the format check, the cheapest run possible, so for the other checks the check's own time "
            "is estimated as its run minus the `format` run (≥ 0; noise can hide a check faster than the noise). "
            "Throughput is per check's own time, over what the check walks: intersections — coarse triangles; "
            "topology — original + coarse triangles; bijectivity — pieces (they tile both surfaces).", "",
            "| input | format (read + check) s | intersections s | topology s | bijectivity s "
            "| intersections own s | topology own s | bijectivity own s "
            "| intersections coarse T / s | topology T / s | bijectivity pieces / s |",
            "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        if "error" in r or r["all"]["status"] != "ok":
            continue
        n = r.get("counts", {})

        def cpu(c):
            res = r.get(c)
            if not res:
                return None
            return res["cpu_seconds"] if res["status"] == "ok" else None

        def cell(c):
            res = r.get(c)
            if res is None:
                return "—"
            if res["status"] != "ok":
                return f"**{res['status']}**"
            return fmt(res["cpu_seconds"], ".2f") + ("" if res.get("passed") else " (**fail**)")
        base = cpu("format")
        own = {c: (max(cpu(c) - base, 0.0) if cpu(c) is not None and base is not None else None)
               for c in ("intersections", "topology", "bijectivity")}
        units = {"intersections": n.get("coarse_triangles"),
                 "topology": (n.get("original_triangles") or 0) + (n.get("coarse_triangles") or 0) or None,
                 "bijectivity": n.get("pieces")}
        out.append(f"| {r['input']} | {cell('format')} | {cell('intersections')} | {cell('topology')} | "
                   f"{cell('bijectivity')} | " + " | ".join(fmt(own[c], ".2f") for c in own) + " | "
                   + " | ".join(kilo(per_second(units[c], own[c])) if own[c] and own[c] > 0.005 else "—" for c in own)
                   + " |")
    out.append("")
    return "\n".join(out)


# ---------------------------------------------------------------- all: the one command

def run_streamed(cmd, log_path, timeout, env=None, capture=None):
    """Runs cmd from the repository root in its own process group, its standard error (and standard output unless
    `capture` names a file for it) copied to log_path and to our standard error. On timeout the whole group is
    ended (SIGTERM, then SIGKILL). Returns (status, exit code, seconds)."""
    start = time.monotonic()
    with open(log_path, "w") as lf:
        lf.write("$ " + shlex.join(cmd) + "\n")
        lf.flush()
        out_file = open(capture, "w") if capture else None
        proc = subprocess.Popen(cmd, cwd=ROOT, env=env, start_new_session=True, text=True, errors="replace",
                                stdout=out_file if capture else subprocess.PIPE,
                                stderr=subprocess.PIPE if capture else subprocess.STDOUT)
        stream = proc.stderr if capture else proc.stdout

        def pump():
            for line in stream:
                lf.write(line)
                lf.flush()
                sys.stderr.write(line)
                sys.stderr.flush()
        reader = threading.Thread(target=pump, daemon=True)
        reader.start()
        status = "ok"
        try:
            proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            status = "timeout"
            for sig, grace in ((signal.SIGTERM, 20), (signal.SIGKILL, 10)):
                try:
                    os.killpg(proc.pid, sig)
                except ProcessLookupError:
                    break
                try:
                    proc.wait(timeout=grace)
                    break
                except subprocess.TimeoutExpired:
                    continue
        reader.join(timeout=10)
        if out_file:
            out_file.close()
    seconds = time.monotonic() - start
    if status == "ok" and proc.returncode != 0:
        status = "failed"
    return status, proc.returncode, seconds


def package_versions(names):
    out = {}
    for n in names:
        p = subprocess.run(["dpkg-query", "-W", "-f", "${Version}", n], capture_output=True, text=True)
        out[n] = p.stdout.strip() if p.returncode == 0 and p.stdout.strip() else "not installed"
    return out


def compiler_line(build_dir):
    try:
        with open(os.path.join(build_dir, "CMakeCache.txt")) as f:
            for line in f:
                if line.startswith("CMAKE_CXX_COMPILER:"):
                    cxx = line.split("=", 1)[1].strip()
                    v = subprocess.run([cxx, "--version"], capture_output=True, text=True).stdout.splitlines()
                    return v[0] if v else cxx
    except OSError:
        pass
    return "unknown"


def os_name():
    try:
        with open("/etc/os-release") as f:
            for line in f:
                if line.startswith("PRETTY_NAME="):
                    return line.split("=", 1)[1].strip().strip('"')
    except OSError:
        pass
    return platform.system()


def machine_info():
    """The machine as RESULTS.md describes it, captured when a run starts."""
    mem = memory_gib()
    return {"cpu": cpu_model(), "cores": os.cpu_count(), "memory_gib": mem,
            "system": f"{os_name()}, Linux {platform.release()}"}


def manual_sections():
    """Paths of the hand-written sections in MANUAL_SECTIONS order; exits if the folder and the list disagree."""
    present = sorted(os.path.basename(p) for p in glob.glob(os.path.join(MANUAL, "*.md")))
    missing = [n for n in MANUAL_SECTIONS if n not in present]
    unlisted = [n for n in present if n not in MANUAL_SECTIONS and not n.startswith("after-")]
    if missing or unlisted:
        sys.exit("run.py: error: bench/results/manual/ and MANUAL_SECTIONS in bench/run.py disagree: "
                 + "; ".join(([f"missing {', '.join(missing)}"] if missing else [])
                             + ([f"not listed {', '.join(unlisted)}"] if unlisted else [])))
    return [os.path.join(MANUAL, n) for n in MANUAL_SECTIONS]


def manual_remarks(step_name):
    """The text of manual/after-STEP.md for a step, or None."""
    try:
        with open(os.path.join(MANUAL, f"after-{step_name}.md")) as f:
            return f.read().strip()
    except FileNotFoundError:
        return None


def save_run(run, path):
    """The run record as JSON: times as ISO strings, paths relative to the repository root."""
    def encode(v):
        if isinstance(v, datetime.datetime):
            return v.isoformat()
        if isinstance(v, dict):
            return {k: (rel(x) if k in ("path", "log", "capture") and isinstance(x, str) and os.path.isabs(x)
                        else [[rel(a) if os.path.isabs(a) else a for a in c] for c in x] if k == "commands"
                        else encode(x)) for k, x in v.items()}
        if isinstance(v, (list, tuple)):
            return [encode(x) for x in v]
        return v
    write_atomic(path, json.dumps(encode(run), indent=1, ensure_ascii=False) + "\n")


def load_run(path):
    """save_run's record back: times as datetimes, paths absolute."""
    try:
        with open(path) as f:
            run = json.load(f)
    except OSError as e:
        sys.exit(f"run.py: error: {rel(path)}: {e.strerror}: --assemble needs the record of a run of `all`")
    for key in ("started", "finished"):
        if run.get(key):
            run[key] = datetime.datetime.fromisoformat(run[key])
    for step in run.get("steps", []):
        for key in ("log", "capture"):
            if step.get(key) and not os.path.isabs(step[key]):
                step[key] = os.path.join(ROOT, step[key])
        for f in step.get("files", []):
            if not os.path.isabs(f["path"]):
                f["path"] = os.path.join(ROOT, f["path"])
    return run


def assemble(args):
    """--assemble: RESULTS.md from the recorded run, its results files and the hand-written sections."""
    run = load_run(os.path.join(args.results_dir, RUN_RECORD))
    out_dir = os.path.dirname(args.results_file)
    write_atomic(args.results_file, results_markdown(args, run, lambda path: os.path.relpath(path, out_dir)))
    log(f"wrote {args.results_file}")


def demote(md):
    """A results file's markdown with every heading one level lower, to sit inside RESULTS.md."""
    lines, fence = [], False
    for line in md.splitlines():
        if line.startswith("```"):
            fence = not fence
        if not fence and line.startswith("#"):
            line = "##" + line
        lines.append(line)
    return "\n".join(lines).strip() + "\n"


def suite_args(args, suite):
    """The explicit options forwarded to `run.py SUITE`, so the recorded command says everything that matters."""
    common = ["--no-build", "--build-dir", rel(args.build_dir), "--results-dir", rel(args.results_dir)]
    if suite == "simplify":
        return common + ["--meshes", ",".join(args.meshes), "--tools", ",".join(args.tools),
                         "--timeout", str(args.timeout), "--samples", str(args.samples),
                         "--repeats", str(args.repeats)] + (
            [f"--psurface-flags={args.psurface_flags}"] if args.psurface_flags else []) + (
            [f"--bpm-flags={args.bpm_flags}"] if args.bpm_flags else [])
    if suite == "scaling":
        return common + ["--levels", ",".join(map(str, args.levels)), "--scaling-target", str(args.scaling_target),
                         "--scaling-timeout", str(args.scaling_timeout), "--scaling-repeats", str(args.scaling_repeats)]
    return common + ["--check-levels", ",".join(map(str, args.check_levels)),
                     "--scaling-target", str(args.scaling_target), "--scaling-timeout", str(args.scaling_timeout),
                     "--check-timeout", str(args.check_timeout), "--check-repeats", str(args.check_repeats)]


def all_suites(args, invocation):
    results_md = args.results_file
    out_dir = os.path.dirname(results_md)
    os.makedirs(out_dir, exist_ok=True)
    logs = os.path.join(args.build_dir, "bench-work", "logs")
    os.makedirs(logs, exist_ok=True)
    started = utcnow()
    load_start = load_average()
    run = {"started": started, "load_start": load_start, "commit": git_commit(), "invocation": invocation,
           "machine": machine_info(), "logs": rel(logs), "steps": [], "build": None}
    if not args.quick:
        manual_sections()  # fail now rather than after the run

    def link(path):
        return os.path.relpath(path, out_dir)

    def write():
        save_run(run, os.path.join(args.results_dir, RUN_RECORD))
        write_atomic(results_md, results_markdown(args, run, link))

    def step(name, title, cmd, timeout, result_globs=(), env=None, capture=None, note=None, display_env=""):
        log(f"== {title}: {shlex.join(cmd)}")
        t0 = time.time()
        status, code, seconds = run_streamed(cmd, os.path.join(logs, f"{name}.log"), timeout, env=env, capture=capture)
        log(f"== {title}: {status} (exit {code}, {seconds:.0f} s)")
        files = []
        for pattern in result_globs:
            for p in sorted(glob.glob(pattern)):
                if p.endswith(".md"):
                    files.append({"path": p, "fresh": os.path.getmtime(p) >= t0 - 1})
        run["steps"].append({"name": name, "title": title, "command": display_env + shlex.join(cmd),
                             "status": status, "exit": code, "seconds": seconds, "timeout": timeout,
                             "files": files, "capture": capture, "note": note,
                             "log": os.path.join(logs, f"{name}.log")})
        write()

    write()
    if not args.no_build:
        t0 = time.monotonic()
        try:
            commands = build(args.build_dir, args.jobs)
            run["build"] = {"status": "ok", "commands": commands, "seconds": time.monotonic() - t0}
        except subprocess.CalledProcessError as e:
            run["build"] = {"status": f"failed (exit {e.returncode})", "commands": [e.cmd],
                            "seconds": time.monotonic() - t0}
            write()
            sys.exit(f"run.py: error: the build failed: {shlex.join(e.cmd)}")
    else:
        run["build"] = {"status": "skipped (--no-build)", "commands": [], "seconds": 0.0}
    run["versions"] = {"compiler": compiler_line(args.build_dir), "bpm-simplify binary": binary_line(
        os.path.join(args.build_dir, "bin", "bpm-simplify")),
        **package_versions(["libcgal-dev", "libhdf5-dev", "psurface", "tetgen"])}
    write()

    py = [PYTHON, rel(os.path.join(BENCH, "run.py"))]
    suite_timeout = args.external_timeout
    step("simplify", "simplify: bpm vs psurface vs CGAL", py + ["simplify"] + suite_args(args, "simplify"), suite_timeout,
         [os.path.join(args.results_dir, "simplify.md")])
    def without_cgal():
        variant = [a for a in suite_args(args, "simplify")]
        variant[variant.index("--tools") + 1] = ",".join(t for t in args.tools if t != "cgal")
        return variant
    if not args.quick and "psurface" in args.tools and not args.psurface_flags:
        step("simplify-psurface-s", "simplify, psurface forbidding self-intersections (-s)",
             py + ["simplify"] + without_cgal() + ["--psurface-flags=-s", "--suffix=-psurface-s"], suite_timeout,
             [os.path.join(args.results_dir, "simplify-psurface-s.md")])
    if not args.quick and "psurface" in args.tools and not args.bpm_flags:
        # CGAL stays in: issue 21's target is bpm's one-thread CPU time against CGAL's.
        step("simplify-1thread", "simplify, bpm on one thread (--threads 1)",
             py + ["simplify"] + suite_args(args, "simplify") + ["--bpm-flags=--threads=1", "--suffix=-1thread"],
             suite_timeout,
             [os.path.join(args.results_dir, "simplify-1thread.md")])
    step("scaling", "scaling", py + ["scaling"] + suite_args(args, "scaling"), suite_timeout, [os.path.join(args.results_dir, "scaling.md")])
    step("check", "check speed", py + ["check"] + suite_args(args, "check"), suite_timeout, [os.path.join(args.results_dir, "check.md")])

    # The external scripts: options are passed only when the script's text mentions them. Their results go to
    # args.results_dir when they take --results-dir; a quick run skips a script that cannot be redirected, so that
    # a trial never overwrites bench/results (corpus.sh excepted: its run is the whole corpus in both modes).
    def external(name, title, script, cmd, quick_options, globs_name, env=None, display_env=""):
        text = open(script).read()
        if not all(o in text for o in ("--no-build", "--build-dir")):
            return False
        cmd = cmd + ["--no-build", "--build-dir", rel(args.build_dir)]
        results_dir = RESULTS
        if "--results-dir" in text:
            cmd += ["--results-dir", rel(args.results_dir)]
            results_dir = args.results_dir
        elif args.quick:
            run["steps"].append({"name": name, "title": title, "command": None, "status": "skipped", "files": [],
                                 "note": f"{rel(script)} takes no --results-dir, so --quick skips it rather than let "
                                         f"it overwrite bench/results; the full run includes it."})
            write()
            return True
        if args.quick:
            quick_work = os.path.join(os.path.dirname(args.results_file), f"{name}-work")  # apart from full runs
            cmd += [x for option, value in quick_options + [("--work-dir", rel(quick_work))] if option in text
                    for x in (option, value)]
        step(name, title, cmd, args.external_timeout, [os.path.join(results_dir, globs_name)], env=env,
             display_env=display_env)
        return True

    refine = os.path.join(BENCH, "refine.py")
    refine_title = "refinement convergence, shape, φ throughput"
    if not os.path.exists(refine):
        run["steps"].append({"name": "refine", "title": refine_title, "command": None, "status": "absent", "files": [],
                             "note": "bench/refine.py does not exist in this tree, so the refinement tables "
                                     "(convergence, shape, φ evaluation throughput) were not measured."})
        write()
    elif not external("refine", refine_title, refine, [PYTHON, rel(refine)],
                      [("--meshes", QUICK_REFINE_MESHES)], "refine*.md"):
        run["steps"].append({"name": "refine", "title": refine_title, "command": None, "status": "not run",
                             "files": [], "note": "bench/refine.py does not take `--no-build --build-dir` yet."})
        write()

    adaptive = os.path.join(BENCH, "adaptive.py")
    if os.path.exists(adaptive):
        # --quick: femur only, T = 0.003 and 0.001.
        external("adaptive", "adaptive refinement: error bound and triangle count (issue 19)", adaptive,
                 [PYTHON, rel(adaptive)], [("--meshes", QUICK_REFINE_MESHES), ("--tolerances", "0.003,0.001")],
                 "adaptive.md")

    refined_check = os.path.join(BENCH, "refined_check.py")
    if os.path.exists(refined_check):
        # --quick: femur only, K = 1, no multi-material fixtures.
        external("refined-check", "refined .bpm files through bpm-check (issue 19)", refined_check,
                 [PYTHON, rel(refined_check)],
                 [("--meshes", QUICK_REFINE_MESHES), ("--levels", "1"), ("--fixtures", "")], "refined-check.md")

    tetmesh = os.path.join(BENCH, "tetmesh.sh")
    env = dict(os.environ)
    display_env = ""
    if args.quick:
        env["BPM_BENCH_MAX_TETS"] = QUICK_MAX_TETS
        display_env = f"BPM_BENCH_MAX_TETS={QUICK_MAX_TETS} "
    if not external("tetmesh", "tet meshes", tetmesh, [rel(tetmesh)],
                    [("--meshes", QUICK_TETMESH_MESHES), ("--max-tets", QUICK_MAX_TETS)], "tetmesh*.md",
                    env=env, display_env=display_env):
        capture = os.path.join(args.build_dir, "bench-work", "tetmesh-stdout.txt")
        work = os.path.join(args.build_dir, "bench-work", "tetmesh")
        step("tetmesh", "tet meshes", [rel(tetmesh), rel(os.path.join(args.build_dir, "bin")), rel(work)],
             args.external_timeout, env=env, capture=capture, display_env=display_env,
             note="bench/tetmesh.sh does not accept `--no-build --build-dir` yet and writes no results file; it was "
                  "run with its positional interface (TOOL_DIR WORK_DIR) on the binaries built above, and its "
                  "standard output is copied below.")

    repair = os.path.join(BENCH, "repair.sh")
    if os.path.exists(repair):
        # --quick: 2 flat levels (131k tetrahedra on femur) instead of 3 (1 M).
        external("repair", "repair after a solver refines", repair, [rel(repair)], [("--levels", "2")], "repair*.md")
    # The deal.II experiment (paper §3): builds its own deal.II program in BUILD_DIR-dealii, notes a skip when
    # deal.II is not installed.
    dealii = os.path.join(BENCH, "dealii_torsion.py")
    if os.path.exists(dealii):
        external("dealii", "Solvers: deal.II torsion", dealii, [PYTHON, rel(dealii)], [("--levels", "2")],
                 "dealii-torsion.md")

    step("corpus", "the whole libcgal-demo corpus", [rel(os.path.join(BENCH, "corpus.sh")), rel(args.build_dir)],
         args.external_timeout, [os.path.join(RESULTS, "corpus.md")])

    run["finished"] = utcnow()
    run["load_end"] = load_average()
    write()
    log(f"wrote {results_md}")
    failed = [s["name"] for s in run["steps"] if s["status"] in ("failed", "timeout")]
    if failed:
        log(f"steps that did not finish cleanly: {', '.join(failed)}")
        sys.exit(1)


def results_markdown(args, run, link):
    machine = run["machine"]
    mem = machine["memory_gib"]
    ls, le = run["load_start"], run.get("load_end")
    out = ["# bpm benchmark results", "",
           "<!-- Written by bench/all.sh (bench/run.py): edit the hand-written sections in "
           "bench/results/manual/, not here. -->", ""]
    if args.quick:
        out += ["> **Quick mode** (`--quick`): fewer meshes, fewer subdivision levels, fewer samples, shorter "
                "timeouts. For trying the command out, not for quoting. The full run is `bench/all.sh`.", ""]
    finished = run.get("finished")
    out += [f"Generated by `{run['invocation']}`, started {run['started']:%Y-%m-%d %H:%M} UTC"
            + (f", finished {finished:%H:%M} UTC ({(finished - run['started']).total_seconds() / 60:.0f} min)."
               if finished else " — **still running or interrupted**: the sections below are what has finished."),
            "", "## Machine and software", "",
            "| | |", "|---|---|",
            f"| CPU | {machine['cpu']}, {machine['cores']} cores |",
            f"| memory | {'unknown' if mem is None else f'{mem:.1f} GiB'} |",
            f"| load average at start (1 / 5 / 15 min) | {ls[0]:.2f} / {ls[1]:.2f} / {ls[2]:.2f} |"]
    if le:
        out.append(f"| load average at the end | {le[0]:.2f} / {le[1]:.2f} / {le[2]:.2f} |")
    out += [f"| system | {machine['system']} |",
            f"| bpm commit | {run['commit']} |"]
    for k, v in run.get("versions", {}).items():
        out.append(f"| {k} | {v} |")
    out += ["", "The suites run one after the other, each tool single-threaded except bpm-simplify (2 threads when a "
                "core is free, its default; the simplify-1thread suite runs it on one), bpm-check (structural "
                "checks on a second thread) and the φ throughput rows with 2 threads. On a shared or loaded machine the "
                "wall times carry noise; the tables also give CPU seconds, the steadier number.", "",
            "## Commands", "",
            "Run from the repository root, in this order; logs in "
            f"`{run['logs']}/`.", ""]
    b = run.get("build")
    n = 0
    if b and not b["commands"]:
        out += [f"Build: {b['status']}: the binaries already in `{rel(os.path.join(args.build_dir, 'bin'))}` "
                "were used.", ""]
    elif b:
        for c in b["commands"]:
            n += 1
            out.append(f"{n}. `{shlex.join(rel(x) if os.path.isabs(x) else x for x in c)}`")
        out.append(f"   — build: {b['status']}, {b['seconds']:.0f} s")
    for s in run["steps"]:
        n += 1
        if s.get("command"):
            out.append(f"{n}. `{s['command']}`")
            out.append(f"   — {s['title']}: **{s['status']}** (exit {s['exit']}, {s['seconds']:.0f} s, "
                       f"timeout {s['timeout']} s)")
        else:
            out.append(f"{n}. {s['title']}: **{s['status']}** — {s['note']}")
    out.append("")

    for s in run["steps"]:
        out += [f"## {s['title'][0].upper() + s['title'][1:]}", ""]
        if s.get("command"):
            out.append(f"`{s['command']}` — **{s['status']}** (exit {s['exit']}, {s['seconds']:.0f} s).")
            out.append("")
        if s.get("note"):
            out += [s["note"], ""]
        if s.get("status") in ("failed", "timeout") and s.get("log"):
            try:
                with open(s["log"], errors="replace") as f:
                    tail = [l.rstrip() for l in f.read().splitlines()[1:] if l.strip()][-15:]
            except OSError:
                tail = []
            out += [f"Last lines of its output ({rel(s['log'])}):", "", "```"] + (tail or ["(none)"]) + ["```", ""]
        if s.get("capture"):
            try:
                with open(s["capture"]) as f:
                    text = f.read().strip()
            except OSError:
                text = ""
            out += ["```", text or "(no output)", "```", ""]
        for f in s.get("files", []):
            if not f["fresh"]:
                out += [f"[{os.path.basename(f['path'])}]({link(f['path'])}) was **not rewritten by this run** "
                        "(left from an earlier one); not copied here.", ""]
                continue
            out += [f"From [{os.path.basename(f['path'])}]({link(f['path'])}):", ""]
            with open(f["path"]) as fh:
                out.append(demote(fh.read()))
        if not s.get("files") and not s.get("capture") and s.get("command"):
            out += ["No results file was written.", ""]
        remarks = None if args.quick else manual_remarks(s["name"])
        if remarks:
            out += [f"<!-- {rel(os.path.join(MANUAL, 'after-' + s['name'] + '.md'))}: written by hand -->", "",
                    remarks, ""]
    if not args.quick:
        for path in manual_sections():
            with open(path) as fh:
                out += [f"<!-- {rel(path)}: written by hand, appended by bench/all.sh -->", "",
                        fh.read().strip(), ""]
    return "\n".join(out)


# ---------------------------------------------------------------- main

def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("suite", nargs="?", default="all", choices=["simplify", "scaling", "check", "all"])
    ap.add_argument("--quick", action="store_true",
                    help="fewer meshes and levels, fewer samples, shorter timeouts; results to BUILD_DIR/bench-quick")
    ap.add_argument("--build-dir", default=os.path.join(ROOT, "build-bench"))
    ap.add_argument("--no-build", action="store_true", help="use the binaries already in BUILD_DIR/bin")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--results-dir", help="where results/*.md go (default bench/results; with --quick "
                                          "BUILD_DIR/bench-quick/results)")
    ap.add_argument("--meshes", help=f"comma-separated names in .data/meshes (default {PROFILES['meshes'][0]}; "
                                     f"--quick: {PROFILES['meshes'][1]})")
    ap.add_argument("--tools", default=",".join(TOOLS), help="simplify suite: which of bpm,psurface,cgal to run")
    ap.add_argument("--timeout", type=int, help="seconds per tool run in the simplify suite (900; --quick 300)")
    ap.add_argument("--samples", type=int, help="bpm-bench-metrics --samples (500000; --quick 100000)")
    ap.add_argument("--psurface-flags", default="", help="extra psurface-simplify flags, e.g. '-s'")
    ap.add_argument("--bpm-flags", default="", help="extra bpm-simplify flags, e.g. '--threads=1'")
    ap.add_argument("--repeats", type=int, help="simplify suite: runs per tool and row, the median wall time is "
                    "reported (3; --quick 1)")
    ap.add_argument("--suffix", default="", help="results go to results/simplify<SUFFIX>.md etc. (e.g. '-psurface-s')")
    ap.add_argument("--levels", help="Loop subdivision levels for the scaling suite (0,1,2,3; --quick 0,1)")
    ap.add_argument("--scaling-repeats", type=int, help="scaling suite: runs of each tool per row below 3 M triangles, "
                    "medians reported (3; --quick 1)")
    ap.add_argument("--scaling-target", type=int, default=10000)
    ap.add_argument("--scaling-timeout", type=int, help="seconds per scaling run (900; --quick 300)")
    ap.add_argument("--check-levels", help="check suite: which scaling outputs to check (0,1,2; --quick 0,1)")
    ap.add_argument("--check-timeout", type=int, help="seconds per bpm-check run (900; --quick 300)")
    ap.add_argument("--check-repeats", type=int, help="check suite: runs per measurement, the best is kept (3; --quick 1)")
    ap.add_argument("--assemble", action="store_true",
                    help="all: only rewrite RESULTS.md from results/all.json, results/*.md and results/manual/*.md "
                         "(no build, no runs)")
    ap.add_argument("--external-timeout", type=int,
                    help="all: seconds per suite and per external script (7200; --quick 1800)")
    args = ap.parse_args()
    argv = sys.argv[1:]
    if os.environ.pop("BPM_BENCH_VIA_ALL_SH", None) and argv[:1] == ["all"]:
        invocation = shlex.join(["bench/all.sh"] + argv[1:])
    else:
        invocation = shlex.join([PYTHON, "bench/run.py"] + argv)
    for key, (full, quick) in PROFILES.items():
        if getattr(args, key) is None:
            setattr(args, key, quick if args.quick else full)
    args.meshes = [m for m in args.meshes.split(",") if m]
    args.levels = [int(l) for l in str(args.levels).split(",") if l]
    args.check_levels = [int(l) for l in str(args.check_levels).split(",") if l]
    args.tools = [t for t in args.tools.split(",") if t]
    bad = [t for t in args.tools if t not in TOOLS]
    if bad:
        ap.error(f"--tools: unknown {', '.join(bad)} (choose from {', '.join(TOOLS)})")
    args.build_dir = os.path.abspath(args.build_dir)
    quick_dir = os.path.join(args.build_dir, "bench-quick")
    if args.results_dir is None:
        args.results_dir = os.path.join(quick_dir, "results") if args.quick else RESULTS
    args.results_dir = os.path.abspath(args.results_dir)
    args.results_file = os.path.join(quick_dir if args.quick else BENCH, "RESULTS.md")
    if args.assemble:
        if args.suite != "all":
            ap.error("--assemble works with `all` only")
        assemble(args)
        return
    work = os.path.join(args.build_dir, "bench-work")
    os.makedirs(work, exist_ok=True)
    os.makedirs(args.results_dir, exist_ok=True)

    if args.suite == "all":
        all_suites(args, invocation)
        return

    targets = list(SUITE_TARGETS[args.suite])
    if args.suite == "simplify" and "cgal" not in args.tools:
        targets.remove("bpm-bench-cgal-decimate")
    if not args.no_build:
        build(args.build_dir, args.jobs, targets)
    bins = {t: os.path.join(args.build_dir, "bin", t) for t in targets}
    for t, p in bins.items():
        if not os.access(p, os.X_OK):
            sys.exit(f"run.py: error: {p} missing (build first)")
    if args.suite == "simplify" and "psurface" in args.tools and not shutil.which("psurface-simplify"):
        log("warning: psurface-simplify not found; its rows will say 'failed'")
    {"simplify": simplify_suite, "scaling": scaling_suite, "check": check_suite}[args.suite](args, bins, work)


if __name__ == "__main__":
    main()
