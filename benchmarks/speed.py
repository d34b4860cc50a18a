"""Speed of the time step: time per step by n_seg, and side by side against an earlier commit.

The table: for each n_seg the slope scene is stepped through a fixed window of time steps (after
the impact for the dropped square up to n_seg 32; at n_seg 64, where the impact takes minutes, the
square starts on the slope, sliding as the dropped one does after its impact): the time per step
(process CPU time and wall time, medians over repeats of the same window), Newton iterations per
step, and the share of the step spent in `utils.SPDSolver.solve` (assembling the band and the
factorization and solve) against the rest (energies, line search, CCD, friction update).

This module is the table and the command line of the speed benchmarks; each other one is a module of
its own: the comparison with an earlier commit (`--against REV`: benchmarks/speed_against.py), the live
window's real time (`--window`: window_speed.py), the cost of the frames (`--frames`: frames_cost.py),
the chalk's wait (`--chalk`: chalk_speed.py).

    python -m benchmarks.speed                       # the table, n_seg 4 ... 64 (1-2 minutes)
    python -m benchmarks.speed --against c6bcae2     # and the comparison (3 min CPU, 5-7 min on a busy machine)
    python -m benchmarks.speed --quick [--against REV]   # a smoke run, a few seconds
    python -m benchmarks.speed --frames              # the default run with and without frames (frames_overhead)
    python -m benchmarks.speed --window              # the live window at n_seg 4, 8, 16 (on $DISPLAY too)
    python -m benchmarks.speed --chalk               # the chalk's 3 s runs, pushed and dragged (about 2 minutes)
    python -m benchmarks.speed --chalk --python A,B  # the same, under the interpreters at the paths A and B

Only the plain command writes into benchmarks/results/ (speed.csv, the table benchmarks/README.md
quotes); a run with --quick, --sizes or --against writes speed.csv (and speed-against.csv) into a new
temporary folder, and --out DIR into DIR. --window and --frames only print; --chalk writes chalk-speed.csv
(into benchmarks/results/ unless --quick, --python or --out).

Timing on a shared machine: the figures to read are the CPU medians; a line is marked noisy as
benchmarks/tables.noise says. BLAS runs on one thread unless OPENBLAS_NUM_THREADS says otherwise.
"""
import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")     # before numpy loads OpenBLAS

import argparse
import math
import statistics
import sys
import tempfile
import time

import benchmarks
from benchmarks import chalk_speed, frames_cost, speed_against, tables, window_speed

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# n_seg: (scene, steps before the window, window steps, repeats)
TABLE = {4: ("drop", 110, 200, 5), 8: ("drop", 110, 100, 5), 16: ("drop", 110, 50, 5),
         32: ("drop", 110, 20, 3), 64: ("slide", 5, 10, 3)}
TABLE_QUICK = {4: ("drop", 40, 10, 3), 8: ("drop", 40, 5, 3)}

COLUMNS = ["n_seg", "dof", "scene", "solver", "cpu_ms_per_step", "wall_ms_per_step", "newton_per_step",
           "solve_share", "noise"]


# ------------------------------------------------------------------------------------------------
# The table (in this process, with the working tree)
# ------------------------------------------------------------------------------------------------

def slide_scene(simulator, n_seg, d0=0.008, speed=0.43):
    """The default slope and parameters, but the square starts on the slope, aligned with it (bottom
    row at d0 < dhat), sliding down at `speed` m/s, as the dropped square does after its impact."""
    import BarrierEnergy
    import FrictionEnergy
    theta = math.atan(0.1)
    probe = simulator.build_scene(n_seg=n_seg, angle=-theta, center=(0.0, 1.0))
    d = BarrierEnergy.distances(probe.x0, probe.n, probe.o)
    tangent = FrictionEnergy.tangent(probe.n)
    return simulator.build_scene(n_seg=n_seg, angle=-theta, center=(0.0, 1.0 - (d.min() - d0) / probe.n[1]),
                                 v0=tuple(speed * tangent))


class SolveTimer:
    """Adds up the wall time spent in utils.SPDSolver.solve while it is open (the method is wrapped)."""

    def __init__(self, utils):
        self.utils, self.seconds = utils, 0.0

    def __enter__(self):
        self.original = original = self.utils.SPDSolver.solve

        def timed(solver, H, b):
            start = time.perf_counter()
            try:
                return original(solver, H, b)
            finally:
                self.seconds += time.perf_counter() - start
        self.utils.SPDSolver.solve = timed
        return self

    def __exit__(self, *exc):
        self.utils.SPDSolver.solve = self.original


def run_window(time_integrator, scene, x, v, first, steps):
    """Take `steps` steps from (x, v): (wall s, CPU s, Newton iterations)."""
    wall, cpu, newton = time.perf_counter(), time.process_time(), 0
    for i in range(steps):
        x, v, report = time_integrator.step(scene, x, v, step_index=first + i)
        newton += report.newton_iterations
    return time.perf_counter() - wall, time.process_time() - cpu, newton


def measure(n_seg, kind, warm, steps, repeats):
    """One row of the table."""
    sys.path.insert(0, ROOT)
    import simulator
    import time_integrator
    import utils
    scene = simulator.build_scene(n_seg=n_seg) if kind == "drop" else slide_scene(simulator, n_seg)
    x, v = scene.x0, scene.v0
    for i in range(warm):
        x, v, _ = time_integrator.step(scene, x, v, step_index=i)
    runs = [run_window(time_integrator, scene, x, v, warm, steps) for _ in range(repeats)]
    with SolveTimer(utils) as timer:
        wall_instrumented = run_window(time_integrator, scene, x, v, warm, steps)[0]
    walls, cpus = [r[0] for r in runs], [r[1] for r in runs]
    return {"n_seg": n_seg, "dof": 2 * len(scene.x0), "scene": kind, "solver": scene.solver.kind,
            "cpu_ms_per_step": 1e3 * statistics.median(cpus) / steps,
            "wall_ms_per_step": 1e3 * statistics.median(walls) / steps,
            "newton_per_step": runs[0][2] / steps, "solve_share": timer.seconds / wall_instrumented,
            "noise": tables.noise(walls, cpus)}


def format_table(rows):
    head = ["n_seg", "DOF", "scene", "solver", "CPU ms/step", "wall ms/step", "Newton/step", "solve", "rest", "noise"]
    cells = [head] + [[str(r["n_seg"]), str(r["dof"]), r["scene"], r["solver"], f"{r['cpu_ms_per_step']:.3g}",
                       f"{r['wall_ms_per_step']:.3g}", f"{r['newton_per_step']:.3g}",
                       f"{100 * r['solve_share']:.0f}%", f"{100 * (1 - r['solve_share']):.0f}%", r["noise"]]
                      for r in rows]
    return "\n".join(tables.aligned(cells) + [
        "CPU, wall: medians over repeats of one window of steps; drop: the default scene after the impact;",
        "slide: the square placed on the slope sliding at 0.43 m/s; solve: share of the window's wall time in",
        "utils.SPDSolver.solve (band assembly, factorization, triangular solves), rest: everything else"])


def usage_error(message):
    """Bad input: one line naming the option, exit status 2, before anything is run or written."""
    print(f"python -m benchmarks.speed: error: {message}", file=sys.stderr)
    return 2


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m benchmarks.speed", description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="smoke run: n_seg 4 and 8, few steps (comparison: n_seg 4)")
    ap.add_argument("--against", metavar="REV", help="also compare with this commit (or folder), side by side")
    ap.add_argument("--sizes", help="comma-separated n_seg values of the table (default: all of the mode)")
    ap.add_argument("--out", help="folder for speed.csv and speed-against.csv (default: benchmarks/results/ for the "
                                  "plain command; with --quick, --sizes or --against a new temporary folder)")
    ap.add_argument("--window", action="store_true",
                    help="only the live window's real-time figures (n_seg 4, 8, 16; on $DISPLAY too when there is one)")
    ap.add_argument("--frames", action="store_true", help="only the default run with frames against --no-frames")
    ap.add_argument("--chalk", action="store_true", help="only the chalk's runs, pushed and dragged, from x_tilde "
                                                         "and x^n (with --quick: 0.3 s runs, once)")
    ap.add_argument("--python", metavar="EXE[,EXE]",
                    help="with --chalk: the interpreters whose processes run, in turn (default: this one)")
    args = ap.parse_args(argv)
    if args.python is not None and not args.chalk:
        return usage_error("--python needs --chalk: it names the interpreters the chalk's processes run in")
    if args.window:
        print(window_speed.window_table())
        return 0
    if args.frames:
        return frames_cost.print_frames_overhead(3 if args.quick else 5)
    if args.chalk:
        try:            # each interpreter given, checked before anything runs (None: this one)
            versions = None if args.python is None else {
                python: chalk_speed.python_version(python) for python in (p.strip() for p in args.python.split(","))}
        except ValueError as err:
            return usage_error(str(err))
        rows = chalk_speed.print_chalk_table(1 if args.quick else 3, 0.3 if args.quick else None, versions)
        out = benchmarks.output_folder(args.out, not (args.quick or args.python), "chalk-speed")
        tables.write_csv(os.path.join(out, "chalk-speed.csv"), chalk_speed.COLUMNS, rows)
        print(f"wrote chalk-speed.csv into {out}", file=sys.stderr)
        return 0
    table = TABLE_QUICK if args.quick else TABLE
    sizes = [int(s) for s in args.sizes.split(",")] if args.sizes else list(table)
    rows = []
    for n_seg in sizes:
        rows.append(measure(n_seg, *table.get(n_seg, ("drop" if n_seg <= 32 else "slide", 110 if n_seg <= 32 else 5, 10, 3))))
        print(f"n_seg {n_seg}: {rows[-1]['cpu_ms_per_step']:.3g} ms/step", file=sys.stderr, flush=True)
    print(format_table(rows))
    out = benchmarks.output_folder(args.out, not (args.quick or args.sizes or args.against), "speed")
    path = os.path.join(out, "speed.csv")
    tables.write_csv(path, COLUMNS, rows)
    if args.against:
        with tempfile.TemporaryDirectory(prefix="speed-against-") as folder:
            old_tree = speed_against.export_tree(args.against, folder)
            comparison = speed_against.compare(ROOT, old_tree, speed_against.AGAINST_QUICK if args.quick
                                               else speed_against.AGAINST)
        print()
        print(speed_against.format_comparison(comparison, args.against))
        tables.write_csv(os.path.join(out, "speed-against.csv"), speed_against.AGAINST_COLUMNS, comparison)
    print(f"BLAS threads: OPENBLAS_NUM_THREADS={os.environ['OPENBLAS_NUM_THREADS']}")
    print(f"wrote speed.csv{' and speed-against.csv' if args.against else ''} into {out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
