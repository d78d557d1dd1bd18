#!/usr/bin/env python3
"""The paper's §3 experiment in DUNE: the torsion problem on femur at 10 % (bench/RESULTS.md,
"Solvers: DUNE torsion"), or on a multi-material input (one surface per material).

bpm-simplify --ratio R -> bpm-mesh -> examples/dune/bpm-torsion on levels 0..K, with the
boundary refined through phi and flat (plain midpoints), uniformly and adaptively; the
reference J is the same problem on a mesh of the original surface itself (--ratio 1),
refined flat (its boundary is the original) and Richardson-extrapolated (P1: J_h = J + C h^2).
Writes RESULTS_DIR/dune_torsion-MESH.md and .json. With several regions (materials) the
tables also give the volume error of every region, against the volume its original surfaces
enclose.

Usage: bench/dune_torsion.py [--build-dir build] [--work-dir DIR] [--results-dir bench/results]
                             [--mesh femur | --nested-spheres SUBDIVISIONS | --mesh NAME --inputs A.off B.off ...]
                             [--ratio 0.1] [--levels 3] [--reference-levels 2]
                             [--adaptive-levels 6] [--adaptive-runs phi,flat] [--adaptive-until-flat]
                             [--reference-json FILE] [--results-name NAME] [--reuse]
Needs build-dir/bin/{bpm-simplify,bpm-mesh,bpm-torsion} (bpm-torsion is built with the tests
when DUNE 2.9 with UG is installed). Non-interactive; progress on stderr.
"""
import argparse
import json
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(cmd, out=None):
    print("+ " + " ".join(cmd), file=sys.stderr, flush=True)
    start = time.time()
    result = subprocess.run(cmd, check=True, stdout=subprocess.PIPE, text=True)
    seconds = time.time() - start
    if out:
        with open(out, "w") as f:
            f.write(result.stdout)
    return result.stdout, seconds


def richardson(levels):
    j = [l["J"] for l in levels]
    return j[-1] + (j[-1] - j[-2]) / 3.0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build-dir", default="build")
    ap.add_argument("--work-dir", default=None)
    ap.add_argument("--results-dir", default="bench/results")
    ap.add_argument("--mesh", default=None, help="NAME: the input is .data/meshes/NAME.off (unless --inputs); "
                    "results are written as dune_torsion-NAME.* (default femur, or nested_spheres)")
    ap.add_argument("--inputs", nargs="+", default=None,
                    help="input surfaces, one per material (bpm-simplify A B ...), instead of .data/meshes/NAME.off")
    ap.add_argument("--nested-spheres", type=int, default=None, metavar="SUBDIVISIONS",
                    help="the input is bench/make_nested_spheres.py's two icospheres (radius 1 and 0.5, "
                         "SUBDIVISIONS as there; two materials: the shell and the inner ball); --mesh defaults to "
                         "nested_spheres")
    ap.add_argument("--ratio", default="0.1")
    ap.add_argument("--levels", type=int, default=3)
    ap.add_argument("--reference-levels", type=int, default=2)
    ap.add_argument("--adaptive-levels", type=int, default=6,
                    help="adaptive steps (with --adaptive-until-flat: the most steps); 0: no adaptive runs")
    ap.add_argument("--adaptive-runs", default="flat,phi",
                    help="which adaptive series to run: comma-separated from flat, phi")
    ap.add_argument("--adaptive-until-flat", action="store_true",
                    help="stop each adaptive series at the first step whose J error is at most the uniform flat "
                         "series' error at --levels (bpm-torsion --reference-j --until-error)")
    ap.add_argument("--adaptive-until-error", type=float, default=None,
                    help="with --adaptive-until-flat: this fraction instead of the flat series' final error "
                         "(for instance the flat error of an earlier level-0 mesh)")
    ap.add_argument("--results-name", default=None,
                    help="write RESULTS_DIR/dune_torsion-NAME.{md,json} (default: the --mesh name)")
    ap.add_argument("--reuse", action="store_true",
                    help="reuse meshes and bpm-torsion JSON already in the work directory from an earlier run "
                         "with the same arguments (one run at a time on a shared machine)")
    ap.add_argument("--reference-json", default=None,
                    help="reuse an earlier reference run: bpm-torsion --flat --json of the --ratio 1 mesh, or a results file dune_torsion-NAME.json")
    args = ap.parse_args()
    os.chdir(ROOT)
    bin_dir = os.path.join(args.build_dir, "bin")
    work = args.work_dir or os.path.join(args.build_dir, "bench-work", "dune_torsion")
    os.makedirs(work, exist_ok=True)
    os.makedirs(args.results_dir, exist_ok=True)
    if args.nested_spheres is not None:
        if args.inputs:
            ap.error("--nested-spheres and --inputs exclude each other")
        args.mesh = args.mesh or "nested_spheres"
        args.inputs = [os.path.join(work, f"spheres{args.nested_spheres}-outer.off"),
                       os.path.join(work, f"spheres{args.nested_spheres}-inner.off")]
        if not (args.reuse and all(os.path.exists(p) for p in args.inputs)):
            run(["/usr/bin/python3", os.path.join("bench", "make_nested_spheres.py"), *args.inputs,
                 str(args.nested_spheres)])
    args.mesh = args.mesh or "femur"
    surfaces = args.inputs or [os.path.join(".data", "meshes", args.mesh + ".off")]
    tool = lambda name: os.path.join(bin_dir, name)

    def mesh(ratio, tag):
        coarse = os.path.join(work, f"{args.mesh}-{tag}.bpm")
        tets = os.path.join(work, f"{args.mesh}-{tag}.tets.bpm")
        if args.reuse and os.path.exists(tets):
            return tets
        run([tool("bpm-simplify"), *surfaces, "--ratio", str(ratio), "-o", coarse, "-q", "--deterministic"])
        run([tool("bpm-mesh"), coarse, "-o", tets, "-q", "--deterministic"])
        return tets

    def torsion(tets, levels, *flags, until=None):
        name = os.path.basename(tets).replace(".tets.bpm", "") + "".join(f.replace("--", "-") for f in flags)
        name += f"-levels{levels}" + (f"-until{until[1]:.6g}" if until else "")
        path = os.path.join(work, name + ".json")
        if args.reuse and os.path.exists(path):
            print(f"reusing {path}", file=sys.stderr)
            with open(path) as f:
                return json.load(f)
        extra = ["--reference-j", repr(until[0]), "--until-error", repr(until[1])] if until else []
        # CPU seconds of the child (bpm-torsion and its forked adapt tries) from the kernel's accounting.
        before = os.times()
        out, seconds = run([tool("bpm-torsion"), tets, "--levels", str(levels), "--json", *flags, *extra])
        after = os.times()
        data = json.loads(out)
        data["wall_seconds"] = seconds
        data["cpu_seconds"] = (after.children_user - before.children_user) + (after.children_system - before.children_system)
        with open(path, "w") as f:
            json.dump(data, f, indent=1)
        return data

    if args.reference_json:
        with open(args.reference_json) as f:
            reference = json.load(f)
        # Either bpm-torsion's JSON of the reference run or an earlier results file
        # (dune_torsion-NAME.json), which keeps that run under "reference".
        if "levels" not in reference and "reference" in reference:
            reference = reference["reference"]
    else:
        reference_tets = mesh(1, "original")
        reference = torsion(reference_tets, args.reference_levels, "--flat")
    j_ref = richardson(reference["levels"])
    tets = mesh(args.ratio, f"r{args.ratio}")
    runs = {
        "flat": torsion(tets, args.levels, "--flat"),
        "phi": torsion(tets, args.levels),
    }
    flat_final_error = abs(runs["flat"]["levels"][-1]["J"] - j_ref) / j_ref
    until_error = args.adaptive_until_error if args.adaptive_until_error else flat_final_error
    until = (j_ref, until_error) if args.adaptive_until_flat else None
    adaptive_runs = [r for r in args.adaptive_runs.split(",") if r] if args.adaptive_levels > 0 else []
    for r in adaptive_runs:
        if r not in ("flat", "phi"):
            ap.error(f"--adaptive-runs: unknown series {r!r} (flat, phi)")
        runs["adaptive " + r] = torsion(tets, args.adaptive_levels, *(["--flat"] if r == "flat" else []), "--adaptive",
                                        until=until)
    v_orig = sum(runs["phi"]["original_region_volumes"])

    lines = []
    lines.append(f"### Torsion -Δu = 1 on {args.mesh} at {float(args.ratio) * 100:g} % (bench/dune_torsion.py)\n")
    lines.append("P1 elements on Dune::UGGrid<3> (DUNE 2.9), CG with dune-istl's AMG (relative residual 1e-10); "
                 "`bpm-torsion` (examples/dune). *phi*: UG's refinement puts new boundary vertices at phi of their "
                 "parameter points (one bpm::dune::PhiBoundarySegment per boundary face); *flat*: at edge "
                 "midpoints. Errors are relative to the reference J and to the volume enclosed by the original "
                 f"surface ({v_orig:.6g}).\n")
    lines.append(f"Reference: {' + '.join(os.path.basename(p) for p in surfaces)} itself (bpm-simplify --ratio 1, "
                 "bpm-mesh, flat refinement, whose boundary is the original surface): J = " +
                 ", ".join(f"{l['J']:.6g}" for l in reference["levels"]) +
                 f" on {', '.join(str(l['tets']) for l in reference['levels'])} tets; Richardson-extrapolated "
                 f"J_ref = {j_ref:.6g}.\n")
    lines.append("phi runs apply bpm::repair_boundary after every refinement (bpm/dune/uggrid_repair.h: UG's new "
                 "boundary vertices back to their edge midpoints, then towards phi as far as no element inverts or "
                 "flattens, interior smoothed; UG keeps the rules of refined elements, "
                 "bpm/dune/uggrid_refinement_rules.h); *without repair* counts the inverted elements with UG's "
                 "vertices at phi, before the repair.\n")
    lines.append("| level | tets (flat / phi) | unknowns flat | J flat | error flat | J phi | error phi | volume error flat | volume error phi "
                 "| inverted phi (without repair) | held back | min dihedral flat / phi (deg) | CG iterations phi |")
    lines.append("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for a, b in zip(runs["flat"]["levels"], runs["phi"]["levels"]):
        tets = str(a["tets"]) if a["tets"] == b["tets"] else f"{a['tets']} / {b['tets']}"
        lines.append(f"| {a['level']} | {tets} | {a['unknowns']} | {a['J']:.6g} | {abs(a['J'] - j_ref) / j_ref:.2%} "
                     f"| {b['J']:.6g} | {abs(b['J'] - j_ref) / j_ref:.2%} "
                     f"| {abs(a['volume'] - v_orig) / v_orig:.3%} | {abs(b['volume'] - v_orig) / v_orig:.3%} "
                     f"| {b['inverted']} ({b['inverted_before_repair']}) | {b['held_back']} "
                     f"| {a['min_dihedral_degrees']:.3g} / {b['min_dihedral_degrees']:.3g} | {b['cg_iterations']} |")
    xf, xp = richardson(runs["flat"]["levels"]), richardson(runs["phi"]["levels"])
    lines.append("")
    lines.append(f"Extrapolated from the last two levels: flat {xf:.6g} ({abs(xf - j_ref) / j_ref:.2%} from J_ref), "
                 f"phi {xp:.6g} ({abs(xp - j_ref) / j_ref:.2%}).\n")
    ef = abs(runs["flat"]["levels"][-1]["J"] - j_ref) / j_ref
    ep = abs(runs["phi"]["levels"][-1]["J"] - j_ref) / j_ref
    lines.append(f"At level {args.levels}: error flat / error phi = {ef / ep:.1f}.\n")
    if "cpu_seconds" in runs["flat"] and "cpu_seconds" in runs["phi"]:
        lines.append(f"CPU seconds, levels 0..{args.levels}: flat {runs['flat']['cpu_seconds']:.1f}, "
                     f"phi {runs['phi']['cpu_seconds']:.1f}.\n")
    original = runs["phi"]["original_region_volumes"]
    if len(original) > 1:
        lines += region_table(runs, original)
    adaptive = [name for name in ("adaptive flat", "adaptive phi") if name in runs]
    if not adaptive:
        return finish(args, lines, reference, j_ref, runs)
    lines.append("Adaptive (residual estimator, Dörfler marking of half the estimate, UG red-green refinement "
                 "with the marks of a step applied in one adapt() per level of the elements UG refines, "
                 "bpm/dune/uggrid_adapt.h: *marked* = marks, *adapts* = adapt() calls of the step; the repair "
                 "runs after each; *reset* = vertices of inverted tets the repair put back to their edge "
                 "midpoints first, *held back* = boundary vertices it left short of phi, both summed over the "
                 "step's adapt() calls; s = wall seconds of the step):\n")
    lines.append("| run | step | tets | unknowns | J | error | inverted (without repair) | min dihedral (deg) "
                 "| marked | adapts | reset | held back | s |")
    lines.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name in adaptive:
        for l in runs[name]["levels"]:
            lines.append(f"| {name} | {l['level']} | {l['tets']} | {l['unknowns']} | {l['J']:.6g} "
                         f"| {abs(l['J'] - j_ref) / j_ref:.2%} | {l['inverted']} ({l['inverted_before_repair']}) "
                         f"| {l['min_dihedral_degrees']:.3g} | {l.get('marked', 0)} | {l.get('adapts', 0)} "
                         f"| {l.get('reset', 0)} | {l.get('held_back', 0)} | {l['seconds']:.1f} |")
    flat_last = runs["flat"]["levels"][-1]
    lines.append("")
    for name in adaptive:
        run_ = runs[name]
        if "cpu_seconds" in run_:
            lines.append(f"{name}: {run_['cpu_seconds']:.1f} CPU s, "
                         f"{run_['wall_seconds']:.0f} s wall.\n")
        reached = [l for l in run_["levels"] if abs(l["J"] - j_ref) / j_ref <= flat_final_error]
        if reached:
            l = reached[0]
            verdict = "yes" if l["unknowns"] < flat_last["unknowns"] else "no (more unknowns)"
            lines.append(f"{name} reaches the uniform flat series' final accuracy ({flat_final_error:.2%} at level "
                         f"{flat_last['level']}, {flat_last['unknowns']} unknowns) at step {l['level']}: "
                         f"{abs(l['J'] - j_ref) / j_ref:.2%} with {l['unknowns']} unknowns "
                         f"({flat_last['unknowns'] / l['unknowns']:.1f}x fewer): **{verdict}**.\n")
        else:
            last = run_["levels"][-1]
            lines.append(f"{name} does not reach the uniform flat series' final accuracy ({flat_final_error:.2%}) "
                         f"within {last['level']} steps (last {abs(last['J'] - j_ref) / j_ref:.2%} with "
                         f"{last['unknowns']} unknowns).\n")
    finish(args, lines, reference, j_ref, runs)


def region_table(runs, original):
    """Volume error of every region per level, flat and phi (several materials)."""
    names = runs["phi"].get("region_names") or [f"region {r + 1}" for r in range(len(original))]
    lines = [f"Volume of every region (regions of bpm-mesh; original volumes {', '.join(f'{n} {v:.6g}' for n, v in zip(names, original))}: "
             "enclosed by that region's original surfaces). Signed relative errors; the interface between regions "
             "is moved towards phi like the boundary (bpm-torsion's default):\n"]
    header = "| level | " + " | ".join(f"{n} flat | {n} phi" for n in names) + " | inverted flat / phi |"
    lines.append(header)
    lines.append("|---:|" + "---:|" * (2 * len(names) + 1))
    for a, b in zip(runs["flat"]["levels"], runs["phi"]["levels"]):
        cells = []
        for r, v in enumerate(original):
            cells.append(f"{(a['region_volumes'][r] - v) / v:+.3%}")
            cells.append(f"{(b['region_volumes'][r] - v) / v:+.3%}")
        lines.append(f"| {a['level']} | " + " | ".join(cells) + f" | {a['inverted']} / {b['inverted']} |")
    lines.append("")
    for r, (n, v) in enumerate(zip(names, original)):
        e = [abs(l["region_volumes"][r] - v) / v for l in runs["phi"]["levels"]]
        falls = all(y < x for x, y in zip(e, e[1:]))
        lines.append(f"{n}: phi volume error {' -> '.join(f'{x:.3%}' for x in e)}: "
                     f"{'falls at every level' if falls else '**does not fall at every level**'}.\n")
    return lines


def finish(args, lines, reference, j_ref, runs):
    text = "\n".join(lines) + "\n"
    name = args.results_name or args.mesh
    with open(os.path.join(args.results_dir, f"dune_torsion-{name}.md"), "w") as f:
        f.write(text)
    with open(os.path.join(args.results_dir, f"dune_torsion-{name}.json"), "w") as f:
        json.dump({"reference": reference, "j_ref": j_ref, "runs": runs}, f, indent=1)
    print(text)


if __name__ == "__main__":
    main()
