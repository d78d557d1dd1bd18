"""What the VTK tests of tests/python share: their command line (tests/CMakeLists.txt
passes --tools, --source, --meshes and --work to every Python test), the check that
Debian's python3-vtk9 is importable, and the per-file report."""
import argparse
import importlib
import os


def parse_args():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tools", required=True, help="directory of the bpm executables")
    ap.add_argument("--source", required=True, help="the repository")
    ap.add_argument("--meshes", help="the real meshes (.data/meshes)")
    ap.add_argument("--work", required=True, help="a directory for the test's files")
    return ap.parse_args()


def vtk_missing(test, module):
    """None if `module` imports; else the failure line for `test` (printed by the caller)."""
    try:
        importlib.import_module(module)
    except ImportError as e:
        return "%s: FAILED, cannot import %s (python3-vtk9): %s" % (test, module, e)
    return None


def work_dir(args, name):
    work = os.path.join(args.work, name)
    os.makedirs(work, exist_ok=True)
    return work


def report(files, check):
    """Runs check(path) -> list of problems for every file, prints ok / FAILED and the
    problems per file; returns how many files failed."""
    failed = 0
    for path in files:
        problems = check(path)
        print("%s: %s" % (os.path.basename(path), "ok" if not problems else "FAILED"))
        for p in problems:
            print("  " + p)
        failed += bool(problems)
    return failed
