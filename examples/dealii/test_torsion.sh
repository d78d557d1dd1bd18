#!/usr/bin/env bash
# The deal.II adapter in a Debug deal.II build (libdeal.ii.g: assertions on), on a real
# mesh: femur simplified to 10 % (390 vertices; 528 tet-mesh vertices, 2048 tets),
# bpm-dealii-torsion with global refinement to K = 2, with phi and --flat.
# Asserts: no inverted cell at any level with phi (the repair) or flat; the phi series of
# J = ∫u approaches the femur's torsion constant at every level and ends closer to it than
# the flat series (which converges to the coarse surface's domain, about 5 % below);
# refinement through phi without the repair does invert cells (what the repair is for);
# --adaptive (local refinement) is refused with the adapter's message.
# Usage: test_torsion.sh TOOL_DIR SOURCE_DIR WORK_DIR
set -u
tools=$1
src=$2
work=$3
rm -rf "$work"
mkdir -p "$work"
source "$src/tests/cli/lib/harness.bash"
femur=$src/.data/meshes/femur.off
if [ ! -f "$femur" ] || ! command -v tetgen >/dev/null; then
    echo "skipped: needs $femur and tetgen (scripts/setup.sh installs both)"
    exit 1
fi
expect 0 "simplify femur to 10 %" -- "$tools/bpm-simplify" "$femur" -o "$work/f.bpm" --ratio 0.1 -q
expect 0 "mesh it" -- "$tools/bpm-mesh" "$work/f.bpm" -o "$work/f.tet.bpm" -q
expect 0 "torsion with phi, K = 2" -- "$tools/bpm-dealii-torsion" "$work/f.tet.bpm" --levels 2 --json
cp "$work/out" "$work/phi.json"
expect 0 "torsion flat, K = 2" -- "$tools/bpm-dealii-torsion" "$work/f.tet.bpm" --levels 2 --flat --json
cp "$work/out" "$work/flat.json"
expect 0 "torsion with phi and no repair, K = 1" -- "$tools/bpm-dealii-torsion" "$work/f.tet.bpm" --levels 1 --no-repair --json
cp "$work/out" "$work/norepair.json"
# Local refinement (what --adaptive asks for) is refused by the adapter, with a message.
expect 2 "adaptive refinement refused" -- "$tools/bpm-dealii-torsion" "$work/f.tet.bpm" --levels 1 --adaptive --json
contains "$work/err" "refines tetrahedral meshes only globally" "the refusal says why"
# J of the original femur's domain (femur.off of libcgal-demo), measured by
# bench/dealii_torsion.py (bench/RESULTS.md, "Solvers: deal.II torsion"): a bpm-mesh mesh of
# the original surface refined to level 2, Aitken-extrapolated: 1.3543e-5; the phi series on
# femur 10 % extrapolates to 1.3598e-5 and the trial in the issue got 1.3622e-5. The
# assertions below hold for any J_ref in that range (at K = 2 the phi error is about 4 %, the
# flat one about 10 %).
ok "phi approaches J_ref at every level and beats flat; no inverted cell" -- /usr/bin/python3 -c '
import json, sys
phi, flat, norepair = (json.load(open(f)) for f in sys.argv[1:4])
J_ref = 1.3543e-5
for series in (phi, flat):
    for l in series["levels"]:
        assert l["inverted"] == 0, ("inverted cells", series["mode"], l)
        assert l["phi_fallbacks"] == 0, ("new points without a parameter point", series["mode"], l)
err = lambda s: [abs(l["J"] - J_ref) / J_ref for l in s["levels"]]
ep, ef = err(phi), err(flat)
print("phi errors", ep, "flat errors", ef)
assert all(b < a for a, b in zip(ep, ep[1:])), ("phi error does not fall at every level", ep)
assert ep[-1] < ef[-1] / 2, ("phi does not end much closer to J_ref than flat", ep, ef)
c0 = phi["levels"][0]["cells"]
assert [l["cells"] for l in phi["levels"]] == [c0 * 8**k for k in range(3)], ("not global red refinement", phi)
assert norepair["levels"][1]["inverted"] > 0, ("refinement through phi alone inverted nothing: the test mesh no longer tests the repair", norepair)
assert phi["levels"][1]["inverted_without_repair"] > 0, phi
' "$work/phi.json" "$work/flat.json" "$work/norepair.json"
finish
