#!/usr/bin/python3
"""bpm benchmark driver (bench/README.md).

    /usr/bin/python3 bench/run.py [simplify | scaling | all] [options]

simplify  bpm-simplify vs psurface-simplify on real meshes at 10 % of the input vertices
          and at 1000 vertices: wall time, peak memory, bpm-bench-metrics on both outputs,
          bpm-check on bpm's output -> bench/results/simplify.{md,json}
scaling   bpm-simplify to 10,000 vertices on armadillo after 0, 1, 2 Loop subdivisions
          (52k / 208k / 832k triangles) -> bench/results/scaling.{md,json}

Builds bpm-simplify, bpm-check and bpm-bench-metrics in Release first (--no-build skips
that). Everything generated besides the results (converted meshes, subdivided meshes,
.bpm/.vtu outputs, logs) goes to BUILD_DIR/bench-work, never into the source tree.
Results are rewritten after every run, so an interrupted run leaves what it measured.
"""
import argparse
import datetime
import json
import math
import os
import platform
import shutil
import statistics
import subprocess
import sys
import time

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)
MESHES = os.path.join(ROOT, ".data", "meshes")
RESULTS = os.path.join(BENCH, "results")
PYTHON = "/usr/bin/python3"
DEFAULT_MESHES = ["femur", "fandisk", "elephant", "armadillo", "mech-holes-shark"]


def log(msg):
    sys.stderr.write(f"[{datetime.datetime.utcnow():%H:%M:%S}] {msg}\n")
    sys.stderr.flush()


# ---------------------------------------------------------------- helpers

def build(build_dir, jobs):
    log(f"building in {build_dir} (Release)")
    subprocess.run(["cmake", "-S", ROOT, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release", "-DBPM_BUILD_TESTS=OFF"],
                   check=True, stdout=subprocess.DEVNULL)
    subprocess.run(["cmake", "--build", build_dir, f"-j{jobs}", "--target",
                    "bpm-simplify", "bpm-check", "bpm-bench-metrics"], check=True, stdout=subprocess.DEVNULL)


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


def timed(cmd, log_path, timeout, cwd=None):
    """Runs cmd under `timeout` and /usr/bin/time; returns dict(status, seconds (wall), cpu_seconds (user + system),
    peak_mb (maximum resident set size), exit, message)."""
    time_file = log_path + ".time"
    if os.path.exists(time_file):
        os.remove(time_file)
    full = ["/usr/bin/time", "-f", "%e %M %U %S", "-o", time_file, "timeout", "--kill-after=10", str(timeout)] + cmd
    with open(log_path, "w") as lf:
        lf.write("$ " + " ".join(cmd) + "\n")
        lf.flush()
        start = time.monotonic()
        proc = subprocess.run(full, stdout=lf, stderr=subprocess.STDOUT, cwd=cwd)
        wall = time.monotonic() - start
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


def machine_line():
    try:
        load = os.getloadavg()[0]
    except OSError:
        load = float("nan")
    cpu = platform.processor() or platform.machine()
    return (f"{datetime.datetime.utcnow():%Y-%m-%d %H:%M} UTC, {os.cpu_count()} cores ({cpu}), "
            f"load average at start {load:.1f}")


def binary_line(path):
    """'bpm-simplify 0.1.0 (bpm format 1.0), built 2026-11-22 04:13 UTC' for the results header."""
    try:
        version = subprocess.run([path, "--version"], capture_output=True, text=True).stdout.strip()
        built = datetime.datetime.utcfromtimestamp(os.path.getmtime(path))
        return f"{version}, built {built:%Y-%m-%d %H:%M} UTC"
    except OSError:
        return "unknown"


def git_commit():
    try:
        c = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True).stdout.strip()
        return c + (" (with uncommitted changes)" if dirty else "")
    except OSError:
        return "unknown"


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
    json_path = os.path.join(RESULTS, f"simplify{args.suffix}.json")
    md_path = os.path.join(RESULTS, f"simplify{args.suffix}.md")
    header = {"date": machine_line(), "commit": git_commit(), "binary": binary_line(bins["bpm-simplify"]),
              "timeout_s": args.timeout,
              "metrics_samples": args.samples, "psurface_flags": args.psurface_flags}
    for name in args.meshes:
        off = os.path.join(MESHES, name + ".off")
        if not os.path.exists(off):
            rows.append({"mesh": name, "error": f"{off} not found (run scripts/setup.sh)"})
            continue
        nv, nt = read_off_header(off)
        msh = os.path.join(work, name + ".msh")
        off_to_msh22(off, msh)
        for label, target in (("10%", max(4, round(0.1 * nv))), ("1000", 1000)):
            row = {"mesh": name, "input_vertices": nv, "input_triangles": nt, "target_label": label,
                   "target_vertices": target}
            stem = os.path.join(work, f"{name}-{target}{args.suffix}")
            if target >= nv:
                row["error"] = f"target {target} >= input vertices {nv}"
                rows.append(row)
                continue
            log(f"{name} -> {target} vertices: bpm-simplify")
            bpm_out = stem + ".bpm"
            for p in (bpm_out,):
                if os.path.exists(p):
                    os.remove(p)
            bpm = timed([bins["bpm-simplify"], off, "-o", bpm_out, "--vertices", str(target)],
                        stem + "-bpm.log", args.timeout)
            log(f"  bpm: {bpm['status']} {fmt(bpm['seconds'], '.2f')} s {fmt(bpm['peak_mb'], '.0f')} MB {bpm['message']}")
            log(f"{name} -> {target} vertices: psurface-simplify")
            ps_out = stem + "-psurface.vtu"
            for p in (ps_out, stem + "-psurface-graph.vtu"):
                if os.path.exists(p):
                    os.remove(p)
            ps_cmd = ["psurface-simplify", "-i", msh, "-o", ps_out, "-c", str(nv - target)] + args.psurface_flags.split()
            ps = timed(ps_cmd, stem + "-psurface.log", args.timeout, cwd=work)
            if ps["status"] == "ok" and not os.path.exists(ps_out):
                ps["status"], ps["message"] = "failed", "exit 0 but no output file"
            log(f"  psurface: {ps['status']} {fmt(ps['seconds'], '.2f')} s {fmt(ps['peak_mb'], '.0f')} MB {ps['message']}")

            for tool, res, out in (("bpm", bpm, bpm_out), ("psurface", ps, ps_out)):
                if res["status"] != "ok":
                    continue
                code, data, err = run_json([bins["bpm-bench-metrics"], off, out, "--samples", str(args.samples)],
                                           args.timeout)
                res["metrics"] = data
                if data is None:
                    res["metrics_error"] = f"bpm-bench-metrics exit {code}: {err}"
            if bpm["status"] == "ok":
                code, data, err = run_json([bins["bpm-check"], "--json", bpm_out], args.timeout)
                bpm["check_exit"] = code
                bpm["check"] = data
                if data:
                    bpm["check_failed"] = [c["name"] for c in data.get("checks", []) if not c.get("passed", False)]
                else:
                    bpm["check_failed"] = [f"no report ({err})"]
            row["bpm"], row["psurface"] = bpm, ps
            if bpm["status"] == ps["status"] == "ok" and bpm["seconds"]:
                row["time_ratio"] = ps["seconds"] / max(bpm["seconds"], 0.01)
            rows.append(row)
            write_atomic(json_path, json.dumps({"run": header, "rows": rows}, indent=1) + "\n")
            write_atomic(md_path, simplify_markdown(header, rows))
    write_atomic(json_path, json.dumps({"run": header, "rows": rows}, indent=1) + "\n")
    write_atomic(md_path, simplify_markdown(header, rows))
    log(f"wrote {md_path}")


def status_cell(res):
    if res is None:
        return "—"
    if res["status"] == "ok":
        return "ok"
    return f"**{res['status']}**"


def simplify_markdown(header, rows):
    out = ["# bpm-simplify vs psurface-simplify", "",
           f"Measured {header['date']}; bpm commit {header['commit']}; {header.get('binary', '')}. "
           "Generated by `bench/run.py simplify`; "
           "see bench/README.md for what each column means.", "",
           f"Both tools get the same target vertex count (psurface: `-c <input vertices - target>` "
           f"{('with flags `' + header['psurface_flags'] + '`') if header['psurface_flags'] else 'with default flags'}). "
           f"Memory = peak resident set (MB), times from `/usr/bin/time -f \"%e %M %U %S\"`; "
           f"timeout {header['timeout_s']} s per run. The machine is shared, so times carry noise.", "",
           "## Time and memory", "",
           "Wall = elapsed seconds; CPU = user + system seconds (less sensitive to other load on the machine; both "
           "tools are single-threaded, so CPU ≈ wall on an idle machine).", "",
           "| mesh | input V | target V | bpm wall s | bpm CPU s | bpm MB | psurface wall s | psurface CPU s | psurface MB "
           "| psurface/bpm wall | psurface/bpm CPU |",
           "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    ratios, cpu_ratios = [], []
    for r in rows:
        if "bpm" not in r:
            out.append(f"| {r['mesh']} | {r.get('input_vertices', '—')} | {r.get('target_vertices', '—')} | "
                       f"{r.get('error', 'not run')} | | | | | | | |")
            continue
        b, p = r["bpm"], r["psurface"]

        def t(res, key):
            return fmt(res.get(key), ".2f") if res["status"] == "ok" else f"**{res['status']}**"

        def m(res):
            return fmt(res["peak_mb"], ".0f") if res["status"] == "ok" else "—"
        ratio = r.get("time_ratio")
        if ratio is not None:
            ratios.append(ratio)
        cpu_ratio = None
        if b["status"] == p["status"] == "ok" and b.get("cpu_seconds") is not None and p.get("cpu_seconds") is not None:
            cpu_ratio = p["cpu_seconds"] / max(b["cpu_seconds"], 0.01)
            cpu_ratios.append(cpu_ratio)
        out.append(f"| {r['mesh']} | {r['input_vertices']} | {r['target_vertices']} ({r['target_label']}) "
                   f"| {t(b, 'seconds')} | {t(b, 'cpu_seconds')} | {m(b)} "
                   f"| {t(p, 'seconds')} | {t(p, 'cpu_seconds')} | {m(p)} | {fmt(ratio, '.2f')} | {fmt(cpu_ratio, '.2f')} |")
    med = statistics.median(ratios) if ratios else None
    cpu_med = statistics.median(cpu_ratios) if cpu_ratios else None
    out += ["", f"Median time ratio psurface/bpm over the {len(ratios)} rows where both succeeded: "
                f"**{fmt(med, '.2f')}** (wall), **{fmt(cpu_med, '.2f')}** (CPU); > 1 means bpm is faster.", ""]
    failures = [f"- {r['mesh']} → {r['target_vertices']}, {tool}: {r[tool]['status']} — {r[tool]['message']}"
                for r in rows if "bpm" in r for tool in ("bpm", "psurface") if r[tool]["status"] != "ok"]
    if failures:
        out += ["Runs that did not finish:", ""] + failures + [""]

    out += ["## Quality of the coarse surfaces", "",
            "Hausdorff = two-sided sampled Hausdorff distance / bounding-box diagonal of the original; mean = mean of the "
            "two one-sided mean distances / diagonal; R/r = circumradius / inradius (2 = equilateral); "
            "self-int. = self-intersecting triangle pairs (`bpm::check_intersections`); topology = Euler characteristic, "
            "components, boundary loops, Betti numbers, orientability, manifoldness equal to the original's "
            "(`bpm::compare_topology`); bpm-check = format, intersections, topology, bijectivity of the .bpm.", "",
            "| mesh | target V | tool | V | T | Hausdorff | mean | max R/r | mean R/r | self-int. | topology | bpm-check |",
            "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---|---|"]
    for r in rows:
        if "bpm" not in r:
            continue
        for tool in ("bpm", "psurface"):
            res = r[tool]
            if res["status"] != "ok":
                out.append(f"| {r['mesh']} | {r['target_vertices']} | {tool} | **{res['status']}**: {res['message']} "
                           "| | | | | | | | |")
                continue
            q = metrics_cell(res.get("metrics"))
            if q is None:
                out.append(f"| {r['mesh']} | {r['target_vertices']} | {tool} | metrics failed: "
                           f"{res.get('metrics_error', '')[:120]} | | | | | | | | |")
                continue
            if tool == "bpm":
                failed = res.get("check_failed", [])
                check = "pass" if res.get("check_exit") == 0 else ("**fail**: " + ", ".join(failed) if failed
                                                                   else f"exit {res.get('check_exit')}")
            else:
                check = "n/a"
            amax = fmt(q["aspect_max"], ".1f") if q["aspect_max"] is not None else "∞"
            out.append(f"| {r['mesh']} | {r['target_vertices']} | {tool} | {q['vertices']} | {q['triangles']} | "
                       f"{q['hausdorff_relative']:.5f} | {q['mean_relative']:.6f} | {amax} | {q['aspect_mean']:.2f} | "
                       f"{q['self_intersecting_pairs']} | {'yes' if q['topology_preserved'] else '**no**'} | {check} |")
    notes = []
    for r in rows:
        for tool in ("bpm", "psurface"):
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
    out += ["", "psurface writes Float32 coordinates to its .vtu; its coarse vertices are therefore rounded to single "
                "precision before they are measured.", ""]
    return "\n".join(out)


# ---------------------------------------------------------------- scaling suite

def scaling_suite(args, bins, work):
    base = os.path.join(MESHES, "armadillo.off")
    rows = []
    json_path = os.path.join(RESULTS, f"scaling{args.suffix}.json")
    md_path = os.path.join(RESULTS, f"scaling{args.suffix}.md")
    header = {"date": machine_line(), "commit": git_commit(), "binary": binary_line(bins["bpm-simplify"]),
              "timeout_s": args.scaling_timeout,
              "target_vertices": args.scaling_target}
    for level in args.levels:
        path = base if level == 0 else os.path.join(work, f"armadillo-loop{level}.off")
        if level > 0 and (not os.path.exists(path) or os.path.getmtime(path) < os.path.getmtime(base)):
            log(f"Loop subdivision level {level} -> {path}")
            subprocess.run([PYTHON, os.path.join(BENCH, "make_subdivided.py"), base, str(level), path], check=True)
        nv, nt = read_off_header(path)
        log(f"scaling: armadillo level {level} ({nt} triangles) -> {args.scaling_target} vertices")
        out = os.path.join(work, f"armadillo-loop{level}-{args.scaling_target}.bpm")
        if os.path.exists(out):
            os.remove(out)
        res = timed([bins["bpm-simplify"], path, "-o", out, "--vertices", str(args.scaling_target)],
                    os.path.join(work, f"scaling-loop{level}.log"), args.scaling_timeout)
        log(f"  {res['status']} {fmt(res['seconds'], '.1f')} s {fmt(res['peak_mb'], '.0f')} MB {res['message']}")
        rows.append({"level": level, "input": os.path.relpath(path, ROOT) if level == 0 else f"armadillo + {level}x Loop",
                     "vertices": nv, "triangles": nt, **res})
        write_atomic(json_path, json.dumps({"run": header, "rows": rows}, indent=1) + "\n")
        write_atomic(md_path, scaling_markdown(header, rows))
    log(f"wrote {md_path}")


def scaling_markdown(header, rows):
    out = ["# bpm-simplify scaling", "",
           f"Measured {header['date']}; bpm commit {header['commit']}; {header.get('binary', '')}. "
           "Generated by `bench/run.py scaling`.", "",
           f"armadillo.off (52k triangles) and its Loop subdivisions (1 and 2 levels: 208k, 832k triangles, made by "
           f"`bench/make_subdivided.py`), each simplified by `bpm-simplify --vertices {header['target_vertices']}`. "
           f"Wall = elapsed seconds, CPU = user + system seconds (bpm-simplify is single-threaded; on a loaded machine "
           f"CPU is the steadier number), memory = peak resident set; all from `/usr/bin/time`; timeout "
           f"{header['timeout_s']} s. n = input triangles; the last two columns are time / (n log2 n), normalised to 1 "
           "for the first row that finished (≈ 1 on every row means O(n log n)).", "",
           "Target (issue): 830k triangles → 10k vertices in ≤ 60 s and ≤ 2 GB.", "",
           "| input | V | T (n) | status | wall s | CPU s | peak MB | µs per triangle (wall) "
           "| wall/(n log n), normalised | CPU/(n log n), normalised |",
           "|---|---:|---:|---|---:|---:|---:|---:|---:|---:|"]
    ref = cpu_ref = None
    for r in rows:
        if r["status"] == "ok" and r["seconds"]:
            ref = r["seconds"] / (r["triangles"] * math.log2(r["triangles"]))
            if r.get("cpu_seconds"):
                cpu_ref = r["cpu_seconds"] / (r["triangles"] * math.log2(r["triangles"]))
            break
    for r in rows:
        ok = r["status"] == "ok"
        norm = (r["seconds"] / (r["triangles"] * math.log2(r["triangles"])) / ref) if ok and ref else None
        cpu_norm = (r["cpu_seconds"] / (r["triangles"] * math.log2(r["triangles"])) / cpu_ref
                    if ok and cpu_ref and r.get("cpu_seconds") else None)
        per = 1e6 * r["seconds"] / r["triangles"] if ok else None
        status = "ok" if ok else f"**{r['status']}** {r['message']}"
        mem = fmt(r["peak_mb"], ".0f") if r["peak_mb"] is not None and ok else (
            f"≥ {r['peak_mb']:.0f}" if r["peak_mb"] else "—")
        secs = fmt(r["seconds"], ".1f") if ok else f"> {r['seconds']:.0f}" if r["status"] == "timeout" else fmt(r["seconds"], ".1f")
        cpu = fmt(r.get("cpu_seconds"), ".1f") if ok else "—"
        out.append(f"| {r['input']} | {r['vertices']} | {r['triangles']} | {status} | {secs} | {cpu} | {mem} | "
                   f"{fmt(per, '.1f')} | {fmt(norm, '.2f')} | {fmt(cpu_norm, '.2f')} |")
    big = [r for r in rows if r["triangles"] > 800000]
    if big:
        r = big[-1]
        if r["status"] == "ok":
            meets = r["seconds"] <= 60 and r["peak_mb"] <= 2048
            cpu = f" ({r['cpu_seconds']:.1f} s CPU)" if r.get("cpu_seconds") is not None else ""
            out += ["", f"832k-triangle row: {r['seconds']:.1f} s wall{cpu}, {r['peak_mb']:.0f} MB — target "
                        f"{'met' if meets else '**not met**'} (time ≤ 60 s: {'yes' if r['seconds'] <= 60 else 'no'}, "
                        f"memory ≤ 2 GB: {'yes' if r['peak_mb'] <= 2048 else 'no'})."]
        else:
            out += ["", f"832k-triangle row: {r['status']} — target **not met**."]
    out.append("")
    return "\n".join(out)


# ---------------------------------------------------------------- main

def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("suite", nargs="?", default="all", choices=["simplify", "scaling", "all"])
    ap.add_argument("--build-dir", default=os.path.join(ROOT, "build-bench"))
    ap.add_argument("--no-build", action="store_true", help="use the binaries already in BUILD_DIR/bin")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--meshes", default=",".join(DEFAULT_MESHES), help="comma-separated names in .data/meshes")
    ap.add_argument("--timeout", type=int, default=900, help="seconds per tool run in the simplify suite")
    ap.add_argument("--samples", type=int, default=500000, help="bpm-bench-metrics --samples")
    ap.add_argument("--psurface-flags", default="", help="extra psurface-simplify flags, e.g. '-s'")
    ap.add_argument("--suffix", default="", help="results go to results/simplify<SUFFIX>.md etc. (e.g. '-psurface-s')")
    ap.add_argument("--levels", default="0,1,2", help="Loop subdivision levels for the scaling suite")
    ap.add_argument("--scaling-target", type=int, default=10000)
    ap.add_argument("--scaling-timeout", type=int, default=900)
    args = ap.parse_args()
    args.meshes = [m for m in args.meshes.split(",") if m]
    args.levels = [int(l) for l in args.levels.split(",") if l]
    args.build_dir = os.path.abspath(args.build_dir)

    if not args.no_build:
        build(args.build_dir, args.jobs)
    bins = {t: os.path.join(args.build_dir, "bin", t) for t in ("bpm-simplify", "bpm-check", "bpm-bench-metrics")}
    for t, p in bins.items():
        if not os.access(p, os.X_OK):
            sys.exit(f"run.py: error: {p} missing (build first)")
    if args.suite in ("simplify", "all") and not shutil.which("psurface-simplify"):
        log("warning: psurface-simplify not found; its rows will say 'failed'")
    work = os.path.join(args.build_dir, "bench-work")
    os.makedirs(work, exist_ok=True)
    os.makedirs(RESULTS, exist_ok=True)
    if args.suite in ("simplify", "all"):
        simplify_suite(args, bins, work)
    if args.suite in ("scaling", "all"):
        scaling_suite(args, bins, work)


if __name__ == "__main__":
    main()
