#!/usr/bin/python3
"""Refined .bpm files pass bpm-check: issue 19's target, measured (bench/README.md).

    /usr/bin/python3 bench/refined_check.py [--no-build] [--build-dir DIR] [--results-dir DIR] [--work-dir DIR]
                                            [--meshes a,b,c] [--levels 1,2] [options]

For every mesh (default femur, fandisk, elephant, armadillo, mech-holes-shark from .data/meshes) at both
coarse sizes (10 % of the input vertices and 1000 vertices), and for the two multi-material fixtures
(two_cubes: two unit cubes sharing a face, bench/make_two_cubes.py, 30 % of the vertices; nested_spheres:
two icospheres, one file per material, bench/make_nested_spheres.py, 10 %):

  bpm-simplify IN... -o COARSE.bpm (--ratio R | --vertices 1000) --deterministic
  bpm-smooth COARSE.bpm -o SMOOTH.bpm --deterministic            (the same rows again from the smoothed phi)
  bpm-refine COARSE.bpm --levels K -o K.bpm --deterministic      (default options: the refined phi; new
                                                                 vertices held back where the surface would
                                                                 intersect itself; bpm-refine verifies its
                                                                 output before writing it)
  bpm-check --json K.bpm                                         (all checks, independently of bpm-refine)

and writes RESULTS_DIR/refined-check.md and refined-check.json (default bench/results), rewritten after
every row. Work files go to WORK_DIR (default BUILD_DIR/bench-work/refined_check).

Target (issue 19): refined .bpm files at K = 1, 2 pass bpm-check on every row and on the multi-material
fixtures. Exit 1 when a row fails (a tool failed, or a check failed).
"""
import argparse
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run import MESHES, binary_line, rel, write_atomic  # noqa: E402  (the main driver)
from suite import PYTHON, Suite, load_json  # noqa: E402  (shared with refine.py, adaptive.py)

SUITE = Suite("refined_check", ["bpm-simplify", "bpm-smooth", "bpm-refine", "bpm-check"])
log = SUITE.log
HERE = os.path.dirname(os.path.abspath(__file__))
FIXTURES = ["two_cubes", "nested_spheres"]


def fixture_inputs(args, name):
    """(input files, bpm-simplify options) of a multi-material fixture, made in the work directory."""
    if name == "two_cubes":
        out = os.path.join(args.work_dir, "two_cubes.obj")
        SUITE.runner(args).run([PYTHON, os.path.join(HERE, "make_two_cubes.py"), out, "4"], "two_cubes-make")
        return [out], ["--ratio", "0.3"]
    outer, inner = (os.path.join(args.work_dir, f"nested_spheres_{w}.off") for w in ("outer", "inner"))
    SUITE.runner(args).run([PYTHON, os.path.join(HERE, "make_nested_spheres.py"), outer, inner, "4"],
                           "nested_spheres-make")
    return [outer, inner], ["--ratio", "0.1"]


def run_row(args, bins, runner, name, label, tag, inputs, sim_opts, smoothed):
    stem = f"{name}-{tag}" if tag else name
    coarse = os.path.join(args.work_dir, stem + ".bpm")
    row = {"mesh": name, "target": label, "smoothed": smoothed, "inputs": [rel(i) for i in inputs], "levels": []}
    row["simplify"] = runner.run([bins["bpm-simplify"]] + inputs + ["-o", coarse] + sim_opts + ["--deterministic"],
                                 stem + "-simplify")
    if row["simplify"]["status"] != "ok":
        return row
    if smoothed:
        smooth = os.path.join(args.work_dir, stem + ".smooth.bpm")
        row["smooth"] = runner.run([bins["bpm-smooth"], coarse, "-o", smooth, "--deterministic"], stem + "-smooth")
        if row["smooth"]["status"] != "ok":
            return row
        coarse, stem = smooth, stem + ".smooth"
    for k in args.levels:
        level = {"K": k}
        out = os.path.join(args.work_dir, f"{stem}.K{k}.bpm")
        level["refine"] = runner.run([bins["bpm-refine"], coarse, "--levels", str(k), "-o", out, "--deterministic"],
                                     f"{stem}-K{k}-refine")
        if level["refine"]["status"] == "ok":
            report = os.path.join(args.work_dir, f"{stem}.K{k}.check.json")
            # Exit 1 (a check failed) is a measurement: the report says which.
            level["check"] = runner.run([bins["bpm-check"], "--json", out], f"{stem}-K{k}-check", stdout_path=report)
            level["report"] = load_json(report)
            level["bytes"] = os.path.getsize(out)
        row["levels"].append(level)
    return row


def passed(level):
    rep = level.get("report")
    return None if rep is None else bool(rep.get("passed"))


def check_cell(level, name):
    for c in (level.get("report") or {}).get("checks", []):
        if c.get("name") == name:
            return "pass" if c.get("passed") else f"**FAIL** ({len(c.get('problems') or [])})"
    return "—"


def markdown(header, rows):
    names = ["format", "intersections", "topology", "bijectivity", "distortion"]
    out = ["# Refined .bpm files through bpm-check (issue 19)", "",
           f"Generated by `{header['invocation']}` on {header['started']} UTC, commit {header['commit']}, "
           f"{header['cpu']} ({header['cores']} cores), binaries `{header['binary']}`.", "",
           "Per row: `bpm-simplify IN... --ratio R | --vertices 1000 --deterministic`, then per level K "
           "`bpm-refine COARSE.bpm --levels K -o K.bpm` (default options) and `bpm-check --json K.bpm` (every "
           "check; independent of the verification bpm-refine runs before it writes). Fixtures: two_cubes "
           "(two unit cubes sharing a face, one OBJ with patch groups, 30 %), nested_spheres (two icospheres, "
           "one OFF per material, 10 %). φ = the map refined: bpm-simplify's, or bpm-smooth's of it "
           "(`bpm-smooth COARSE.bpm -o SMOOTH.bpm`). **met** = the file passes every check.", "",
           "| mesh | target | φ | K | coarse T | " + " | ".join(names) + " | .bpm MB | refine CPU s | check CPU s | met |",
           "|---|---|---|---:|---:|" + "---|" * len(names) + "---:|---:|---:|---|"]
    results = []
    for row in rows:
        for level in row["levels"]:
            rep = level.get("report") or {}
            counts = {}
            for c in rep.get("checks", []):
                if c.get("name") == "intersections":
                    counts = c.get("counts") or {}
            p = passed(level)
            results.append(bool(p))
            refine, check = level.get("refine") or {}, level.get("check") or {}
            out.append(f"| {row['mesh']} | {row['target']} | {'bpm-smooth' if row['smoothed'] else 'simplified'} | "
                       f"{level['K']} | {counts.get('triangles', '—')} | " +
                       " | ".join(check_cell(level, n) for n in names) +
                       f" | {level.get('bytes', 0) / 1e6:.1f} | {refine.get('cpu_seconds') or 0:.2f} | "
                       f"{check.get('cpu_seconds') or 0:.2f} | "
                       f"{'met' if p else ('**not met**' if p is not None else '**failed: ' + refine.get('status', '?') + '**')} |")
    out += ["", f"Passed every check: {sum(results)} of {len(results)} refined files."]
    failures = []
    for row in rows:
        tag = f"{row['mesh']} {row['target']}{' smoothed' if row['smoothed'] else ''}"
        if (row.get("simplify") or {}).get("status") != "ok":
            failures.append(f"- {tag}: bpm-simplify {row['simplify'].get('message')} "
                            f"(log `{rel(row['simplify']['log'])}`)")
        if row.get("smooth") and row["smooth"].get("status") != "ok":
            failures.append(f"- {tag}: bpm-smooth {row['smooth'].get('message')} (log `{rel(row['smooth']['log'])}`)")
        for level in row["levels"]:
            r = level["refine"]
            if r.get("status") != "ok":
                failures.append(f"- {tag} K = {level['K']}: bpm-refine "
                                f"{r.get('message', r.get('status'))} (log `{rel(r['log'])}`)")
            for c in (level.get("report") or {}).get("checks", []):
                if not c.get("passed"):
                    first = (c.get("problems") or [{}])[0]
                    failures.append(f"- {tag} K = {level['K']}: {c.get('name')}: "
                                    f"{c.get('summary', '')} {json.dumps(first)[:300]}")
    if failures:
        out += ["", "Failures:", ""] + failures
    return "\n".join(out) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    SUITE.add_arguments(ap)
    SUITE.add_target_argument(ap)
    ap.add_argument("--levels", default="1,2", help="bpm-refine --levels values")
    ap.add_argument("--fixtures", default=",".join(FIXTURES), help="multi-material fixtures ('' for none)")
    args = ap.parse_args()
    SUITE.prepare(args)
    args.levels = [int(x) for x in args.levels.split(",") if x]
    targets = SUITE.targets(args)
    fixtures = [f for f in args.fixtures.split(",") if f]
    unknown = [f for f in fixtures if f not in FIXTURES]
    if unknown:
        sys.exit(f"refined_check.py: error: unknown fixture(s) {', '.join(unknown)} (known: {', '.join(FIXTURES)})")

    t_start = time.monotonic()
    header = SUITE.header(args, sys.argv[1:])
    header["build"] = SUITE.build(args)
    bins = SUITE.binaries(args)
    header["binary"] = binary_line(bins["bpm-refine"])
    runner = SUITE.runner(args)
    header["commands"] = runner.commands
    md_path = os.path.join(args.results_dir, "refined-check.md")
    json_path = os.path.join(args.results_dir, "refined-check.json")
    rows = []

    def write():
        write_atomic(md_path, markdown(header, rows))
        write_atomic(json_path, json.dumps({"header": header, "rows": rows}, indent=1, default=str) + "\n")

    for mesh in args.meshes:
        for label, tag, opts in targets:
            for smoothed in (False, True):
                rows.append(run_row(args, bins, runner, mesh, label, tag, [os.path.join(MESHES, mesh + ".off")], opts,
                                    smoothed))
                write()
    for name in fixtures:
        inputs, opts = fixture_inputs(args, name)
        for smoothed in (False, True):
            rows.append(run_row(args, bins, runner, name, "fixture", "", inputs, opts, smoothed))
            write()
    SUITE.finish_header(header, t_start)
    write()
    log(f"wrote {rel(md_path)} and {rel(json_path)}")
    ok = all((r.get("simplify") or {}).get("status") == "ok" and (r.get("smooth") or {"status": "ok"})["status"] == "ok"
             and r["levels"] and all(passed(x) for x in r["levels"])
             for r in rows)
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
