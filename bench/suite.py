"""The frame the per-mesh suites bench/refine.py and bench/adaptive.py share (bench/README.md).

Both run a fixed set of tools on every mesh of .data/meshes at two coarse sizes, time every
command under /usr/bin/time, and rewrite RESULTS_DIR/NAME.md and NAME.json after every mesh.
What they have in common lives here: the command line every suite takes, the checks of its
inputs, the Release build of the tools it needs, the machine header of the report and the timed
command runner. What each suite measures and how it writes its tables stays in its own file.
"""
import datetime
import json
import os
import shlex
import subprocess
import sys
import time

from run import MESHES, RESULTS, ROOT, cpu_model, git_commit, load_average, memory_gib, rel, timed, utcnow

PYTHON = "/usr/bin/python3"
DEFAULT_MESHES = ["femur", "fandisk", "elephant", "armadillo", "mech-holes-shark"]
# The two coarse sizes of every row: (label in the tables, file tag, bpm-simplify options).
TARGETS = [("10%", "r10", ["--ratio", "0.1"]), ("1000 V", "v1000", ["--vertices", "1000"])]


class Suite:
    """One suite's name (its log prefix and results file stem) and the tools it builds."""

    def __init__(self, name, build_targets):
        self.name, self.build_targets = name, build_targets

    def log(self, msg):
        sys.stderr.write(f"[{utcnow():%H:%M:%S}] {self.name}.py: {msg}\n")
        sys.stderr.flush()

    def add_arguments(self, ap):
        """The options every suite takes; the suite adds its own after them."""
        ap.add_argument("--build-dir", default=os.path.join(ROOT, "build-bench"))
        ap.add_argument("--no-build", action="store_true", help="use the binaries already in BUILD_DIR/bin")
        ap.add_argument("--jobs", type=int, default=2)
        ap.add_argument("--results-dir", default=RESULTS,
                        help=f"where {self.name}.md / {self.name}.json go (default bench/results)")
        ap.add_argument("--work-dir", help=f"scratch files (default BUILD_DIR/bench-work/{self.name})")
        ap.add_argument("--meshes", default=",".join(DEFAULT_MESHES), help="comma-separated names in .data/meshes")
        ap.add_argument("--timeout", type=int, default=1800, help="seconds per command")

    def add_target_argument(self, ap):
        """--targets: which of TARGETS (the coarse sizes) a per-row suite runs."""
        ap.add_argument("--targets", default=",".join(t[1] for t in TARGETS),
                        help="coarse sizes: " + ", ".join(f"{t[1]} ({t[0]})" for t in TARGETS).replace("%", "%%"))

    def targets(self, args):
        """The (label, tag, bpm-simplify options) of TARGETS that --targets names, in TARGETS' order;
        exits with an error naming a tag that is not one of them (rather than run nothing)."""
        asked = [t for t in args.targets.split(",") if t]
        unknown = [t for t in asked if t not in [x[1] for x in TARGETS]]
        if unknown or not asked:
            sys.exit(f"{self.name}.py: error: --targets {args.targets!r}: use one or more of "
                     f"{', '.join(t[1] for t in TARGETS)}")
        return [t for t in TARGETS if t[1] in asked]

    def prepare(self, args):
        """Absolute directories, the mesh list, and an error naming every mesh that is missing."""
        args.build_dir = os.path.abspath(args.build_dir)
        args.results_dir = os.path.abspath(args.results_dir)
        args.work_dir = os.path.abspath(args.work_dir or os.path.join(args.build_dir, "bench-work", self.name))
        args.meshes = [m for m in args.meshes.split(",") if m]
        missing = [m for m in args.meshes if not os.path.exists(os.path.join(MESHES, m + ".off"))]
        if missing:
            sys.exit(f"{self.name}.py: error: not in {rel(MESHES)}: {', '.join(m + '.off' for m in missing)} "
                     "(scripts/setup.sh unpacks them)")
        os.makedirs(args.work_dir, exist_ok=True)
        os.makedirs(args.results_dir, exist_ok=True)

    def header(self, args, argv):
        """The report's header: when, on what machine, at which commit, how it was invoked."""
        return {"started": f"{utcnow():%Y-%m-%d %H:%M}", "load_start": list(load_average()), "cpu": cpu_model(),
                "cores": os.cpu_count(), "memory_gib": memory_gib(), "commit": git_commit(),
                "invocation": shlex.join([PYTHON, f"bench/{self.name}.py"] + argv), "build_dir": args.build_dir}

    def finish_header(self, header, t_start):
        header["finished"] = f"{utcnow():%Y-%m-%d %H:%M}"
        header["minutes"] = (time.monotonic() - t_start) / 60.0
        header["load_end"] = list(load_average())

    def build(self, args):
        """The suite's tools in Release in BUILD_DIR (None with --no-build); the commands it ran.
        Unlike run.py's build it leaves BPM_BUILD_TESTS alone, so that pointing --build-dir at a
        developer's build does not switch its tests off."""
        if args.no_build:
            return None
        configure = ["cmake", "-S", ROOT, "-B", args.build_dir, "-DCMAKE_BUILD_TYPE=Release"]
        compile_ = ["cmake", "--build", args.build_dir, f"-j{args.jobs}", "--target"] + self.build_targets
        self.log(f"building in {args.build_dir} (Release): {' '.join(self.build_targets)}")
        subprocess.run(configure, check=True, stdout=subprocess.DEVNULL)
        subprocess.run(compile_, check=True, stdout=subprocess.DEVNULL)
        return [configure, compile_]

    def binaries(self, args):
        """{tool: path} of the built tools; exits with an error naming the first one missing."""
        bins = {t: os.path.join(args.build_dir, "bin", t) for t in self.build_targets}
        for p in bins.values():
            if not os.access(p, os.X_OK):
                sys.exit(f"{self.name}.py: error: {p} missing (build first, or leave out --no-build)")
        return bins

    def runner(self, args):
        return Runner(args.work_dir, args.timeout, self.log)


class Runner:
    """Runs commands from the repository root under `timeout` and /usr/bin/time; records every command."""

    def __init__(self, work, timeout, log):
        self.work, self.timeout, self.log, self.commands = work, timeout, log, []

    def run(self, cmd, stem, stdout_path=None):
        """run.timed's result plus the command as shown, its log and the log's last lines."""
        logs = os.path.join(self.work, "logs")
        os.makedirs(logs, exist_ok=True)
        log_path = os.path.join(logs, stem + ".log")
        shown = shlex.join(rel(c) if os.path.isabs(c) else c for c in cmd)
        if stdout_path:
            shown += " > " + rel(stdout_path)
        self.commands.append(shown)
        self.log(shown)
        r = timed(cmd, log_path, self.timeout, cwd=ROOT, stdout_path=stdout_path)
        r.update({"command": shown, "log": log_path})
        if r["status"] != "ok":
            self.log(f"  -> {r['status']}: {r['message']}")
        with open(log_path, errors="replace") as lf:
            r["stderr_tail"] = [l.rstrip() for l in lf.read().splitlines()[1:] if l.strip()][-12:]
        return r


def load_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, json.JSONDecodeError):
        return None


def stamp(t):
    return f"{datetime.datetime.fromtimestamp(t, datetime.timezone.utc):%Y-%m-%d %H:%M:%S} UTC"
