"""The default run against the lecture's tutorial code (solid-sim-tutorial's 4_friction, the scene
our default reproduces), whole processes run in turn: the tutorial's simulator.py without its
real-time wait (tutorial_driver.py), `python simulator.py` and `python simulator.py --no-frames`;
medians of their CPU time (user + system) and wall time, and how many times less ours take."""
import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")     # before numpy loads OpenBLAS

import argparse
import functools
import json
import math
import statistics
import sys
import textwrap

import simulator
from benchmarks import tables, waits
from viewer.command.cli import DURATION

SOURCE = "https://github.com/phys-sim-book/solid-sim-tutorial"
CHAPTER = "4_friction"      # friction on the slope: the scene of our default run
TARGET = 8.0                # the tutorial's wall time over our default run's (issue 42)
STEPS = round(DURATION / simulator.DEFAULTS["h"])       # our default run's: 6 s at h = 0.01
QUICK_STEPS = 30
DRIVER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "tutorial_driver.py")
TEXT = [("run", "run", ""), ("wall s", "wall_s", ".2f"), ("CPU s", "cpu_s", ".2f"),
        ("x CPU", "times_cpu", ".1f"), ("x wall", "times_wall", ".1f"),
        ("Newton", "newton", ""), ("noise", "noise", "")]
NOTE = (
    "{steps} steps of h = {h:g} s at n_seg 4, each run a whole process (import, steps, output), "
    "medians of {rounds} run in turn; CPU: user + system time; x: the tutorial's time over the "
    "run's. The tutorial: its {chapter}/simulator.py unchanged but for its wait of h per frame "
    "(benchmarks/tutorial_driver.py): it draws each step (SDL's dummy driver), prints its Newton "
    "iterations, writes an OBJ per step; {step_cpu:.2f} s of its CPU time in step_forward "
    "({step_ms:.1f} ms a step). Newton: the run's iterations (the tutorial's \"Iteration\" lines; "
    "ours: log.csv's).")


def chapter_folder(path):
    """The tutorial's chapter folder under `path` (a clone, or the chapter itself); ValueError
    naming --tutorial unless it holds simulator.py and time_integrator.py."""
    for folder in (os.path.join(path, CHAPTER), path):
        if all(os.path.isfile(os.path.join(folder, f))
               for f in ("simulator.py", "time_integrator.py")):
            return os.path.abspath(folder)
    raise ValueError(f"--tutorial {path!r} holds no {CHAPTER}/simulator.py")


def run_tutorial(chapter, steps):
    """The tutorial's simulator.py for `steps` steps in a scratch folder (its output/*.obj go
    there): wall and CPU s, and tutorial_driver.py's report (steps, step CPU, Newton, numbers)."""
    with tables.scratch("tutorial-") as scratch:
        wall, cpu, stderr = tables.run_process(
            [sys.executable, DRIVER, chapter, str(steps)], cwd=scratch, SDL_AUDIODRIVER="dummy")
    return {"wall_s": wall, "cpu_s": cpu, **json.loads(stderr.splitlines()[-1])}


def run_ours(flags, steps):
    """`python simulator.py --steps steps *flags` (waits.run_simulator), Newton from log.csv."""
    done = waits.run_simulator(["--steps", str(steps), *flags])
    return {**done, "newton": round(done["newton_per_step"] * steps)}


def differences(numbers):
    """Where the tutorial's scene numbers differ from simulator.DEFAULTS: 'name ours/tutorial'."""
    ours = dict(simulator.DEFAULTS)
    norm = math.hypot(*ours["slope"])
    ours["slope"] = [c / norm for c in ours["slope"]]           # the tutorial's normalized normal
    found = []
    for name, theirs in numbers.items():
        mine = ours[name]
        pairs = zip(mine, theirs) if isinstance(theirs, list) else [(mine, theirs)]
        if not all(math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-15) for a, b in pairs):
            found.append(f"{name} {mine} against {theirs}")
    return found


def table(chapter, rounds, steps):
    """The three runs, `rounds` times in turn: the rows, and the tutorial's first report."""
    runs = {"tutorial " + os.path.join(CHAPTER, "simulator.py"): functools.partial(
                run_tutorial, chapter, steps),
            "python simulator.py": functools.partial(run_ours, [], steps),
            "python simulator.py --no-frames": functools.partial(run_ours, ["--no-frames"], steps)}
    done = tables.in_turn(runs, rounds)
    tutorial = next(iter(done.values()))
    rows = []
    for name, results in done.items():
        walls, cpus = [r["wall_s"] for r in results], [r["cpu_s"] for r in results]
        rows.append({"run": name, "wall_s": statistics.median(walls),
                     "cpu_s": statistics.median(cpus), "newton": results[0]["newton"],
                     "noise": tables.noise(walls, cpus)})
    for row in rows:
        row["times_cpu"] = rows[0]["cpu_s"] / row["cpu_s"]
        row["times_wall"] = rows[0]["wall_s"] / row["wall_s"]
    return rows, tutorial


def report(rows, tutorial, rounds, steps):
    """The table, its note, the scene's numbers compared and the verdict, as lines."""
    step_cpu = statistics.median(r["step_cpu_s"] for r in tutorial)
    note = NOTE.format(steps=steps, h=simulator.DEFAULTS["h"], rounds=rounds, chapter=CHAPTER,
                       step_cpu=step_cpu, step_ms=1000 * step_cpu / steps)
    different = differences(tutorial[0]["numbers"])
    numbers = ("the scene's numbers: as ours (" + ", ".join(tutorial[0]["numbers"]) + ")"
               if not different else "the scene's numbers differ (ours against the tutorial's): "
               + "; ".join(different))
    times = rows[1]["times_wall"]
    status = (("met" if times >= TARGET else "NOT met") if steps == STEPS
              else f"not judged: {steps} steps, not the default run's {STEPS}")
    verdict = (f"python simulator.py is {times:.1f}x faster than the tutorial in wall time "
               f"(target >= {TARGET:g}x: {status}), {rows[1]['times_cpu']:.1f}x in CPU time "
               f"(its frames' process's included){waits.load_text()}")
    return tables.text(TEXT, rows) + [line for paragraph in (note, numbers, verdict)
                                      for line in textwrap.wrap(paragraph, 100)]


def usage_error(message):
    """Bad input: one line (under 100 columns for a short PATH), exit status 2, before anything
    runs."""
    print(f"error: {message}", file=sys.stderr)
    return 2


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m benchmarks.tutorial", description=__doc__)
    ap.add_argument("--tutorial", metavar="PATH", help=f"a clone of {SOURCE}")
    ap.add_argument("--rounds", type=int, default=5, help="runs of each, in turn (default 5)")
    ap.add_argument("--quick", action="store_true",
                    help=f"a smoke run: {QUICK_STEPS} steps, one round")
    args = ap.parse_args(argv)
    if args.tutorial is None:
        return usage_error(f"give --tutorial PATH, a clone of {SOURCE}")
    if args.rounds < 1:
        return usage_error(f"--rounds must be at least 1, got {args.rounds}")
    try:
        chapter = chapter_folder(args.tutorial)
    except ValueError as err:
        return usage_error(str(err))
    rounds, steps = (1, QUICK_STEPS) if args.quick else (args.rounds, STEPS)
    rows, tutorial = table(chapter, rounds, steps)
    print("\n".join(report(rows, tutorial, rounds, steps)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
