"""Speed of the time step: time per step by n_seg, and side by side against an earlier commit.

The table: for each n_seg the slope scene is stepped through a fixed window of time steps (after
the impact for the dropped square up to n_seg 32; at n_seg 64, where the impact takes minutes, the
square starts on the slope, sliding as the dropped one does after its impact): the time per step
(process CPU time and wall time, medians over repeats of the same window), Newton iterations per
step, and the share of the step spent in `utils.SPDSolver.solve` (assembling the band and the
factorization and solve) against the rest (energies, line search, CCD, friction update).

The comparison (`--against REV`): the default scene run by `simulator.simulate` at n_seg 4 (300
steps), 16 (300 steps) and 32 (150 steps, through the impact), once with the working tree and once
with commit REV (exported with `git archive` into a temporary folder), each run in its own Python
process with its tree first on sys.path, alternating A/B/A/B; medians of the per-step CPU and wall
time, each tree's total Newton iterations (the same trajectory must take the same number: a mismatch
is flagged) and the ratio working tree / REV. Only `simulator.build_scene(n_seg=...)`,
`simulator.simulate(scene, steps)` and `record.report.newton_iterations` are used, so any tree that
has them can be compared. REV may also be a folder holding a tree.

    python -m benchmarks.speed                       # the table, n_seg 4 ... 64 (1-2 minutes)
    python -m benchmarks.speed --against c6bcae2     # and the comparison (3 min CPU, 5-7 min on a busy machine)
    python -m benchmarks.speed --quick [--against REV]   # a smoke run, a few seconds
    python -m benchmarks.speed --frames              # the default run with and without frames (frames_overhead)
    python -m benchmarks.speed --window              # the live window at n_seg 4, 8, 16 (on $DISPLAY too)

Only the plain command writes into benchmarks/results/ (speed.csv, the table benchmarks/README.md
quotes); a run with --quick, --sizes or --against writes speed.csv (and speed-against.csv) into a new
temporary folder, and --out DIR into DIR. --window and --frames only print.

Timing on a shared machine: other processes take the CPU at times, which stretches wall time but
not the process's own CPU time, so the figures to read are the CPU medians; a line is marked noisy
when wall / CPU time exceeds WAIT_LIMIT (the process waited for a CPU) or the repeats spread by more
than SPREAD_LIMIT. BLAS runs on one thread unless OPENBLAS_NUM_THREADS says otherwise.
"""
import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")     # before numpy loads OpenBLAS

import argparse
import csv
import json
import math
import statistics
import subprocess
import sys
import tempfile
import time

import benchmarks

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# n_seg: (scene, steps before the window, window steps, repeats)
TABLE = {4: ("drop", 110, 200, 5), 8: ("drop", 110, 100, 5), 16: ("drop", 110, 50, 5),
         32: ("drop", 110, 20, 3), 64: ("slide", 5, 10, 3)}
TABLE_QUICK = {4: ("drop", 40, 10, 3), 8: ("drop", 40, 5, 3)}
# n_seg: (steps from the start, runs per tree) for the comparison
AGAINST = {4: (300, 7), 16: (300, 5), 32: (150, 3)}
AGAINST_QUICK = {4: (30, 2)}
SPREAD_LIMIT, WAIT_LIMIT = 0.20, 1.15

COLUMNS = ["n_seg", "dof", "scene", "solver", "cpu_ms_per_step", "wall_ms_per_step", "newton_per_step",
           "solve_share", "noise"]
AGAINST_COLUMNS = ["n_seg", "steps", "runs", "cpu_ms_new", "cpu_ms_old", "cpu_ratio", "wall_ms_new", "wall_ms_old",
                   "wall_ratio", "newton_new", "newton_old", "noise"]


# ------------------------------------------------------------------------------------------------
# The table (in this process, with the working tree)
# ------------------------------------------------------------------------------------------------

def slide_scene(simulator, n_seg, d0=0.008, speed=0.43):
    """The default slope and parameters, but the square starts on the slope, aligned with it (bottom
    row at d0 < dhat), sliding down at `speed` m/s, as the dropped square does after its impact."""
    import numpy as np
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
            "noise": noise(walls, cpus)}


def spread(values):
    return (max(values) - min(values)) / statistics.median(values)


def noise(walls, cpus):
    """'ok', or why the machine was too busy for these figures to mean much."""
    reasons = []
    if spread(cpus) > SPREAD_LIMIT:
        reasons.append(f"CPU times spread {100 * spread(cpus):.0f}%")
    wait = statistics.median(walls) / statistics.median(cpus)
    if wait > WAIT_LIMIT:
        reasons.append(f"wall/CPU {wait:.2f}")
    return "NOISY: " + ", ".join(reasons) if reasons else "ok"


def format_table(rows):
    head = ["n_seg", "DOF", "scene", "solver", "CPU ms/step", "wall ms/step", "Newton/step", "solve", "rest", "noise"]
    cells = [head] + [[str(r["n_seg"]), str(r["dof"]), r["scene"], r["solver"], f"{r['cpu_ms_per_step']:.3g}",
                       f"{r['wall_ms_per_step']:.3g}", f"{r['newton_per_step']:.3g}",
                       f"{100 * r['solve_share']:.0f}%", f"{100 * (1 - r['solve_share']):.0f}%", r["noise"]]
                      for r in rows]
    return "\n".join(aligned(cells) + [
        "CPU, wall: medians over repeats of one window of steps; drop: the default scene after the impact;",
        "slide: the square placed on the slope sliding at 0.43 m/s; solve: share of the window's wall time in",
        "utils.SPDSolver.solve (band assembly, factorization, triangular solves), rest: everything else"])


def aligned(cells):
    widths = [max(len(c[i]) for c in cells) for i in range(len(cells[0]))]
    lines = ["  ".join(c.rjust(w) for c, w in zip(line[:-1], widths)) + "  " + line[-1] for line in cells]
    return lines[:1] + ["-" * len(lines[0])] + lines[1:]


# ------------------------------------------------------------------------------------------------
# The comparison: each run a fresh process with its tree first on sys.path
# ------------------------------------------------------------------------------------------------

def run_default_scene(tree, n_seg, steps):
    """(CPU s, wall s, Newton iterations) of `steps` steps of simulator.simulate on the default scene
    at n_seg, with `tree`'s modules (runs in the worker process)."""
    sys.path.insert(0, tree)
    import simulator
    scene = simulator.build_scene(n_seg=n_seg)
    newton, wall, cpu = 0, time.perf_counter(), time.process_time()
    for record in simulator.simulate(scene, steps):
        newton += record.report.newton_iterations
    return time.process_time() - cpu, time.perf_counter() - wall, newton


def run_in_process(tree, n_seg, steps):
    job = json.dumps({"tree": tree, "n_seg": n_seg, "steps": steps})
    done = subprocess.run([sys.executable, "-m", "benchmarks.speed", "--worker", job], cwd=ROOT,
                          capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"n_seg {n_seg} with the tree {tree} failed:\n{done.stderr}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def compare(new_tree, old_tree, configs):
    """The comparison's rows: per n_seg, runs alternating new/old, medians per step."""
    rows = []
    for n_seg, (steps, runs) in configs.items():
        new, old = [], []
        for r in range(runs):
            new.append(run_in_process(new_tree, n_seg, steps))
            old.append(run_in_process(old_tree, n_seg, steps))
            print(f"  n_seg {n_seg} run {r + 1}/{runs}: CPU {new[-1][0] / steps * 1e3:.3g} ms/step (working tree), "
                  f"{old[-1][0] / steps * 1e3:.3g} (against)", file=sys.stderr, flush=True)
        row = {"n_seg": n_seg, "steps": steps, "runs": runs}
        for name, results in (("new", new), ("old", old)):
            row[f"cpu_ms_{name}"] = 1e3 * statistics.median(c for c, _, _ in results) / steps
            row[f"wall_ms_{name}"] = 1e3 * statistics.median(w for _, w, _ in results) / steps
            row[f"newton_{name}"] = results[0][2]
        row["cpu_ratio"] = row["cpu_ms_new"] / row["cpu_ms_old"]
        row["wall_ratio"] = row["wall_ms_new"] / row["wall_ms_old"]
        same = {n for _, _, n in new} | {n for _, _, n in old}
        noisy = [f"{name}: {verdict}" for name, results in (("new", new), ("old", old))
                 if (verdict := noise([w for _, w, _ in results], [c for c, _, _ in results])) != "ok"]
        row["noise"] = "; ".join(noisy) or "ok"
        if len(same) != 1:
            row["noise"] = f"NEWTON MISMATCH ({sorted(same)}); " + row["noise"]
        rows.append(row)
    return rows


def format_comparison(rows, rev):
    head = ["n_seg", "steps", "runs", "CPU ms/step new", f"CPU {rev}", "CPU new/old", "wall ms/step new",
            f"wall {rev}", "wall new/old", "Newton new", f"Newton {rev}", "noise"]
    cells = [head] + [[str(r["n_seg"]), str(r["steps"]), str(r["runs"]), f"{r['cpu_ms_new']:.3g}",
                       f"{r['cpu_ms_old']:.3g}", f"{r['cpu_ratio']:.2f}", f"{r['wall_ms_new']:.3g}",
                       f"{r['wall_ms_old']:.3g}", f"{r['wall_ratio']:.2f}", str(r["newton_new"]),
                       str(r["newton_old"]), r["noise"]] for r in rows]
    return "\n".join(aligned(cells) + [
        f"new: the working tree; {rev}: the tree compared against; the default scene from its start through",
        "simulator.simulate, each run a fresh process, runs alternating new/old; medians of CPU and wall time per step;",
        "Newton: total Newton iterations of a run (the same trajectory must take the same number)"])


def export_tree(rev, folder):
    """The tree to compare against: `rev` itself if it is a folder, else commit `rev` (git archive into
    `folder`; the checkout is not touched)."""
    if os.path.isdir(rev):
        return os.path.abspath(rev)
    archive = subprocess.run(["git", "-C", ROOT, "archive", "--format=tar", rev], capture_output=True)
    if archive.returncode != 0:
        raise SystemExit(f"speed: error: git archive {rev}: {archive.stderr.decode().strip()}")
    subprocess.run(["tar", "-x", "-C", folder], input=archive.stdout, check=True)
    return folder


# ------------------------------------------------------------------------------------------------
# The command line
# ------------------------------------------------------------------------------------------------

def write_csv(path, columns, rows):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns, extrasaction="ignore", lineterminator="\n")
        writer.writeheader()
        writer.writerows({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()} for r in rows)


# ------------------------------------------------------------------------------------------------
# The live window keeps real time (python -m benchmarks.speed --window)
# ------------------------------------------------------------------------------------------------

WINDOW_N_SEGS = (4, 8, 16)
WINDOW_PIXELS = 652         # the window's default side on a 1024x768 projector (viewer.window.FIT)
MEMORY_DRIVER = "dummy"     # SDL's driver that draws into memory only, no display needed


class MeteredClock:
    """The wall clock for the window's loop, adding up the time it sleeps (its idle time); it presses
    the close button once the run is over, and notes the lowest rate the window measured."""

    def __init__(self):
        self.slept, self.window, self.end, self.lowest_rate = 0.0, None, None, math.inf

    now = staticmethod(time.perf_counter)

    def sleep(self, seconds):
        rate = self.window.pacer.rate() if self.window.pacer.samples else None
        self.lowest_rate = min(self.lowest_rate, math.inf if rate is None else rate)
        if self.end is not None:            # the run is over: the close button is on its way
            return
        if self.window.run.finished:
            self.end = time.perf_counter()
            self.window.pygame.event.post(self.window.pygame.event.Event(self.window.pygame.QUIT))
            return
        start = time.perf_counter()
        time.sleep(seconds)
        self.slept += time.perf_counter() - start


def window_real_time(n_seg, speed=1.0, duration=3.0, driver=MEMORY_DRIVER):
    """The default run (3 s) in the live window at `speed`, drawing included, on SDL video driver
    `driver` (the dummy one draws into memory; x11 shows it on $DISPLAY, a desktop or Xvfb): wall
    seconds per simulated second (1/speed when it keeps up), CPU seconds per simulated
    second (what it needs of one core, whatever else the machine runs), the share of the wall time the
    loop was busy (not sleeping), frames drawn and those with the 'slower than real time' note, and
    the lowest rate the window measured (over its one-second spans, as a fraction of speed)."""
    os.environ["SDL_VIDEODRIVER"] = driver
    sys.path.insert(0, ROOT)
    import simulator
    from viewer import window
    scene = simulator.build_scene(n_seg=n_seg)
    steps = int(round(duration / scene.h))
    pygame = window.open_display()
    try:
        screen = pygame.display.set_mode((WINDOW_PIXELS, WINDOW_PIXELS))
        clock = MeteredClock()
        live = clock.window = window.LiveWindow(pygame, screen, scene, steps, speed, clock=clock)
        start, cpu = time.perf_counter(), time.process_time()
        live.loop()
        cpu = time.process_time() - cpu
    finally:
        pygame.display.quit()
    wall = clock.end - start
    return {"n_seg": n_seg, "speed": speed, "driver": driver, "wall_per_simulated": wall / (steps * scene.h),
            "cpu_per_simulated": cpu / (steps * scene.h),
            "busy": 1.0 - min(clock.slept, wall) / wall, "frames": live.frames, "slow_frames": live.slow_frames,
            "lowest_rate": clock.lowest_rate}


def display_driver():
    """The SDL driver of the display at $DISPLAY (x11 on a desktop or under Xvfb), or None: the window
    is then measured on the dummy driver only."""
    if not os.environ.get("DISPLAY"):
        return None
    probe = subprocess.run([sys.executable, "-c", "import pygame; pygame.display.init(); print(pygame.display.get_driver())"],
                           env={**os.environ, "SDL_VIDEODRIVER": "x11", "PYGAME_HIDE_SUPPORT_PROMPT": "1"},
                           capture_output=True, text=True, timeout=60)
    return "x11" if probe.returncode == 0 and probe.stdout.strip() == "x11" else None


def window_table(sizes=WINDOW_N_SEGS):
    """The window's real-time figures at speed 1, and flat out (speed 100: as fast as it can go), on the
    dummy driver and, where there is a display, on it."""
    drivers = [MEMORY_DRIVER] + [d for d in [display_driver()] if d]
    where = f"DISPLAY={os.environ.get('DISPLAY')}" if len(drivers) > 1 else "no display found: dummy only"
    lines = [f"Live window ({WINDOW_PIXELS} px, drawing included; {where}), the default 3 s run:",
             "  n_seg  driver  speed  wall/simulated s  CPU/simulated s  busy  frames  frames 'slower'  "
             "lowest rate  -> x real time"]
    for n_seg in sizes:
        for driver in drivers:
            for speed in (1.0, 100.0):
                r = window_real_time(n_seg, speed, driver=driver)
                lowest = f"{r['lowest_rate']:.2g}" if r["lowest_rate"] < math.inf else "-"
                lines.append(f"  {n_seg:>5}  {driver:>6}  {speed:>5g}  {r['wall_per_simulated']:>16.3f}  "
                             f"{r['cpu_per_simulated']:>15.3f}  {100 * r['busy']:>3.0f}%  {r['frames']:>6}  "
                             f"{r['slow_frames']:>15}  {lowest:>11}  {1 / r['wall_per_simulated']:>6.2f}")
    lines.append("CPU/simulated: CPU seconds per simulated second (below 1: one free core keeps real time);")
    lines.append("busy: share of the wall time not spent sleeping between frames; lowest rate: simulated over wall")
    lines.append("time over the window's one-second spans, / speed ('-': the run was shorter than a span); at speed")
    lines.append("100 the window steps flat out, so 'x real time' is the fastest it can run; dummy: SDL draws into")
    lines.append("memory, x11: the frames shown on the display (the X server's own CPU time not included)")
    return "\n".join(lines)


# ------------------------------------------------------------------------------------------------
# The cost of the frames: the default `python simulator.py` against the same run with --no-frames
# ------------------------------------------------------------------------------------------------

FRAMES_TARGET = 3.0         # the default run at most 3x the wall time of --no-frames (issue 16)


def frames_overhead(repeats=5, extra=()):
    """Whole-process wall time of `python simulator.py` and of `python simulator.py --no-frames`,
    run alternately (so both meet the machine in the same state), `repeats` times each: the medians,
    their ratio, and the frames written per simulated second."""
    import tempfile
    times = {"frames": [], "no-frames": []}
    with tempfile.TemporaryDirectory() as folder:
        for _ in range(repeats):
            for kind in times:
                out = os.path.join(folder, kind)
                command = [sys.executable, os.path.join(ROOT, "simulator.py"), "--out", out, *extra]
                start = time.perf_counter()
                done = subprocess.run(command + (["--no-frames"] if kind == "no-frames" else []), cwd=ROOT,
                                      capture_output=True, text=True, env={**os.environ, "SDL_VIDEODRIVER": "dummy"})
                times[kind].append(time.perf_counter() - start)
                if done.returncode != 0:
                    raise RuntimeError(f"simulator.py failed:\n{done.stderr}")
        frames = len([f for f in os.listdir(os.path.join(folder, "frames")) if f.endswith(".png") and f.startswith("frame_")])
        with open(os.path.join(folder, "frames", "log.csv")) as f:
            simulated = float(list(csv.DictReader(f))[-1]["t"])
    with_frames, without = statistics.median(times["frames"]), statistics.median(times["no-frames"])
    return {"frames_s": with_frames, "no_frames_s": without, "ratio": with_frames / without,
            "frames_per_simulated_s": (frames - 1) / simulated, "frames": frames,
            "spread": max(spread(times["frames"]), spread(times["no-frames"]))}


def print_frames_overhead(repeats):
    r = frames_overhead(repeats)
    verdict = "met" if r["ratio"] <= FRAMES_TARGET else "NOT met"
    print(f"python simulator.py: {r['frames_s']:.2f} s with {r['frames']} frames ({r['frames_per_simulated_s']:.1f} "
          f"per simulated second), {r['no_frames_s']:.2f} s with --no-frames (whole processes, medians of "
          f"{repeats}, run alternately): {r['ratio']:.2f}x (target <= {FRAMES_TARGET:g}x: {verdict}; "
          f"repeats spread {100 * r['spread']:.0f}%)")
    return 0


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m benchmarks.speed", description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="smoke run: n_seg 4 and 8, few steps (comparison: n_seg 4)")
    ap.add_argument("--against", metavar="REV", help="also compare with this commit (or folder), side by side")
    ap.add_argument("--sizes", help="comma-separated n_seg values of the table (default: all of the mode)")
    ap.add_argument("--out", help="folder for speed.csv and speed-against.csv (default: benchmarks/results/ for the "
                                  "plain command; with --quick, --sizes or --against a new temporary folder)")
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--window", action="store_true",
                    help="only the live window's real-time figures (n_seg 4, 8, 16; on $DISPLAY too when there is one)")
    ap.add_argument("--frames", action="store_true", help="only the default run with frames against --no-frames")
    args = ap.parse_args(argv)
    if args.window:
        print(window_table())
        return 0
    if args.frames:
        return print_frames_overhead(3 if args.quick else 5)
    if args.worker:
        job = json.loads(args.worker)
        print(json.dumps(run_default_scene(job["tree"], job["n_seg"], job["steps"])))
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
    write_csv(path, COLUMNS, rows)
    if args.against:
        with tempfile.TemporaryDirectory(prefix="speed-against-") as folder:
            old_tree = export_tree(args.against, folder)
            comparison = compare(ROOT, old_tree, AGAINST_QUICK if args.quick else AGAINST)
        print()
        print(format_comparison(comparison, args.against))
        write_csv(os.path.join(out, "speed-against.csv"), AGAINST_COLUMNS, comparison)
    print(f"BLAS threads: OPENBLAS_NUM_THREADS={os.environ['OPENBLAS_NUM_THREADS']}")
    print(f"wrote speed.csv{' and speed-against.csv' if args.against else ''} into {out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
