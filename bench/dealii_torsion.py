#!/usr/bin/env python3
"""The paper's §3 experiment with deal.II: the torsion problem -Δu = 1, u = 0 on the boundary,
J = ∫u, on bpm-mesh meshes refined globally through the deal.II adapter (bpm/dealii/), with phi
(and the boundary repair) and flat, against a reference from a mesh of the original surface.

    bench/dealii_torsion.py [--no-build] [--build-dir build-bench] [--results-dir bench/results]
                            [--meshes femur] [--ratio 0.1] [--levels 3] [--reference-levels 2]

Builds bpm-dealii-torsion against deal.II's Release library in BUILD_DIR-dealii (also with
--no-build when it is not there: the main bench build does not include deal.II programs) and
writes RESULTS_DIR/dealii-torsion.md and .json. Skips (exit 0, a note in the .md) when deal.II
is not installed (Debian libdeal.ii-dev).

Reference J: the original surface itself (bpm-simplify --ratio 1, phi = identity), meshed by
bpm-mesh and refined (flat = phi there) to --reference-levels, extrapolated from its last three
levels (Aitken's delta-squared: J_inf = J2 - (J2 - J1)^2 / ((J2 - J1) - (J1 - J0))).
"""
import argparse
import json
import os
import platform
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEALII_CONFIG = "/usr/share/cmake/deal.II/deal.IIConfig.cmake"


def run(cmd, **kw):
    t0 = time.monotonic()
    p = subprocess.run(cmd, check=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)
    return p.stdout, time.monotonic() - t0


def aitken(j):
    if len(j) < 3 or any(x is None for x in j[-3:]):
        return None
    j0, j1, j2 = j[-3:]
    d1, d2 = j1 - j0, j2 - j1
    if d2 == d1:
        return None
    return j2 - d2 * d2 / (d2 - d1)


def torsion(exe, mesh, levels, *flags):
    out, seconds = run([exe, mesh, "--levels", str(levels), "--json", *flags])
    data = json.loads(out)
    data["wall_seconds"] = seconds
    return data


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--no-build", action="store_true", help="do not rebuild when the binaries exist")
    ap.add_argument("--build-dir", default="build-bench", help="the deal.II build goes to BUILD_DIR-dealii")
    ap.add_argument("--results-dir", default=os.path.join(ROOT, "bench", "results"))
    ap.add_argument("--work-dir", default=None)
    ap.add_argument("--meshes", default="femur")
    ap.add_argument("--ratio", type=float, default=0.1)
    ap.add_argument("--levels", type=int, default=3)
    ap.add_argument("--reference-levels", type=int, default=2)
    args = ap.parse_args()

    os.makedirs(args.results_dir, exist_ok=True)
    md_path = os.path.join(args.results_dir, "dealii-torsion.md")
    title = "# Solvers: deal.II torsion (bench/dealii_torsion.py)"
    if not os.path.exists(DEALII_CONFIG):
        open(md_path, "w").write(f"{title}\n\nSkipped: deal.II is not installed ({DEALII_CONFIG}; Debian libdeal.ii-dev).\n")
        return 0
    build = os.path.abspath(args.build_dir.rstrip("/") + "-dealii")
    work = os.path.abspath(args.work_dir or os.path.join(build, "bench-work", "dealii-torsion"))
    os.makedirs(work, exist_ok=True)
    exe = os.path.join(build, "bin", "bpm-dealii-torsion")
    tools = [os.path.join(build, "bin", t) for t in ("bpm-simplify", "bpm-mesh")]
    if not args.no_build or not all(os.path.exists(x) for x in [exe] + tools):
        launcher = []
        if os.environ.get("CCACHE_DIR") and shutil.which("ccache"):  # a shared compiler cache, when one is set up
            launcher = ["-DCMAKE_CXX_COMPILER_LAUNCHER=ccache", "-DCMAKE_C_COMPILER_LAUNCHER=ccache"]
        run(["cmake", "-S", ROOT, "-B", build, "-DCMAKE_BUILD_TYPE=Release", "-DBPM_WITH_DEALII=ON",
             "-DBPM_DEALII_BUILD_TYPE=Release", "-DBPM_BUILD_TESTS=OFF", "-DBPM_BUILD_BENCH=OFF"] + launcher)
        run(["cmake", "--build", build, "-j", "2", "--target", "bpm-simplify", "bpm-mesh"])
        run(["cmake", "--build", build, "-j", "1", "--target", "bpm-dealii-torsion"])  # 1.7 GB per deal.II job
    simplify, mesh_tool = tools

    started = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
    load0 = os.getloadavg()
    results = {}
    for name in args.meshes.split(","):
        src = os.path.join(ROOT, ".data", "meshes", name + ".off")
        r = {}
        coarse = os.path.join(work, f"{name}.bpm")
        tet = os.path.join(work, f"{name}.tet.bpm")
        run([simplify, src, "-o", coarse, "--ratio", str(args.ratio), "--deterministic", "-q"])
        report, _ = run([mesh_tool, coarse, "-o", tet, "-q", "--json"])
        # The volume enclosed by the original surface (per region, summed): the volume target.
        r["original_volume"] = sum(g["original_volume"] for g in json.loads(report)["regions"])
        r["phi"] = torsion(exe, tet, args.levels)
        r["flat"] = torsion(exe, tet, args.levels, "--flat")
        r["no_repair"] = torsion(exe, tet, min(args.levels, 2), "--no-repair")
        s0 = os.path.join(work, f"{name}.s0.bpm")
        s0tet = os.path.join(work, f"{name}.s0.tet.bpm")
        run([simplify, src, "-o", s0, "--ratio", "1", "--deterministic", "-q"])
        run([mesh_tool, s0, "-o", s0tet, "-q"])
        r["s0"] = torsion(exe, s0tet, args.reference_levels, "--flat")
        r["J_ref"] = aitken([l["J"] for l in r["s0"]["levels"]])
        r["J_phi_extrapolated"] = aitken([l["J"] for l in r["phi"]["levels"]])
        r["J_flat_extrapolated"] = aitken([l["J"] for l in r["flat"]["levels"]])
        results[name] = r
    load1 = os.getloadavg()
    json.dump({"started": started, "ratio": args.ratio, "levels": args.levels, "meshes": results},
              open(os.path.join(args.results_dir, "dealii-torsion.json"), "w"), indent=1)

    def e(x):
        return "" if x is None else f"{x:.4e}"

    out = [title, "",
           f"Started {started} on {os.cpu_count()} cores ({platform.machine()}), load average "
           f"{load0[0]:.2f} at the start and {load1[0]:.2f} at the end. bpm-dealii-torsion (examples/dealii) built "
           f"against deal.II's Release library; P1 (FE_SimplexP<3>(1), QGaussSimplex<3>(2), MappingFE), CG with SSOR "
           f"(relative residual 1e-12). Inputs: `bpm-simplify --ratio {args.ratio} --deterministic`, `bpm-mesh` "
           f"(TetGen -pYzA -q1.414), then deal.II's global refinement through the adapter: **phi** puts new points on "
           f"S at their edge midpoints, and the repair (bpm::repair_boundary) moves them towards phi as far as no cell "
           f"inverts and smooths the interior; **flat** keeps the midpoints; **no repair** lets PhiManifold put them "
           f"at phi directly. Reference J_ref: the original surface meshed by bpm-mesh (phi = identity) and refined "
           f"to level {args.reference_levels}, extrapolated by Aitken's delta-squared from its last three levels.", ""]
    for name, r in results.items():
        ref = r["J_ref"]
        out += [f"## {name} at {args.ratio:.0%}", "",
                f"J_ref = {e(ref)} (mesh of S0, levels {', '.join(e(l['J']) for l in r['s0']['levels'])}; "
                f"{r['s0']['levels'][0]['cells']} cells at level 0). Extrapolated from the last three levels: "
                f"phi {e(r['J_phi_extrapolated'])}, flat {e(r['J_flat_extrapolated'])}.", "",
                "| level | cells | J flat | error flat | J phi | error phi | flat / phi error | inverted phi | "
                "inverted, no repair at all | inverted at phi before repair | held back | min dihedral phi | "
                "min dihedral flat | volume error phi | volume error flat | s phi | s flat |",
                "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        nr = {l["level"]: l for l in r["no_repair"]["levels"]}
        for lp, lf in zip(r["phi"]["levels"], r["flat"]["levels"]):
            ep = (lp["J"] - ref) / ref if ref and lp["J"] is not None else None
            ef = (lf["J"] - ref) / ref if ref and lf["J"] is not None else None
            ratio = f"{abs(ef) / abs(ep):.1f}x" if ep and ef else ""
            k = lp["level"]
            without = nr[k]["inverted"] if k in nr else ""
            v0 = r["original_volume"]
            out.append(f"| {k} | {lp['cells']} | {e(lf['J'])} | {ef:+.3e} | {e(lp['J'])} | {ep:+.3e} | {ratio} | "
                       f"{lp['inverted']} | {without} | {lp['inverted_without_repair']} | {lp['held_back']} | "
                       f"{lp['min_dihedral_degrees']:.3f} | {lf['min_dihedral_degrees']:.3f} | "
                       f"{(lp['volume'] - v0) / v0:+.3e} | {(lf['volume'] - v0) / v0:+.3e} | "
                       f"{lp['seconds']:.1f} | {lf['seconds']:.1f} |")
        errs_p = [abs(l["J"] - ref) for l in r["phi"]["levels"]]
        errs_f = [abs(l["J"] - ref) for l in r["flat"]["levels"]]
        falls = all(b < a for a, b in zip(errs_p, errs_p[1:]))
        inv = max(l["inverted"] for l in r["phi"]["levels"] + r["flat"]["levels"])
        out += ["", f"Targets: phi error falls at every level: **{'yes' if falls else 'no'}**; at K = {args.levels} "
                f"flat error / phi error = **{errs_f[-1] / errs_p[-1]:.1f}x** (target >= 4x); inverted cells at any "
                f"level, phi and flat: **{inv}** (target 0).", "",
                f"Columns: *inverted, no repair at all* is deal.II's refinement through PhiManifold alone, every level "
                f"from the unrepaired one before (a run with --no-repair, levels 0..{min(args.levels, 2)}; J is not "
                f"computed on an inverted mesh); *inverted at phi before repair* counts the cells that would be "
                f"inverted if this level's boundary vertices all sat at phi, from the repaired level before; *held "
                f"back*: boundary vertices the repair left short of phi; volume error: meshed volume against the "
                f"volume enclosed by the original surface ({r['original_volume']:.6g}); s: wall seconds of the level "
                f"(refinement, repair, assembly, solve).", ""]
    open(md_path, "w").write("\n".join(out))
    print("\n".join(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
