"""The chalk's wait (`python -m benchmarks.speed --chalk`): `python simulator.py --scene chalk --no-frames`
as a student runs it, pushed and dragged, with Newton starting at x_tilde (the chalk's default) and at
x^n (the lecture's, `--newton-start x_n`), whole processes run alternately.

For each run: the process's wall and CPU time (import, stepping, log, plots.png, summary.png), the
stepping's own wall time as the closing line prints it, the wall time per simulated second against
the target (issue 28: at most CHALK_TARGET s for the 3 s default), and Newton iterations per step from
log.csv. The figures to read are the CPU medians on a busy machine, the wall medians on a quiet one.

`pythons`: the interpreters that run the processes (`--python EXE,EXE`; default the benchmark's own), in
turn with the runs: one machine can have a Python built for speed (a distribution's or python.org's, as
students install) beside one built from source without it (pyenv's default), and the wait differs.
"""
import csv
import math
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile
import time

from benchmarks import tables

try:
    import resource         # POSIX: the CPU time of finished child processes
except ImportError:         # Windows: no such figure, the CPU column is nan
    resource = None

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

CHALK_TARGET = 3.0      # s of wall time per simulated second, the 3 s default with --no-frames (issue 28)
RUNS = {"pushed": [], "dragged": ["--drag"], "pushed, from x^n": ["--newton-start", "x_n"],
        "dragged, from x^n": ["--drag", "--newton-start", "x_n"]}
COLUMNS = ["python", "run", "simulated_s", "wall_s", "cpu_s", "stepping_wall_s", "wall_per_simulated_s",
           "newton_per_step", "noise"]


def children_cpu():
    """CPU seconds (user + system) of the finished child processes so far (nan without `resource`)."""
    if resource is None:
        return math.nan
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def python_version(python):
    """The version ("3.11.2") of the interpreter at the path `python`, which must import the project's
    requirements; ValueError naming --python where it cannot."""
    try:
        done = subprocess.run([python, "-c", "import numpy, scipy, pygame, platform; print(platform.python_version())"],
                              capture_output=True, text=True, timeout=300,
                              env={**os.environ, "SDL_VIDEODRIVER": "dummy"})
    except (OSError, subprocess.TimeoutExpired) as err:
        raise ValueError(f"--python {python!r} could not be run ({getattr(err, 'strerror', None) or err})") from None
    if done.returncode != 0:
        raise ValueError(f"--python {python!r} cannot import numpy, scipy and pygame (install requirements.txt "
                         "into it)")
    return done.stdout.split()[-1]


def run_once(folder, name, extra, duration, python=sys.executable):
    """One `python simulator.py --scene chalk --no-frames` process of the interpreter `python`: (wall s,
    CPU s, the stepping's wall s from its closing line, Newton iterations per step and the simulated
    seconds from its log.csv)."""
    out = tempfile.mkdtemp(prefix=re.sub(r"\W+", "_", name) + "-", dir=folder)    # a new folder each run
    command = [python, os.path.join(ROOT, "simulator.py"), "--scene", "chalk", "--no-frames", "--out", out,
               *extra] + (["--duration", str(duration)] if duration is not None else [])
    cpu, start = children_cpu(), time.perf_counter()
    done = subprocess.run(command, cwd=ROOT, capture_output=True, text=True,
                          env={**os.environ, "SDL_VIDEODRIVER": "dummy", "OPENBLAS_NUM_THREADS": "1"})
    wall, cpu = time.perf_counter() - start, children_cpu() - cpu
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed:\n{done.stderr}")
    stepping = float(re.search(r"in ([0-9.]+) s wall", done.stderr).group(1))
    with open(os.path.join(out, "log.csv")) as f:
        rows = list(csv.DictReader(f))[1:]         # the steps (row 0 is t = 0)
    return wall, cpu, stepping, statistics.mean(int(r["newton_iterations"]) for r in rows), float(rows[-1]["t"])


def chalk_table(repeats=3, duration=None, runs=RUNS, pythons=None):
    """The rows: for each interpreter of `pythons`, {its path: its version} (python_version; None: this
    one), and each of `runs` the medians over `repeats` processes, all taken in turn. A row's "python" is
    the interpreter's version and path."""
    pythons = pythons or {sys.executable: platform.python_version()}
    labels = {python: f"{version} {python}" for python, version in pythons.items()}
    times = {(python, name): [] for python in pythons for name in runs}
    with tempfile.TemporaryDirectory(prefix="chalk-speed-") as folder:
        for _ in range(repeats):
            for python, name in times:
                times[python, name].append(run_once(folder, name, runs[name], duration, python))
    rows = []
    for (python, name), results in times.items():
        walls, cpus, steppings, newton, simulated = zip(*results)
        wall = statistics.median(walls)
        rows.append({"python": labels[python], "run": name, "simulated_s": simulated[0], "wall_s": wall,
                     "cpu_s": statistics.median(cpus), "stepping_wall_s": statistics.median(steppings),
                     "wall_per_simulated_s": wall / simulated[0], "newton_per_step": newton[0],
                     "noise": tables.noise(walls, cpus)})
    return rows


def format_chalk_table(rows, repeats):
    head = ["python", "run", "simulated s", "wall s", "CPU s", "stepping wall s", "wall / simulated s", "Newton/step",
            "noise"]
    cells = [head] + [[r["python"], r["run"], f"{r['simulated_s']:g}", f"{r['wall_s']:.2f}", f"{r['cpu_s']:.2f}",
                       f"{r['stepping_wall_s']:.2f}", f"{r['wall_per_simulated_s']:.2f}", f"{r['newton_per_step']:.2f}",
                       r["noise"]] for r in rows]
    defaults = [r for r in rows if r["run"] == rows[0]["run"]]          # the pushed default, per interpreter
    if rows[0]["simulated_s"] == 3.0:
        verdict = "; ".join(f"{'met' if r['wall_per_simulated_s'] <= CHALK_TARGET else 'NOT met'} with Python "
                            f"{r['python'].split()[0]} ({r['wall_per_simulated_s']:.2f} s)" for r in defaults)
    else:
        verdict = "not judged: a short run's start-up weighs more per simulated second"
    return "\n".join(tables.aligned(cells) + [
        "python simulator.py --scene chalk --no-frames [flags]: whole processes (import, steps, log.csv, plots.png,",
        f"summary.png), medians of {repeats} run alternately; stepping wall: the closing line's figure. Target for",
        f"the pushed 3 s default: at most {CHALK_TARGET:g} s of wall time per simulated second: {verdict}."])


def print_chalk_table(repeats, duration=None, pythons=None):
    rows = chalk_table(repeats, duration, pythons=pythons)
    print(format_chalk_table(rows, repeats))
    return rows
