"""README.md's section "Using bpm from a solver" shows the consumer tests' own code: every
region between README-BEGIN and README-END markers in the files below must appear in
README.md verbatim (dedented), so that a change to a test that the README does not follow
(or the other way round) fails here.

usage: check_readme.py SOURCE_DIR
"""
import sys
import textwrap
from pathlib import Path

FILES = ["tests/consumer/CMakeLists.txt", "tests/consumer/consumer.cpp", "tests/consumer/run.sh",
         "tests/python/module/test_module.py"]


def regions(text):
    out, current = [], None
    for line in text.splitlines():
        if "README-BEGIN" in line:
            current = []
        elif "README-END" in line:
            out.append(textwrap.dedent("\n".join(current)).strip("\n"))
            current = None
        elif current is not None:
            current.append(line)
    return out


def main():
    source = Path(sys.argv[1])
    readme = (source / "README.md").read_text()
    failures = 0
    for name in FILES:
        found = regions((source / name).read_text())
        if not found:
            print(f"FAIL: {name} has no README-BEGIN/README-END region")
            failures += 1
        for region in found:
            if region not in readme:
                print(f"FAIL: README.md does not show this region of {name} verbatim:\n{region}\n")
                failures += 1
    print(f"{len(FILES)} files checked, {failures} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
