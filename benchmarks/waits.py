"""What a user waits for: whole `python simulator.py` processes, run in turn (benchmarks.speed).

--frames: the default run against the same run with --no-frames (issue 16: at most FRAMES_TARGET
times). --chalk: the chalk with --no-frames, pushed and dragged, Newton from x_tilde (its default)
and from x^n (`--newton-start x_n`), under each interpreter --python names (issue 28: at most
CHALK_TARGET s of wall time per simulated second for the 3 s default).
"""
import csv
import functools
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile

from benchmarks import ROOT, tables

FRAMES_TARGET = 3.0
CHALK_TARGET = 3.0
RUNS = {"pushed": [], "dragged": ["--drag"], "pushed, from x^n": ["--newton-start", "x_n"],
        "dragged, from x^n": ["--drag", "--newton-start", "x_n"]}
COLUMNS = ["python", "run", "simulated_s", "wall_s", "cpu_s", "stepping_wall_s",
           "wall_per_simulated_s", "newton_per_step", "noise"]
CHALK_NOTE = """\
python simulator.py --scene chalk --no-frames [flags]: whole processes (import, steps, log.csv, \
plots.png,
summary.png), medians of {repeats} run alternately; stepping wall: the closing line's figure. \
Target for
the pushed 3 s default: at most {target:g} s of wall time per simulated second: {verdict}."""


def run_simulator(folder, flags, python=sys.executable):
    """One `python simulator.py *flags` process into a new folder in `folder`: wall and CPU s, the
    stepping's wall s (its closing line), Newton iterations per step and simulated s (log.csv),
    frames written."""
    out = tempfile.mkdtemp(dir=folder)
    command = [python, os.path.join(ROOT, "simulator.py"), "--out", out, *flags]
    wall, cpu, _, stderr = tables.run_process(command)
    with open(os.path.join(out, "log.csv")) as f:
        steps = list(csv.DictReader(f))[1:]         # row 0 is t = 0
    return {"wall": wall, "cpu": cpu,
            "stepping": float(re.search(r"in ([0-9.]+) s wall", stderr).group(1)),
            "newton": statistics.mean(int(r["newton_iterations"]) for r in steps),
            "simulated": float(steps[-1]["t"]),
            "frames": len([f for f in os.listdir(out) if re.fullmatch(r"frame_.*\.png", f)])}


def print_frames_overhead(repeats):
    """The default run with frames and with --no-frames, in turn: medians and their ratio."""
    runs = {"frames": [], "no-frames": ["--no-frames"]}
    with tempfile.TemporaryDirectory(prefix="frames-") as folder:
        done = tables.in_turn({kind: functools.partial(run_simulator, folder, flags)
                               for kind, flags in runs.items()}, repeats)
    with_frames, without = (tables.medians(done[kind])["wall"] for kind in runs)
    ratio, first = with_frames / without, done["frames"][0]
    spread = max(tables.spread([r["wall"] for r in results]) for results in done.values())
    verdict = "met" if ratio <= FRAMES_TARGET else "NOT met"
    print(f"python simulator.py: {with_frames:.2f} s with {first['frames']} frames "
          f"({(first['frames'] - 1) / first['simulated']:.1f} per simulated second), "
          f"{without:.2f} s with --no-frames (whole processes, medians of {repeats}, run "
          f"alternately): {ratio:.2f}x (target <= {FRAMES_TARGET:g}x: {verdict}; repeats spread "
          f"{100 * spread:.0f}%)")
    return 0


def python_version(python):
    """The version ("3.11.2") of the interpreter at the path `python`, which must import the
    requirements; ValueError naming --python where it cannot."""
    code = "import numpy, scipy, pygame, platform; print(platform.python_version())"
    try:
        done = subprocess.run([python, "-c", code], capture_output=True, text=True, timeout=300,
                              env={**os.environ, "SDL_VIDEODRIVER": "dummy"})
    except (OSError, subprocess.TimeoutExpired) as err:
        why = getattr(err, "strerror", None) or err
        raise ValueError(f"--python {python!r} could not be run ({why})") from None
    if done.returncode != 0:
        raise ValueError(f"--python {python!r} cannot import numpy, scipy and pygame (install "
                         "requirements.txt into it)")
    return done.stdout.split()[-1]


def chalk_table(repeats=3, duration=None, runs=RUNS, pythons=None):
    """For each interpreter of `pythons` ({path: version}; None: this one) and each of `runs`, the
    medians over `repeats` processes, all taken in turn; a row's python: its version and path."""
    pythons = pythons or {sys.executable: platform.python_version()}
    seconds = [] if duration is None else ["--duration", str(duration)]
    with tempfile.TemporaryDirectory(prefix="chalk-speed-") as folder:
        jobs = {(python, name): functools.partial(run_simulator, folder, [
                    "--scene", "chalk", "--no-frames", *flags, *seconds], python)
                for python in pythons for name, flags in runs.items()}
        done = tables.in_turn(jobs, repeats)
    rows = []
    for (python, name), results in done.items():
        m = tables.medians(results)
        rows.append({"python": f"{pythons[python]} {python}", "run": name,
                     "simulated_s": m["simulated"], "wall_s": m["wall"], "cpu_s": m["cpu"],
                     "stepping_wall_s": m["stepping"],
                     "wall_per_simulated_s": m["wall"] / m["simulated"],
                     "newton_per_step": m["newton"],
                     "noise": tables.noise([r["wall"] for r in results],
                                           [r["cpu"] for r in results])})
    return rows


def format_chalk_table(rows, repeats):
    head = ["python", "run", "simulated s", "wall s", "CPU s", "stepping wall s",
            "wall / simulated s", "Newton/step", "noise"]
    cells = [[r["python"], r["run"], f"{r['simulated_s']:g}", f"{r['wall_s']:.2f}",
              f"{r['cpu_s']:.2f}", f"{r['stepping_wall_s']:.2f}",
              f"{r['wall_per_simulated_s']:.2f}", f"{r['newton_per_step']:.2f}", r["noise"]]
             for r in rows]
    if rows[0]["simulated_s"] == 3.0:       # the pushed default, per interpreter
        verdict = "; ".join(
            f"{'met' if r['wall_per_simulated_s'] <= CHALK_TARGET else 'NOT met'} with Python "
            f"{r['python'].split()[0]} ({r['wall_per_simulated_s']:.2f} s)"
            for r in rows if r["run"] == rows[0]["run"])
    else:
        verdict = "not judged: a short run's start-up weighs more per simulated second"
    note = CHALK_NOTE.format(repeats=repeats, target=CHALK_TARGET, verdict=verdict)
    return "\n".join(tables.aligned([head] + cells)) + "\n" + note


def print_chalk_table(repeats, duration=None, pythons=None):
    rows = chalk_table(repeats, duration, pythons=pythons)
    print(format_chalk_table(rows, repeats))
    return rows
