"""spec/info-report.md's examples are what bpm-info prints today, line for line: the text
example (`bpm-info eight.bpm --distortion`), the JSON example (`bpm-info two_cubes.tet.bpm
--json`) and the JSON error report (`bpm-info missing.bpm --json`). The example files are made
here by the commands their provenance names, run by bare name from the work directory as the
spec shows them. The examples still said "bpm format 1.3" after writers moved to format 2.0:
nothing compared them with the tool. On a difference this prints the fresh output (also left in
WORK/info_report_examples/) to paste into the spec."""
import argparse
import difflib
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def fenced_block(text, heading, lang=""):
    """The first ``` block (with the language tag `lang`) after the line `heading`."""
    section = text.split("\n" + heading + "\n", 1)[1]
    return section.split("```" + lang + "\n", 1)[1].split("```", 1)[0]


def write_stl_cubes(work):
    """A.stl = [0,1]^3 and B.stl = [1,2]x[0,1]^2 (tests/cli/lib/two_cubes.py's cubes, one
    ASCII STL file per material, sharing the square x = 1)."""
    subprocess.run([sys.executable, os.path.join(HERE, "..", "cli", "lib", "two_cubes.py"), work], check=True)
    for off, stl in (("left", "A"), ("right", "B")):
        with open(os.path.join(work, off + ".off")) as f:
            lines = f.read().split("\n")
        nv, nt = map(int, lines[1].split()[:2])
        points = [lines[2 + i] for i in range(nv)]
        with open(os.path.join(work, stl + ".stl"), "w") as f:
            f.write("solid %s\n" % stl)
            for t in range(nt):
                f.write("  facet normal 0 0 0\n    outer loop\n")
                for v in map(int, lines[2 + nv + t].split()[1:4]):
                    f.write("      vertex %s\n" % points[v])
                f.write("    endloop\n  endfacet\n")
            f.write("endsolid %s\n" % stl)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tools", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--meshes", required=True)
    ap.add_argument("--work", required=True)
    args = ap.parse_args()
    work = os.path.join(args.work, "info_report_examples")
    os.makedirs(work, exist_ok=True)
    # Bare tool names, as the provenance in the examples shows them.
    env = dict(os.environ, PATH=os.path.abspath(args.tools) + os.pathsep + os.environ.get("PATH", ""))

    def run(*command, expect=0):
        r = subprocess.run(list(command), cwd=work, env=env, capture_output=True, text=True)
        if r.returncode != expect:
            sys.exit("%s: exit %d (expected %d)\n%s" % (" ".join(command), r.returncode, expect, r.stderr))
        return r.stdout

    eight = os.path.join(work, "eight.off")
    if os.path.lexists(eight):
        os.remove(eight)
    os.symlink(os.path.abspath(os.path.join(args.meshes, "eight.off")), eight)
    run("bpm-simplify", "eight.off", "-o", "eight.bpm", "--ratio", "0.5", "--units", "mm", "--record-steps",
        "--deterministic", "-q")
    write_stl_cubes(work)
    run("bpm-simplify", "A.stl", "B.stl", "-o", "two_cubes.bpm", "--merge-duplicate-vertices",
        "--merge-duplicate-triangles", "--ratio", "1", "--deterministic", "-q")
    run("bpm-mesh", "two_cubes.bpm", "-o", "two_cubes.tet.bpm", "--deterministic", "-q")

    with open(os.path.join(args.source, "spec", "info-report.md")) as f:
        spec = f.read()
    examples = [
        ("the text example", fenced_block(spec, "## Text"), run("bpm-info", "eight.bpm", "--distortion")),
        ("the JSON example", fenced_block(spec, "## JSON (`--json`)", "json"),
         run("bpm-info", "two_cubes.tet.bpm", "--json")),
        ("the JSON error example", fenced_block(spec, "### Errors", "json"),
         run("bpm-info", "missing.bpm", "--json", expect=3)),
    ]
    failures = 0
    for i, (name, documented, printed) in enumerate(examples):
        with open(os.path.join(work, "example%d.txt" % i), "w") as f:
            f.write(printed)
        if documented != printed:
            failures += 1
            print("FAIL: spec/info-report.md's %s is not what bpm-info prints:" % name)
            sys.stdout.writelines(difflib.unified_diff(documented.splitlines(True), printed.splitlines(True),
                                                       "spec/info-report.md", "bpm-info"))
    print("test_info_report_examples: %s" % ("ok" if not failures else "FAILED (%d of %d examples)"
                                             % (failures, len(examples))))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
