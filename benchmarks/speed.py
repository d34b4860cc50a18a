"""Speed of the time step, and what a user waits for (--frames, --chalk, --window: waits.py); the
commands, what they take and the figures they printed: benchmarks/README.md."""
import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")     # before numpy loads OpenBLAS

import argparse
import functools
import math
import statistics
import sys
import tempfile
import time

from benchmarks import tables, waits
from benchmarks.tables import ROOT

# n_seg: (scene, steps before the window, window steps, repeats)
TABLE = {4: ("drop", 110, 200, 5), 8: ("drop", 110, 100, 5), 16: ("drop", 110, 50, 5),
         32: ("drop", 110, 20, 3), 64: ("slide", 5, 10, 3)}
TABLE_QUICK = {4: ("drop", 40, 10, 3), 8: ("drop", 40, 5, 3)}
TEXT = [("n_seg", "n_seg", ""), ("DOF", "dof", ""), ("scene", "scene", ""),
        ("solver", "solver", ""), ("CPU ms/step", "cpu_ms_per_step", ".3g"),
        ("wall ms/step", "wall_ms_per_step", ".3g"), ("Newton/step", "newton_per_step", ".3g"),
        ("solve", "solve_share", ".0%"), ("rest", "rest_share", ".0%"), ("noise", "noise", "")]
COLUMNS = [key for _, key, _ in TEXT if key != "rest_share"]      # speed.csv's
NOTE = """\
CPU, wall: medians over repeats of one window of steps; drop: the default scene after the impact;
slide: the square placed on the slope sliding at 0.43 m/s; solve: share of the window's wall time in
utils.SPDSolver.solve (band assembly, factorization, triangular solves), rest: everything else"""
# n_seg: (steps from the start, runs per tree)
AGAINST = {4: (300, 7), 16: (300, 5), 32: (150, 5)}
AGAINST_QUICK = {4: (30, 1)}
AGAINST_TEXT = [
    ("n_seg", "n_seg", ""), ("steps", "steps", ""), ("runs", "runs", ""),
    ("CPU ms/step new", "cpu_ms_new", ".3g"), ("CPU {rev}", "cpu_ms_old", ".3g"),
    ("CPU new/old", "cpu_ratio", ".2f"), ("wall ms/step new", "wall_ms_new", ".3g"),
    ("wall {rev}", "wall_ms_old", ".3g"), ("wall new/old", "wall_ratio", ".2f"),
    ("Newton new", "newton_new", ""), ("Newton {rev}", "newton_old", ""), ("noise", "noise", "")]
AGAINST_COLUMNS = [key for _, key, _ in AGAINST_TEXT]
AGAINST_NOTE = """\
new: the working tree; {rev}: the tree compared against; the default scene from its start through
simulator.simulate, each run a fresh process, runs alternating new/old; medians of CPU and wall \
time per step;
Newton: total Newton iterations of a run (the same trajectory must take the same number)"""


def slide_scene(simulator, n_seg, d0=0.008, speed=0.43):
    """The default scene, but the square placed on the slope, aligned with it (bottom row at
    d0 < dhat), sliding down at `speed` m/s as the dropped one does after its impact."""
    import BarrierEnergy
    import FrictionEnergy
    theta = math.atan(0.1)
    probe = simulator.build_scene(n_seg=n_seg, angle=-theta, center=(0.0, 1.0))
    lift = (BarrierEnergy.distances(probe.x0, probe.n, probe.o).min() - d0) / probe.n[1]
    return simulator.build_scene(n_seg=n_seg, angle=-theta, center=(0.0, 1.0 - lift),
                                 v0=tuple(speed * FrictionEnergy.tangent(probe.n)))


def timed(reports):
    """(CPU s, wall s, Newton iterations) of going through `reports`, the steps' reports."""
    wall, cpu = time.perf_counter(), time.process_time()
    newton = sum(report.newton_iterations for report in reports)
    return time.process_time() - cpu, time.perf_counter() - wall, newton


def solve_share(utils, window):
    """The share of the wall time of `window()` spent in utils.SPDSolver.solve (wrapped)."""
    original, spent = utils.SPDSolver.solve, []

    def solve(solver, H, b):
        start = time.perf_counter()
        result = original(solver, H, b)
        spent.append(time.perf_counter() - start)
        return result
    utils.SPDSolver.solve = solve
    wall = window()[1]          # the same window ran `repeats` times already: it cannot fail
    utils.SPDSolver.solve = original
    return sum(spent) / wall


def measure(n_seg, kind, warm, count, repeats):
    """One row of the table: a window of `count` steps after `warm` ones, `repeats` times."""
    import simulator
    import time_integrator
    import utils
    scene = simulator.build_scene(n_seg=n_seg) if kind == "drop" else slide_scene(simulator, n_seg)
    states = [(scene.x0, scene.v0)]         # (x, v) before each step
    for i in range(warm + count):
        x, v, _ = time_integrator.step(scene, *states[-1], step_index=i)
        states.append((x, v))

    def window():
        return timed(time_integrator.step(scene, x, v, step_index=i)[2]
                     for i, (x, v) in enumerate(states[warm:-1], warm))
    cpus, walls, newton = zip(*(window() for _ in range(repeats)))
    share = solve_share(utils, window)
    return {"n_seg": n_seg, "dof": 2 * len(scene.x0), "scene": kind, "solver": scene.solver.kind,
            "cpu_ms_per_step": 1e3 * statistics.median(cpus) / count,
            "wall_ms_per_step": 1e3 * statistics.median(walls) / count,
            "newton_per_step": newton[0] / count, "solve_share": share, "rest_share": 1 - share,
            "noise": tables.noise(walls, cpus)}


def run_default_scene(tree, n_seg, count):
    """timed of `count` steps of simulate on the default scene at n_seg, with `tree`'s modules."""
    sys.path.insert(0, tree)
    import simulator
    return timed(record.report for record in
                 simulator.simulate(simulator.build_scene(n_seg=n_seg), count))


def compare(new_tree, old_tree, configs):
    """Per n_seg, runs of each tree in turn: medians per step, their ratio, Newton iterations."""
    rows = []
    for n_seg, (count, runs) in configs.items():
        print(f"n_seg {n_seg}, {count} steps, new and old in turn:", file=sys.stderr)
        results = tables.in_turn({name: functools.partial(
            tables.in_fresh_process, "benchmarks.speed", "run_default_scene", tree, n_seg, count)
            for name, tree in (("new", new_tree), ("old", old_tree))}, runs)
        row, noisy = {"n_seg": n_seg, "steps": count, "runs": runs}, []
        for name, tree_runs in results.items():
            cpus, walls, newton = zip(*tree_runs)
            row[f"cpu_ms_{name}"] = 1e3 * statistics.median(cpus) / count
            row[f"wall_ms_{name}"] = 1e3 * statistics.median(walls) / count
            row[f"newton_{name}"] = newton[0]
            if (verdict := tables.noise(walls, cpus)) != "ok":
                noisy.append(f"{name}: {verdict}")
        row["cpu_ratio"] = row["cpu_ms_new"] / row["cpu_ms_old"]
        row["wall_ratio"] = row["wall_ms_new"] / row["wall_ms_old"]
        counts = sorted({n for tree_runs in results.values() for _, _, n in tree_runs})
        if len(counts) > 1:
            noisy.insert(0, f"NEWTON MISMATCH ({counts})")
        row["noise"] = "; ".join(noisy) or "ok"
        rows.append(row)
    return rows


def usage_error(message):
    """Bad input: one line naming the option, exit status 2, before anything runs."""
    print(f"python -m benchmarks.speed: error: {message}", file=sys.stderr)
    return 2


def parse(argv):
    ap = argparse.ArgumentParser(prog="python -m benchmarks.speed", description=__doc__)
    ap.add_argument("--quick", action="store_true", help="a smoke run (comparison: n_seg 4)")
    ap.add_argument("--against", metavar="REV", help="also compare with this commit (or folder)")
    ap.add_argument("--sizes", help="comma-separated n_seg values of the table (and of --against)")
    ap.add_argument("--out", help="folder for the CSV files (default: see benchmarks/README.md)")
    ap.add_argument("--window", action="store_true", help="only the live window's figures")
    ap.add_argument("--frames", action="store_true", help="only the run with and without frames")
    ap.add_argument("--chalk", action="store_true", help="only the chalk's runs")
    ap.add_argument("--python", metavar="EXE[,EXE]", help="with --chalk: the interpreters to run")
    return ap.parse_args(argv)


def chalk(args):
    """--chalk: each interpreter checked before anything runs, then the table and its CSV."""
    try:
        pythons = None if args.python is None else {
            p.strip(): waits.python_version(p.strip()) for p in args.python.split(",")}
    except ValueError as err:
        return usage_error(str(err))
    repeats = 1 if args.quick else 3
    rows = waits.chalk_table(repeats, 0.3 if args.quick else None, pythons=pythons)
    print(waits.format_chalk_table(rows, repeats))
    out = tables.output_folder(args.out, not (args.quick or args.python), "chalk-speed")
    tables.write_csv(os.path.join(out, "chalk-speed.csv"), waits.COLUMNS, rows)
    return 0


def main(argv=None):
    args = parse(argv)
    if args.python is not None and not args.chalk:
        return usage_error("--python needs --chalk: it names the interpreters the chalk's "
                           "processes run in")
    if args.window:
        print(waits.window_table())
        return 0
    if args.frames:
        waits.print_frames_overhead(3 if args.quick else 5)
        return 0
    if args.chalk:
        return chalk(args)
    table = TABLE_QUICK if args.quick else TABLE
    rows = []
    sizes = [int(s) for s in args.sizes.split(",")] if args.sizes else list(table)
    for n_seg in sizes:
        config = table.get(n_seg, ("drop", 110, 10, 3) if n_seg <= 32 else ("slide", 5, 10, 3))
        rows.append(measure(n_seg, *config))
        print(f"n_seg {n_seg}: {rows[-1]['cpu_ms_per_step']:.3g} ms/step", file=sys.stderr)
    print("\n".join(tables.text(TEXT, rows) + [NOTE]))
    full = not (args.quick or args.sizes or args.against)
    out = tables.output_folder(args.out, full, "speed")
    tables.write_csv(os.path.join(out, "speed.csv"), COLUMNS, rows)
    if args.against:
        with tempfile.TemporaryDirectory(prefix="speed-against-") as folder:
            old_tree = tables.export_tree(args.against, folder)
            configs = AGAINST_QUICK if args.quick else AGAINST
            if args.sizes:          # --sizes narrows the comparison (others: 300 steps, 5 runs)
                configs = {n: configs.get(n, (300, 5)) for n in sizes}
            rows = compare(ROOT, old_tree, configs)
        text = tables.text(AGAINST_TEXT, rows, rev=args.against)
        print("\n".join([""] + text + [AGAINST_NOTE.format(rev=args.against)]))
        tables.write_csv(os.path.join(out, "speed-against.csv"), AGAINST_COLUMNS, rows)
    print(f"BLAS threads: OPENBLAS_NUM_THREADS={os.environ['OPENBLAS_NUM_THREADS']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
