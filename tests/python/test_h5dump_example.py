"""The spec's example file: bpm-make-example regenerates it byte for byte, and
`h5dump -H` (hdf5-tools) of it matches the committed spec/examples/two_triangles.h5dump.txt
that the spec quotes."""
import argparse
import os
import subprocess
import sys


def header_dump(path):
    out = subprocess.run(["h5dump", "-H", path], check=True, capture_output=True, text=True).stdout
    lines = out.splitlines()
    lines[0] = 'HDF5 "two_triangles.bpm" {'
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tools", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--meshes")
    ap.add_argument("--work", required=True)
    args = ap.parse_args()
    work = os.path.join(args.work, "h5dump_example")
    os.makedirs(work, exist_ok=True)
    examples = os.path.join(args.source, "spec", "examples")
    committed = os.path.join(examples, "two_triangles.bpm")
    fresh = os.path.join(work, "two_triangles.bpm")
    subprocess.run([os.path.join(args.tools, "bpm-make-example"), "two_triangles", fresh], check=True)
    problems = []
    with open(committed, "rb") as a, open(fresh, "rb") as b:
        if a.read() != b.read():
            problems.append("bpm-make-example two_triangles no longer reproduces %s byte for byte" % committed)
    with open(os.path.join(examples, "two_triangles.h5dump.txt")) as f:
        expected = f.read()
    if header_dump(committed) != expected:
        problems.append("h5dump -H of the example differs from two_triangles.h5dump.txt")
    # The h5py/numpy evaluation code printed in the spec runs and agrees with libbpm.
    with open(os.path.join(args.source, "spec", "bpm-format.md")) as f:
        text = f.read()
    snippet = text.split("```python\n", 1)[1].split("```", 1)[0]
    run = subprocess.run([sys.executable, "-c", snippet], cwd=examples, capture_output=True, text=True)
    if run.returncode != 0:
        problems.append("the spec's Python example fails: " + run.stderr.strip().splitlines()[-1])
    else:
        query = os.path.join(work, "query.txt")
        with open(query, "w") as f:
            f.write("0 0.2 0.3 0.5\n")
        ref = subprocess.run([os.path.join(args.tools, "bpm-eval"), committed, query], check=True,
                             capture_output=True, text=True).stdout.split()
        nums = [float(x) for x in run.stdout.replace("[", " ").replace("]", " ").replace("(", " ")
                .replace(")", " ").replace(",", " ").replace("array", " ").replace("dtype=int32", " ").split()]
        expected = [float(x) for x in ref[:7]]
        if len(nums) != 7 or any(abs(a - b) > 1e-12 for a, b in zip(nums, expected)):
            problems.append("the spec's Python example prints %s, bpm-eval says %s" % (run.stdout.strip(), ref[:7]))
    for p in problems:
        print("  " + p)
    print("test_h5dump_example: %s" % ("ok" if not problems else "FAILED (%d problems)" % len(problems)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
