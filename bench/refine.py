#!/usr/bin/python3
"""Refinement through phi: convergence, shape and phi evaluation throughput (bench/README.md).

    /usr/bin/python3 bench/refine.py [--no-build] [--build-dir DIR] [--results-dir DIR] [--work-dir DIR]
                                     [--meshes a,b,c] [options]

For every mesh (default femur, fandisk, elephant, armadillo, mech-holes-shark from .data/meshes) and
both coarse sizes (10 % of the input vertices and 1000 vertices):

  bpm-simplify IN.off -o RAW.bpm (--ratio 0.1 | --vertices 1000) --deterministic
  bpm-check --json RAW.bpm
  bpm-smooth RAW.bpm -o SMOOTH.bpm --deterministic          (phi smoothed, same coarse surface)
  bpm-check --json SMOOTH.bpm
  bpm-bench-refine convergence RAW.bpm --levels 0,1,2,3,4    (Figure 1: two-sided Hausdorff / diagonal
                                                              between the K-times refined surface and the
                                                              original, with phi and plain midpoints)
  bpm-bench-refine convergence SMOOTH.bpm --levels 0,1,2,3,4 (the same with the smoothed phi; an extra row,
                                                              not a target; --no-convergence-smoothed skips it)
  bpm-bench-refine shape RAW.bpm --levels 3                  (Figure 7: aspect ratios without smoothing)
  bpm-bench-refine shape SMOOTH.bpm --levels 3               (... and with smoothing)
  bpm-refine RAW.bpm / SMOOTH.bpm -o K3.off --levels 3       (the K=3 surfaces, to look at; timed)
  bpm-bench-refine throughput RAW.bpm --points 10000000 --threads 1,2   (phi evaluations per second)

and writes RESULTS_DIR/refine.md and refine.json (default bench/results), rewritten after every mesh,
so an interrupted run leaves what it measured. Work files (.bpm, .off, JSON, logs) go to
WORK_DIR (default BUILD_DIR/bench-work/refine), never into the source tree. Without --no-build the
needed targets are built in Release in BUILD_DIR (default build-bench) with
`cmake --build BUILD_DIR -jN --target ...`.

Targets (the issue): with phi the Hausdorff distance falls >= 10x from K=0 to K=4 on every mesh while
plain refinement stays flat (here: falls less than 2x); bpm-smooth halves the 99th-percentile aspect
ratio of the K=3 surface on every mesh; >= 10 million phi evaluations per second (batched, 10 million
random points, 2 threads, wall clock).
"""
import argparse
import json
import os
import shlex
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run import BENCH, MESHES, ROOT, binary_line, git_commit, read_off_header, rel, write_atomic  # noqa: E402
from suite import TARGETS, Suite, load_json, stamp  # noqa: E402  (shared with adaptive.py)

SUITE = Suite("refine", ["bpm-simplify", "bpm-smooth", "bpm-refine", "bpm-check", "bpm-bench-refine"])
log = SUITE.log

CONVERGENCE_FACTOR = 8.0    # phi: H(K=0) / H(K=max) at least this (issue 19)
MEAN_FACTOR = 100.0         # phi: mean two-sided distance K=0 / K=max at least this (issue 19)
PLAIN_FLAT_FACTOR = 2.0     # plain: H(K=0) / H(K=max) below this counts as "stays flat"
SMOOTH_P99_FACTOR = 2.0     # p99 without / with smoothing at least this
THROUGHPUT_TARGET = 10e6    # phi evaluations per wall second, 2 threads


def newest_source():
    """(path relative to the root, mtime) of the newest file under libbpm/, tools/, bench/tools/ and the CMake files:
    what the binaries are built from (no git needed)."""
    best = (None, 0.0)
    for top in ("libbpm", "tools", os.path.join("bench", "tools")):
        for d, _, files in os.walk(os.path.join(ROOT, top)):
            for name in files:
                p = os.path.join(d, name)
                try:
                    m = os.path.getmtime(p)
                except OSError:
                    continue
                if m > best[1]:
                    best = (rel(p), m)
    for p in (os.path.join(ROOT, "CMakeLists.txt"), os.path.join(BENCH, "CMakeLists.txt")):
        if os.path.exists(p) and os.path.getmtime(p) > best[1]:
            best = (rel(p), os.path.getmtime(p))
    return best


def smooth_summary(log_path):
    """bpm-smooth's summary line ("N sweeps over P pairs ...: U updates ..., R rejected, ..."), from its log."""
    try:
        with open(log_path, errors="replace") as f:
            for l in f:
                if " sweeps over " in l:
                    return l.strip().split("bpm-smooth: ", 1)[-1]
    except OSError:
        pass
    return None


def run_case(args, bins, runner, mesh, label, tag, sim_opts):
    inp = os.path.join(MESHES, mesh + ".off")
    stem = f"{mesh}-{tag}"
    raw = os.path.join(args.work_dir, stem + ".bpm")
    smooth = os.path.join(args.work_dir, stem + ".smooth.bpm")
    case = {"mesh": mesh, "target": label, "tag": tag, "input": rel(inp)}
    case["original_vertices"], case["original_triangles"] = read_off_header(inp)

    r = runner.run([bins["bpm-simplify"], inp, "-o", raw] + sim_opts + ["--deterministic"], stem + "-simplify")
    case["simplify"] = r
    if r["status"] != "ok":
        return case
    chk = os.path.join(args.work_dir, stem + ".check.json")
    r = runner.run([bins["bpm-check"], "--json", raw], stem + "-check", stdout_path=chk)
    case["check_raw"] = {"status": r["status"], "exit": r["exit"], "seconds": r["seconds"], "report": load_json(chk)}

    r = runner.run([bins["bpm-smooth"], raw, "-o", smooth, "--deterministic"], stem + "-smooth")
    case["smooth"] = r
    case["smooth"]["summary"] = smooth_summary(r["log"])
    if r["status"] == "ok":
        chk = os.path.join(args.work_dir, stem + ".smooth.check.json")
        r = runner.run([bins["bpm-check"], "--json", smooth], stem + "-smooth-check", stdout_path=chk)
        case["check_smooth"] = {"status": r["status"], "exit": r["exit"], "seconds": r["seconds"],
                                "report": load_json(chk)}

    levels = ",".join(map(str, args.levels))
    out = os.path.join(args.work_dir, stem + ".convergence.json")
    r = runner.run([bins["bpm-bench-refine"], "convergence", raw, "--levels", levels, "--samples", str(args.samples),
                    "--min-per-triangle", str(args.min_per_triangle)], stem + "-convergence", stdout_path=out)
    case["convergence"] = {"run": r, "data": load_json(out) if r["status"] == "ok" else None}
    if args.convergence_smoothed and case["smooth"]["status"] == "ok":
        out = os.path.join(args.work_dir, stem + ".smooth.convergence.json")
        r = runner.run([bins["bpm-bench-refine"], "convergence", smooth, "--levels", levels, "--samples",
                        str(args.samples), "--min-per-triangle", str(args.min_per_triangle)],
                       stem + "-convergence-smooth", stdout_path=out)
        case["convergence_smooth"] = {"run": r, "data": load_json(out) if r["status"] == "ok" else None}

    for variant, path in (("raw", raw), ("smooth", smooth)):
        if variant == "smooth" and case["smooth"]["status"] != "ok":
            continue
        out = os.path.join(args.work_dir, f"{stem}.{variant}.shape.json")
        r = runner.run([bins["bpm-bench-refine"], "shape", path, "--levels", str(args.shape_level)],
                       f"{stem}-shape-{variant}", stdout_path=out)
        case[f"shape_{variant}"] = {"run": r, "data": load_json(out) if r["status"] == "ok" else None}
        off = os.path.join(args.work_dir, f"{stem}.{variant}.K{args.shape_level}.off")
        r = runner.run([bins["bpm-refine"], path, "-o", off, "--levels", str(args.shape_level)],
                       f"{stem}-refine-{variant}")
        case[f"refine_{variant}"] = r

    if not args.no_throughput:
        out = os.path.join(args.work_dir, stem + ".throughput.json")
        r = runner.run([bins["bpm-bench-refine"], "throughput", raw, "--points", str(args.points),
                        "--threads", ",".join(map(str, args.threads)), "--repeat", str(args.repeat)],
                       stem + "-throughput", stdout_path=out)
        case["throughput"] = {"run": r, "data": load_json(out) if r["status"] == "ok" else None}
    return case


# ---------------------------------------------------------------- evaluation

def conv_levels(case, which="convergence"):
    d = (case.get(which) or {}).get("data")
    return d["levels"] if d else None


def conv_factor(case, key, field="hausdorff_relative", which="convergence"):
    lv = conv_levels(case, which)
    if not lv or len(lv) < 2:
        return None
    first, last = lv[0][key].get(field), lv[-1][key].get(field)
    return first / last if first is not None and last else None


def p99_cell(level):
    v = level.get("p99_two_sided_relative")
    return "—" if v is None else f"{v:.2e}"


def shape(case, variant):
    d = (case.get(f"shape_{variant}") or {}).get("data")
    return d["refined"] if d else None


def p99_factor(case):
    a, b = shape(case, "raw"), shape(case, "smooth")
    return a["p99"] / b["p99"] if a and b and a.get("p99") and b.get("p99") else None


def batched(case, output, threads):
    d = (case.get("throughput") or {}).get("data")
    if not d:
        return None
    for b in d["batched"]:
        if b["output"] == output and b["threads"] == threads:
            return b
    return None


def targets(cases):
    """Per case: dict of target name -> (met: bool | None, value text)."""
    out = []
    for c in cases:
        t = {}
        f = conv_factor(c, "phi")
        t["phi_convergence"] = (None if f is None else f >= CONVERGENCE_FACTOR, "—" if f is None else f"{f:.1f}x")
        f = conv_factor(c, "phi", "mean_two_sided_relative")
        t["phi_mean"] = (None if f is None else f >= MEAN_FACTOR, "—" if f is None else f"{f:.0f}x")
        f = conv_factor(c, "plain")
        t["plain_flat"] = (None if f is None else f < PLAIN_FLAT_FACTOR, "—" if f is None else f"{f:.2f}x")
        f = p99_factor(c)
        t["smooth_p99"] = (None if f is None else f >= SMOOTH_P99_FACTOR, "—" if f is None else f"{f:.2f}x")
        b = batched(c, "PhiSample", 2)
        v = b["per_second_median"] if b else None
        t["throughput"] = (None if v is None else v >= THROUGHPUT_TARGET, "—" if v is None else f"{v / 1e6:.1f} M/s")
        out.append(t)
    return out


# ---------------------------------------------------------------- markdown

def f(v, spec):
    return "—" if v is None else format(v, spec)


def status_cell(r):
    return "ok" if r and r.get("status") == "ok" else (r or {}).get("status", "—")


def check_cell(c):
    if not c:
        return "—"
    if c["exit"] == 0:
        return "pass"
    if c["exit"] == 1:
        return "**fail**"
    return f"error (exit {c['exit']})"


def markdown(header, cases):
    ls, le = header["load_start"], header.get("load_end")
    levels = header["levels"]
    kmax = levels[-1]
    mem = header["memory_gib"]
    out = ["# Refinement through φ: convergence, shape, throughput (bench/refine.py)", ""]
    out += [f"Started {header['started']} UTC" + (f", finished {header['finished']} UTC ({header['minutes']:.0f} min)"
                                                 if header.get("finished") else
                                                 " — **still running or interrupted**: below is what finished") + ".",
            "", "| | |", "|---|---|",
            f"| CPU | {header['cpu']}, {header['cores']} cores |",
            f"| memory | {'unknown' if mem is None else f'{mem:.1f} GiB'} |",
            f"| load average at start (1 / 5 / 15 min) | {ls[0]:.2f} / {ls[1]:.2f} / {ls[2]:.2f} |"]
    if le:
        out.append(f"| load average at the end | {le[0]:.2f} / {le[1]:.2f} / {le[2]:.2f} |")
    commit = header["commit"]
    if header.get("commit_end") and header["commit_end"] != header["commit"]:
        commit = f"{header['commit']} at the start, **{header['commit_end']} at the end** (HEAD moved during the run)"
    src = header.get("sources") or {}
    src_line = (f"newest source file when the binaries were checked: `{src.get('newest')}`, modified "
                f"{src.get('newest_mtime')}; oldest of the binaries used: {src.get('oldest_binary_mtime')}"
                + (" — **the binaries are older than that source file**" if src.get("binaries_older_than_sources")
                   else ""))
    if src.get("newest_mtime_at_end") and src.get("newest_mtime_at_end") != src.get("newest_mtime"):
        src_line += (f"; at the end: `{src['newest_at_end']}`, modified {src['newest_mtime_at_end']} (the tree "
                     "changed during the run; the binaries did not)")
    out += [f"| bpm commit | {commit} (`git rev-parse HEAD`; marked when the tree has uncommitted changes) |",
            f"| binaries | {header['binary']} ({rel(header['build_dir'])}, Release) |",
            f"| sources | {src_line} |",
            f"| invocation | `{header['invocation']}` |", ""]
    out += ["The machine has 2 cores and may be shared: wall times carry noise from other work, CPU seconds "
            "(user + system, from `/usr/bin/time`) are the steadier number.", "",
            "What is measured, for every mesh simplified with `bpm-simplify --deterministic` to 10 % of its "
            "vertices and to 1000 vertices:", "",
            f"- **Convergence** (the paper's Figure 1): the coarse surface is refined uniformly K = "
            f"{', '.join(map(str, levels))} times (each coarse triangle into 4^K, red refinement in parameter "
            "space). **with φ**: every vertex is placed on the original surface through φ (`bpm::refine`, what "
            "`bpm-refine --levels K` writes); **plain**: the same triangles with every vertex at its midpoint "
            "position on the flat coarse triangle (geometrically the coarse surface). The number is the two-sided "
            "sampled Hausdorff distance between the refined surface and the original, over the original's "
            f"bounding-box diagonal: every vertex and edge midpoint of each surface plus {header['samples']:,} "
            f"area-proportional random points (at least {header['min_per_triangle']} per triangle, seed 1), "
            "each measured exactly to the other surface (CGAL AABB tree), max of both directions. φ is the "
            "unsmoothed output of bpm-simplify (the target); the row \"with smoothed φ\" repeats the measurement "
            "with φ after bpm-smooth, for comparison.",
            f"- **Shape** (the paper's Figure 7): aspect ratio R/r (circumradius / inradius, 2 = equilateral) of "
            f"every triangle of the K = {header['shape_level']} surface through φ, without smoothing (φ of "
            "bpm-simplify) and with smoothing (φ of `bpm-smooth` with its defaults); max, 99th percentile "
            "(sorted value at index ⌊0.99 n⌋) and mean. The coarse surface is the same in both.",
            f"- **Throughput**: `PhiEvaluator` batch calls on {header['points']:,} random points (uniform random "
            "coarse triangle, uniform random barycentric coordinates; generating them is not timed) on φ of the "
            "10 % and 1000-vertex files: `evaluate` (full `PhiSample`: position, original triangle, barycentric "
            "coordinates) and `evaluate_positions` (positions only), with 1 and 2 threads, "
            f"{header['repeat']} timed calls each after one untimed warm-up call; wall-clock evaluations per second "
            "of the median call (best call in parentheses) and per CPU second (all threads). Single-query loops "
            "(2 million queries, random order and grouped by coarse triangle) for reference.", ""]

    out += ["## Commands", "",
            "Run from the repository root, in this order (`/usr/bin/time -f \"%e %M %U %S\"` and "
            f"`timeout {header['timeout']}` around each):", "",
            "<details><summary>" + f"{len(header['commands'])} commands</summary>", "", "```sh"]
    out += (["# build"] + [shlex.join(rel(x) if os.path.isabs(x) else x for x in c) for c in header["build"]]
            if header["build"] else ["# build skipped (--no-build)"])
    out += header["commands"] + ["```", "", "</details>", ""]

    # Inputs
    out += ["## Inputs", "",
            "Simplify / smooth: wall and CPU seconds of the whole tool run. Smoothing: bpm-smooth's own summary. "
            "bpm-check: all four checks (format, intersections, topology, bijectivity) on the file.", "",
            "| mesh | target | original V / T | coarse V / T | pieces of φ | simplify wall / CPU s | smooth wall / CPU s "
            "| bpm-check raw / smoothed | bpm-smooth |",
            "|---|---|---|---|---:|---|---|---|---|"]
    for c in cases:
        lv = conv_levels(c)
        coarse = ((c.get("shape_raw") or {}).get("data") or {}).get("coarse")
        coarse_t = lv[0]["triangles"] if lv else (coarse or {}).get("count")
        sm = c.get("smooth") or {}
        summary = sm.get("summary") or status_cell(sm)
        s, m = c.get("simplify") or {}, c.get("smooth") or {}
        out.append(f"| {c['mesh']} | {c['target']} | {c['original_vertices']} / {c['original_triangles']} | "
                   f"{f(c.get('coarse_vertices'), 'd')} / {f(coarse_t, 'd')} | {f(check_count(c, 'pieces'), 'd')} | "
                   f"{f(s.get('seconds'), '.1f')} / {f(s.get('cpu_seconds'), '.1f')} | "
                   f"{f(m.get('seconds'), '.1f')} / {f(m.get('cpu_seconds'), '.1f')} | "
                   f"{check_cell(c.get('check_raw'))} / {check_cell(c.get('check_smooth'))} | {summary} |")
    out.append("")

    # Convergence
    out += ["## Convergence (Figure 1)", "",
            "Two-sided Hausdorff distance / bounding-box diagonal between the K-times refined surface and the "
            f"original. Reduction = value at K = {levels[0]} / value at K = {kmax} (the issue's target: ≥ "
            f"{CONVERGENCE_FACTOR:.0f}x with φ, flat without; here \"flat\" = less than {PLAIN_FLAT_FACTOR:.0f}x). "
            "Seconds: the whole bpm-bench-refine run (refinement and both distance measurements, all K), wall / CPU.",
            "",
            "| mesh | target | refinement | " + " | ".join(f"K={k}" for k in levels) + " | reduction | wall / CPU s |",
            "|---|---|---|" + "---:|" * len(levels) + "---:|---|"]
    for c in cases:
        lv = conv_levels(c)
        run = (c.get("convergence") or {}).get("run") or {}
        if not lv:
            out.append(f"| {c['mesh']} | {c['target']} | — | " + " | ".join("—" for _ in levels)
                       + f" | — | {status_cell(run)} |")
            continue
        rows = [("convergence", "phi", "with φ"), ("convergence", "plain", "plain")]
        if conv_levels(c, "convergence_smooth"):
            rows.append(("convergence_smooth", "phi", "with smoothed φ"))
        for which, key, name in rows:
            lvw = conv_levels(c, which)
            fac = conv_factor(c, key, which=which)
            cells = [f"{l[key]['hausdorff_relative']:.2e}" for l in lvw]
            r = (c.get(which) or {}).get("run") or {}
            t = f"{f(r.get('seconds'), '.0f')} / {f(r.get('cpu_seconds'), '.0f')}" if key == "phi" else ""
            out.append(f"| {c['mesh']} | {c['target']} | {name} | " + " | ".join(cells)
                       + f" | {f(fac, '.1f')}x | {t} |")
    out += ["", "Triangles of the refined surface per K: " + "; ".join(
        f"{c['mesh']} {c['target']}: " + ", ".join(f"{l['triangles']:,}" for l in conv_levels(c))
        for c in cases if conv_levels(c)) + ".", ""]
    out += ["Where the Hausdorff distance comes from, and the mean distance (not a target; for reading the table "
            "above): the two one-sided maxima with φ at K = " + f"{levels[0]} and K = {kmax}" + " (original → "
            "refined: the farthest point of the original from the refined surface; refined → original: the "
            "reverse), and the mean two-sided distance (mean of the two one-sided means) / diagonal per K, with φ "
            "(unsmoothed) and plain.", "",
            f"| mesh | target | orig → refined K={levels[0]} / K={kmax} | refined → orig K={levels[0]} / K={kmax} | "
            "mean with φ " + " | ".join(f"K={k}" for k in levels) + " | mean reduction with φ | mean reduction plain | "
            f"p99 with φ K={levels[0]} / K={kmax} | p99 reduction | p99.9 reduction |",
            "|---|---|---|---|" + "---:|" * len(levels) + "---:|---:|---|---:|---:|"]
    for c in cases:
        lv = conv_levels(c)
        if not lv:
            continue
        a, b = lv[0]["phi"], lv[-1]["phi"]
        out.append(f"| {c['mesh']} | {c['target']} | {a['original_to_refined_max_relative']:.2e} / "
                   f"{b['original_to_refined_max_relative']:.2e} | {a['refined_to_original_max_relative']:.2e} / "
                   f"{b['refined_to_original_max_relative']:.2e} | "
                   + " | ".join(f"{l['phi']['mean_two_sided_relative']:.2e}" for l in lv)
                   + f" | {f(conv_factor(c, 'phi', 'mean_two_sided_relative'), '.0f')}x"
                   f" | {f(conv_factor(c, 'plain', 'mean_two_sided_relative'), '.2f')}x"
                   f" | {p99_cell(a)} / {p99_cell(b)}"
                   f" | {f(conv_factor(c, 'phi', 'p99_two_sided_relative'), '.1f')}x"
                   f" | {f(conv_factor(c, 'phi', 'p999_two_sided_relative'), '.1f')}x |")
    out.append("")

    # Shape
    k = header["shape_level"]
    out += [f"## Shape of the K = {k} surface (Figure 7)", "",
            "Aspect ratio R/r of the refined triangles (2 = equilateral). coarse: the coarse surface itself (plain "
            "midpoint refinement has exactly these values). p99 reduction = p99 without / with smoothing (the "
            f"issue's target: ≥ {SMOOTH_P99_FACTOR:.0f}x). Degenerate triangles (infinite ratio) count as the "
            "largest values and are listed.", "",
            "Distortion = aspect ratio of a refined triangle / aspect ratio of its coarse parent (1 = φ is affine "
            "there, as plain refinement is); its p99 and max isolate what φ adds to the shape of the coarse "
            "triangles.", "",
            "| mesh | target | triangles | coarse max / p99 / mean | without smoothing max / p99 / mean | "
            "with smoothing max / p99 / mean | p99 reduction | distortion p99 / max without | distortion p99 / max "
            "with | degenerate without / with |",
            "|---|---|---:|---|---|---|---:|---|---|---|"]

    def trio(s):
        return "—" if not s else f"{f(s['max'], '.3g')} / {f(s['p99'], '.3g')} / {f(s['mean'], '.3g')}"

    for c in cases:
        a, b = shape(c, "raw"), shape(c, "smooth")
        coarse = ((c.get("shape_raw") or {}).get("data") or {}).get("coarse")
        da = ((c.get("shape_raw") or {}).get("data") or {}).get("distortion") or {}
        db = ((c.get("shape_smooth") or {}).get("data") or {}).get("distortion") or {}
        out.append(f"| {c['mesh']} | {c['target']} | {f((a or {}).get('count'), ',')} | {trio(coarse)} | {trio(a)} | "
                   f"{trio(b)} | {f(p99_factor(c), '.2f')}x | {f(da.get('p99'), '.3g')} / {f(da.get('max'), '.3g')} | "
                   f"{f(db.get('p99'), '.3g')} / {f(db.get('max'), '.3g')} | {f((a or {}).get('degenerate'), 'd')} / "
                   f"{f((b or {}).get('degenerate'), 'd')} |")
    out += ["", f"bpm-refine --levels {k} (writing the OFF files in the work directory), wall / CPU s without and "
            "with smoothing: " + "; ".join(
                f"{c['mesh']} {c['target']}: {f((c.get('refine_raw') or {}).get('seconds'), '.1f')} / "
                f"{f((c.get('refine_raw') or {}).get('cpu_seconds'), '.1f')} and "
                f"{f((c.get('refine_smooth') or {}).get('seconds'), '.1f')} / "
                f"{f((c.get('refine_smooth') or {}).get('cpu_seconds'), '.1f')}"
                for c in cases if c.get("refine_raw")) + ".", ""]

    # Throughput
    if not header.get("no_throughput"):
        out += ["## φ evaluation throughput", "",
                f"Millions of φ evaluations per second for a batch of {header['points']:,} random points: wall clock "
                "of the median call (best in parentheses), and per CPU second (process CPU time, all threads); with "
                "2 threads also the CPU seconds / wall seconds of the median call, i.e. how many cores the call "
                "actually got (2.00 = both, on a quiet machine). Build = constructing the `PhiEvaluator` (s). "
                "Single query: `PhiEvaluator::evaluate(t, b)` in a loop over 2 million of the points, in their "
                "random order and sorted by coarse triangle (wall).", "",
                "| mesh | target | coarse T | pieces | build s | PhiSample, 1 thread | PhiSample, 2 threads | "
                "positions, 1 thread | positions, 2 threads | single query, random / grouped |",
                "|---|---|---:|---:|---:|---|---|---|---|---|"]
        for c in cases:
            d = (c.get("throughput") or {}).get("data")
            if not d:
                out.append(f"| {c['mesh']} | {c['target']} | — | — | — | "
                           f"{status_cell((c.get('throughput') or {}).get('run'))} | | | | |")
                continue
            cells = []
            for output in ("PhiSample", "position"):
                for th in (1, 2):
                    b = batched(c, output, th)
                    cores = (f"; {b['median_cpu_seconds'] / b['median_wall_seconds']:.2f} cores"
                             if b and th > 1 and b.get("median_wall_seconds") else "")
                    cells.append("—" if not b else f"{b['per_second_median'] / 1e6:.1f} ({b['per_second_best'] / 1e6:.1f});"
                                                   f" {b['per_cpu_second'] / 1e6:.1f}/CPU s{cores}")
            out.append(f"| {c['mesh']} | {c['target']} | {d['coarse_triangles']} | {d['pieces']} | "
                       f"{d['build_seconds']:.2f} | " + " | ".join(cells) + f" | "
                       f"{d['single_random_order_per_second'] / 1e6:.1f} / {d['single_grouped_order_per_second'] / 1e6:.1f} |")
        out.append("")

    # Targets
    ts = targets(cases)
    out += ["## Targets", "",
            f"- φ convergence: Hausdorff / diagonal with φ falls ≥ {CONVERGENCE_FACTOR:.0f}x from K = {levels[0]} "
            f"to K = {kmax};",
            f"- φ mean: the mean two-sided distance with φ falls ≥ {MEAN_FACTOR:.0f}x over the same levels;",
            f"- plain flat: without φ it falls less than {PLAIN_FLAT_FACTOR:.0f}x (the refined surface is the coarse "
            "one);",
            f"- smoothing: p99 aspect ratio at K = {k} without / with bpm-smooth ≥ {SMOOTH_P99_FACTOR:.0f};",
            f"- throughput: ≥ {THROUGHPUT_TARGET / 1e6:.0f} million φ evaluations (full `PhiSample`) per wall "
            "second with 2 threads, median call.", "",
            "| mesh | target | φ convergence | φ mean | plain flat | smoothing halves p99 | throughput (2 threads) |",
            "|---|---|---|---|---|---|---|"]

    def cell(t):
        met, text = t
        return f"{text}: —" if met is None else (f"{text}: met" if met else f"{text}: **not met**")

    for c, t in zip(cases, ts):
        cols = ["phi_convergence", "phi_mean", "plain_flat", "smooth_p99"] + ([] if header.get("no_throughput") else ["throughput"])
        row = " | ".join(cell(t[x]) for x in cols)
        out.append(f"| {c['mesh']} | {c['target']} | {row} |" + (" — |" if header.get("no_throughput") else ""))
    out.append("")
    for name, key in (("φ convergence", "phi_convergence"), ("φ mean", "phi_mean"), ("plain flat", "plain_flat"),
                      ("smoothing halves p99", "smooth_p99"), ("throughput", "throughput")):
        vals = [t[key][0] for t in ts]
        if key == "throughput" and header.get("no_throughput"):
            continue
        n_met = sum(1 for v in vals if v)
        n_known = sum(1 for v in vals if v is not None)
        verdict = "met on every row" if n_known == len(vals) and n_met == len(vals) else \
            f"**not met** on {n_known - n_met} of {len(vals)} rows" + (
                f" ({len(vals) - n_known} without a result)" if n_known < len(vals) else "")
        out.append(f"- {name}: {verdict}.")
    notes = []
    red = [conv_factor(c, "phi", "mean_two_sided_relative") for c in cases]
    red = [x for x in red if x]
    if red:
        notes.append(f"Convergence: the mean two-sided distance with φ falls {min(red):.0f}x to {max(red):.0f}x from "
                     f"K = {levels[0]} to K = {kmax} on every row (table above), while the Hausdorff distance (the "
                     "target) is the single farthest point and falls much less where it does not reach the target.")
    near = [c for c in cases if shape(c, "raw") and ((c.get("shape_raw") or {}).get("data") or {}).get("coarse")
            and shape(c, "raw")["p99"] <= 1.1 * c["shape_raw"]["data"]["coarse"]["p99"]]
    if near:
        notes.append(f"Shape: on {len(near)} of {len(cases)} rows the p99 aspect ratio without smoothing is within "
                     "10 % of the coarse surface's own p99 (" + ", ".join(f"{c['mesh']} {c['target']}" for c in near)
                     + "): there φ adds almost nothing to the 99th percentile, and halving it would need refined "
                     "triangles much better shaped than the coarse triangles they subdivide (plain refinement, i.e. an "
                     "affine φ, keeps exactly the coarse shapes).")
    cores = [b["median_cpu_seconds"] / b["median_wall_seconds"] for c in cases
             for b in [batched(c, "PhiSample", 2)] if b and b.get("median_wall_seconds")]
    per_cpu = [b["per_cpu_second"] for c in cases for b in [batched(c, "PhiSample", 1)] if b]
    if cores and per_cpu:
        notes.append(f"Throughput: one thread evaluates {min(per_cpu) / 1e6:.1f}–{max(per_cpu) / 1e6:.1f} million "
                     "full φ samples per CPU second; the 2-thread calls got "
                     f"{min(cores):.2f}–{max(cores):.2f} cores' worth of CPU time (load average "
                     f"{ls[0]:.1f} at the start{'' if not le else f', {le[0]:.1f} at the end'} on 2 cores).")
    if notes:
        out += ["", "Notes (computed from the tables above):", ""] + [f"- {n}" for n in notes]
    failures = [(c["mesh"], c["target"], step, r) for c in cases for step, r in
                (("simplify", c.get("simplify")), ("smooth", c.get("smooth")),
                 ("convergence", (c.get("convergence") or {}).get("run")),
                 ("convergence with smoothed φ", (c.get("convergence_smooth") or {}).get("run")),
                 ("shape", (c.get("shape_raw") or {}).get("run")),
                 ("throughput", (c.get("throughput") or {}).get("run")))
                if r and r.get("status") != "ok"]
    if failures:
        out += ["", "Runs that failed:", ""] + [f"- {m} {t} {s}: {r.get('message', r.get('status'))} (log "
                                                 f"`{rel(r['log'])}`)" for m, t, s, r in failures]
    return "\n".join(out) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    SUITE.add_arguments(ap)
    ap.add_argument("--levels", default="0,1,2,3,4", help="convergence: refinement levels K")
    ap.add_argument("--shape-level", type=int, default=3, help="shape: refinement level K")
    ap.add_argument("--samples", type=int, default=200000, help="convergence: area-proportional samples per surface")
    ap.add_argument("--min-per-triangle", type=int, default=1, help="convergence: random samples at least per triangle")
    ap.add_argument("--points", type=int, default=10000000, help="throughput: random points per batch")
    ap.add_argument("--threads", default="1,2", help="throughput: thread counts")
    ap.add_argument("--repeat", type=int, default=3, help="throughput: timed calls per configuration")
    ap.add_argument("--no-throughput", action="store_true", help="skip the throughput measurement")
    ap.add_argument("--no-convergence-smoothed", dest="convergence_smoothed", action="store_false",
                    help="skip the convergence measurement with the smoothed phi (an extra row, not a target)")
    args = ap.parse_args()
    SUITE.prepare(args)
    args.levels = [int(x) for x in args.levels.split(",") if x]
    args.threads = [int(x) for x in args.threads.split(",") if x]

    t_start = time.monotonic()
    header = SUITE.header(args, sys.argv[1:])
    header.update({"levels": args.levels, "shape_level": args.shape_level, "samples": args.samples,
                   "min_per_triangle": args.min_per_triangle, "points": args.points, "threads": args.threads,
                   "repeat": args.repeat, "timeout": args.timeout, "no_throughput": args.no_throughput})
    header["build"] = SUITE.build(args)
    bins = SUITE.binaries(args)
    header["binary"] = binary_line(bins["bpm-simplify"])
    src, src_time = newest_source()
    oldest_bin = min(os.path.getmtime(p) for p in bins.values())
    header["sources"] = {"newest": src, "newest_mtime": stamp(src_time), "oldest_binary_mtime": stamp(oldest_bin),
                         "binaries_older_than_sources": src_time > oldest_bin}
    runner = SUITE.runner(args)
    header["commands"] = runner.commands
    md_path, json_path = os.path.join(args.results_dir, "refine.md"), os.path.join(args.results_dir, "refine.json")
    cases = []

    def write():
        write_atomic(md_path, markdown(header, cases))
        write_atomic(json_path, json.dumps({"header": header, "cases": cases, "targets": targets(cases)}, indent=1,
                                           default=str) + "\n")

    for mesh in args.meshes:
        for label, tag, opts in TARGETS:
            case = run_case(args, bins, runner, mesh, label, tag, opts)
            case["coarse_vertices"] = coarse_vertex_count(case)
            cases.append(case)
            write()
    SUITE.finish_header(header, t_start)
    header["commit_end"] = git_commit()
    src, src_time = newest_source()
    header["sources"]["newest_at_end"], header["sources"]["newest_mtime_at_end"] = src, stamp(src_time)
    write()
    log(f"wrote {rel(md_path)} and {rel(json_path)}")
    failed = [c for c in cases if any(r and r.get("status") != "ok" for r in (
        c.get("simplify"), c.get("smooth"), (c.get("convergence") or {}).get("run"),
        (c.get("shape_raw") or {}).get("run"), (c.get("throughput") or {}).get("run")))]
    sys.exit(1 if failed else 0)


def check_count(case, key):
    """A count of bpm-check's format check on the unsmoothed file (None when it did not run)."""
    rep = (case.get("check_raw") or {}).get("report") or {}
    for c in rep.get("checks", []):
        if c.get("name") == "format":
            return (c.get("counts") or {}).get(key)
    return None


def coarse_vertex_count(case):
    return check_count(case, "coarse_vertices")


if __name__ == "__main__":
    main()
