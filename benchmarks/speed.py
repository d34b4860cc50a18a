"""Speed of the time step, and how far it is above the floor, the sparse factorization.

For each n_seg the slope scene is stepped through a fixed window of time steps after the impact:
steps per second, Newton iterations and factorizations per step, the time per step split into
energy + assembly, linear solve, convergence proofs, line search and the rest, the ratio of the time
per step to (factorizations, and to Newton iterations, x one factorization-and-solve of that step's
matrix, timed after the window), the same ratio against the factorizations and solves the window's
own steps ran (timed as they ran, so at the same moment), and the peak memory. For the lecture's
dropped square (n_seg <= 32) it also times the whole default run (3 s, 300 steps; the median of 5
runs up to n_seg 8, one run above), to compare with the lecture's loop-based code. Steps are taken
as simulator.simulate takes them (each handed the previous step's report).

    python -m benchmarks.speed               # n_seg 4 ... 128, about two minutes
    python -m benchmarks.speed --quick       # a smoke run: n_seg 4 and 8, a few steps, a few seconds
    python -m benchmarks.speed --sizes 4,32  # some sizes only

Each size runs in its own Python process, so the peak memory (ru_maxrss) is that size's own. BLAS
runs on one thread unless OPENBLAS_NUM_THREADS says otherwise: on a shared 2-core machine a second
BLAS thread gains at most 20 % on the banded factorization and sometimes loses 10x to contention.
Timings are medians over repeats of the same window (same state, same work); a figure is marked
noisy when the repeats spread by more than 20 % or the process waited for a CPU more than 15 % of
the time (wall / CPU time > 1.15): such a figure says more about the machine than the code.
"""
import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")     # before numpy loads OpenBLAS

import argparse
import csv
import io
import json
import math
import resource
import statistics
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

import BarrierEnergy       # noqa: E402  (the project's flat modules, after the path is set)
import simulator           # noqa: E402
import time_integrator     # noqa: E402
import utils               # noqa: E402

# The lecture's loop-based code on these machines (issues A and B): ms per step, ms per Newton iteration.
LECTURE = {4: (15.0, None), 16: (830.0, 77.0), 32: (7500.0, 289.0)}

# n_seg: (scene, steps before the window, window steps, repeats, factorization repeats)
FULL = {4: ("drop", 110, 200, 5, 20), 8: ("drop", 110, 100, 5, 20), 16: ("drop", 110, 50, 5, 10),
        32: ("drop", 110, 20, 5, 10), 64: ("slide", 5, 10, 3, 5), 128: ("slide", 5, 4, 3, 3)}
QUICK = {4: ("drop", 40, 10, 3, 3), 8: ("drop", 40, 5, 3, 3)}
RUN_STEPS = {"full": 300, "quick": 60}     # the whole default run, timed for the drop scenes:
RUN_REPEATS, RUN_REPEAT_MAX_N_SEG = 5, 8        # the median of 5 up to n_seg 8, once above
DROP_CAP = 1000     # Newton iteration cap for the drop: the impact needs > 100 at n_seg >= 16
SPREAD_LIMIT, WAIT_LIMIT = 0.20, 1.15

COLUMNS = ["n_seg", "dof", "scene", "solver", "steps_per_s", "ms_per_step", "newton_per_step",
           "factorizations_per_step", "energy_assembly_ms", "solve_ms", "proof_ms", "line_search_ms", "rest_ms",
           "one_factor_solve_ms", "ratio_per_factorization", "ratio_per_newton", "in_step_factor_solve_ms",
           "ratio_per_newton_in_step", "peak_mb", "run_ms_per_step", "run_newton_per_step",
           "lecture_ms_per_step", "lecture_ms_per_newton", "noise"]


# ------------------------------------------------------------------------------------------------
# Scenes
# ------------------------------------------------------------------------------------------------

def drop_scene(n_seg):
    """The lecture's default scene (the square dropped onto the slope) at this n_seg."""
    return simulator.build_scene(n_seg=n_seg, max_newton_iterations=DROP_CAP)


def slide_scene(n_seg, d0=0.008, speed=0.43):
    """The same slope and parameters, but the square starts on the slope, aligned with it (bottom
    row at d0 < dhat), sliding down at `speed` m/s, as the dropped square does after its impact:
    the window after the impact without paying for the impact (minutes at n_seg 64, hours at 128)."""
    theta = math.atan(0.1)
    probe = simulator.build_scene(n_seg=n_seg, angle=-theta, center=(0.0, 1.0))
    d = BarrierEnergy.distances(probe.x0, probe.n, probe.o)
    tangent = np.array([probe.n[1], -probe.n[0]])
    return simulator.build_scene(n_seg=n_seg, angle=-theta, center=(0.0, 1.0 - (d.min() - d0) / probe.n[1]),
                                 v0=tuple(speed * tangent))


# ------------------------------------------------------------------------------------------------
# Timing (in the worker process of one size)
# ------------------------------------------------------------------------------------------------

PHASES = {  # (owner, attribute): phase; a call inside another timed call counts for its own phase only
    (time_integrator.IncrementalPotential, "evaluate"): "energy_assembly",
    (utils.BlockPattern, "matrix"): "energy_assembly",
    (utils.BlockPattern, "to_csc"): "energy_assembly",
    (utils.BlockPattern, "factor"): "solve",
    (utils.BlockPattern, "solve"): "solve",
    (time_integrator.NewtonSystem, "_cg_bound"): "proof",
    (time_integrator.IncrementalPotential, "val"): "line_search",
    (time_integrator, "_init_step_size"): "line_search",
}


class PhaseTimer:
    """Wraps the functions of PHASES to add up their own wall time per phase (a timed call's time
    less that of the timed calls inside it), keeps the slot values of the last matrix built (to time
    its factorization afterwards), and the time of every factorization and triangular solve as the
    steps ran them."""

    def __init__(self):
        self.seconds = dict.fromkeys(PHASES.values(), 0.0)
        self.calls = {"factor": [], "solve": []}
        self.last_upper = None
        self.inner = []             # per open timed call: the time spent in timed calls inside it
        self.originals = {key: getattr(*key) for key in PHASES}

    def __enter__(self):
        for (owner, name), phase in PHASES.items():
            setattr(owner, name, self._wrap(self.originals[owner, name], phase, name))
        return self

    def __exit__(self, *exc):
        for (owner, name), original in self.originals.items():
            setattr(owner, name, original)

    def _wrap(self, f, phase, name):
        def timed(*args, **kw):
            if name == "matrix":
                self.last_upper = args[1]
            self.inner.append(0.0)
            start = time.perf_counter()
            try:
                return f(*args, **kw)
            finally:
                elapsed = time.perf_counter() - start
                self.seconds[phase] += elapsed - self.inner.pop()
                if name in self.calls:
                    self.calls[name].append(elapsed)
                if self.inner:
                    self.inner[-1] += elapsed
        return timed


def run_window(scene, x, v, steps, first_index, previous):
    """Step `steps` times from (x, v), as simulator.simulate does (each step handed the previous
    one's report); returns wall and CPU seconds, Newton iterations and factorizations."""
    wall, cpu, newton, factorizations = time.perf_counter(), time.process_time(), 0, 0
    report = previous
    for i in range(steps):
        x, v, report = time_integrator.step(scene, x, v, first_index + i, report)
        newton += report.newton_iterations
        factorizations += report.factorizations
    return time.perf_counter() - wall, time.process_time() - cpu, newton, factorizations


def time_factor_solve(pattern, upper, repeats):
    """Median wall time of one factorization-and-solve of the matrix with slot values `upper`."""
    b, times = np.ones(pattern.n_dofs), []
    for _ in range(repeats):
        A = pattern.matrix(upper)
        start = time.perf_counter()
        pattern.factor_solve(A, b)
        times.append(time.perf_counter() - start)
    return statistics.median(times), spread(times)


def spread(values):
    return (max(values) - min(values)) / statistics.median(values)


def measure(n_seg, scene_kind, warm, steps, repeats, fs_repeats, run_steps):
    """All figures of one size (runs in the worker process)."""
    scene = drop_scene(n_seg) if scene_kind == "drop" else slide_scene(n_seg)
    x, v, report, out = scene.x0, scene.v0, None, {}
    if scene_kind == "drop":              # the whole default run; the window starts inside it
        runs, saved = [], None
        for _ in range(RUN_REPEATS if n_seg <= RUN_REPEAT_MAX_N_SEG else 1):
            x, v, report = scene.x0, scene.v0, None
            wall, newton = time.perf_counter(), 0
            for i in range(max(run_steps, warm)):
                if i == warm:
                    saved = (x, v, report)
                x, v, report = time_integrator.step(scene, x, v, i, report)
                if i < run_steps:
                    newton += report.newton_iterations
                if i + 1 == run_steps:
                    runs.append(time.perf_counter() - wall)
        out["run_ms_per_step"] = 1e3 * statistics.median(runs) / run_steps
        out["run_steps"] = run_steps
        out["run_newton_per_step"] = newton / run_steps
        x, v, report = saved if saved is not None else (x, v, report)
    else:
        for i in range(warm):
            x, v, report = time_integrator.step(scene, x, v, i, report)

    # the split: instrumented runs of the window, keeping three of its matrices to factor below, and
    # the in-step ratio: the window's time over its own factorizations and solves, timed as they ran
    phases, uppers, in_step = [], [], []
    for _ in range(repeats):
        timer = PhaseTimer()
        xs, vs, previous, newton = x, v, report, 0
        with timer:
            wall = time.perf_counter()
            for i in range(steps):
                xs, vs, previous = time_integrator.step(scene, xs, vs, warm + i, previous)
                newton += previous.newton_iterations
                if i in (0, steps // 2, steps - 1) and len(uppers) < 3:
                    uppers.append(timer.last_upper)
            wall = time.perf_counter() - wall
        phases.append(timer.seconds)
        fs = statistics.fmean(timer.calls["factor"]) + statistics.median(timer.calls["solve"])
        in_step.append((fs, wall / (newton * fs)))
    # the clean window, each repeat followed at once by one factorization-and-solve of one of those
    # matrices: a ratio compares two times taken while the machine ran at the same speed
    clean, fs_times, fs_spreads = [], [], []
    for r in range(repeats):
        clean.append(run_window(scene, x, v, steps, warm, report))
        fs, fs_spread = time_factor_solve(scene.pattern, uppers[r % len(uppers)], fs_repeats)
        fs_times.append(fs)
        fs_spreads.append(fs_spread)
    walls, cpus = [c[0] for c in clean], [c[1] for c in clean]
    per_step = statistics.median(walls) / steps
    one_fs = statistics.median(fs_times)
    newton, factorizations = clean[0][2] / steps, clean[0][3] / steps

    def ratio(per):
        return statistics.median(w / steps / (per * fs) for w, fs in zip(walls, fs_times)) if per else math.inf
    out.update(
        n_seg=n_seg, dof=scene.pattern.n_dofs, scene=scene_kind, solver=scene.pattern.solver,
        steps_per_s=1.0 / per_step, ms_per_step=1e3 * per_step, newton_per_step=newton,
        factorizations_per_step=factorizations, one_factor_solve_ms=1e3 * one_fs,
        ratio_per_factorization=ratio(factorizations), ratio_per_newton=ratio(newton),
        in_step_factor_solve_ms=1e3 * statistics.median(f for f, _ in in_step),
        ratio_per_newton_in_step=statistics.median(r for _, r in in_step),
        peak_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0)
    for phase in ("energy_assembly", "solve", "proof", "line_search"):
        out[f"{phase}_ms"] = 1e3 * statistics.median(p[phase] for p in phases) / steps
    instrumented = statistics.median(sum(p.values()) for p in phases) / steps
    out["rest_ms"] = 1e3 * max(per_step - instrumented, 0.0)
    out["noise"] = noise_verdict(walls, cpus, statistics.median(fs_spreads))
    return out


def noise_verdict(walls, cpus, fs_spread):
    """'ok', or why the machine was too noisy for the figures of this size to mean much."""
    reasons = []
    if spread(walls) > SPREAD_LIMIT:
        reasons.append(f"repeats spread {100 * spread(walls):.0f}%")
    if fs_spread > SPREAD_LIMIT:
        reasons.append(f"factorizations spread {100 * fs_spread:.0f}%")
    wait = statistics.median(walls) / statistics.median(cpus)
    if wait > WAIT_LIMIT:
        reasons.append(f"wall/CPU {wait:.2f}")
    return "NOISY: " + ", ".join(reasons) if reasons else "ok"


# ------------------------------------------------------------------------------------------------
# The table
# ------------------------------------------------------------------------------------------------

def run_size(n_seg, config, mode):
    """Measure one size in a fresh Python process; its figures as a dict."""
    job = json.dumps({"n_seg": n_seg, "config": list(config), "run_steps": RUN_STEPS[mode]})
    done = subprocess.run([sys.executable, "-m", "benchmarks.speed", "--worker", job], cwd=ROOT,
                          capture_output=True, text=True, env={**os.environ, "OPENBLAS_NUM_THREADS":
                                                                os.environ["OPENBLAS_NUM_THREADS"]})
    if done.returncode != 0:
        raise RuntimeError(f"n_seg {n_seg} failed:\n{done.stderr}")
    row = json.loads(done.stdout.strip().splitlines()[-1])
    lecture = LECTURE.get(n_seg, (None, None)) if config[0] == "drop" else (None, None)
    row["lecture_ms_per_step"], row["lecture_ms_per_newton"] = lecture
    return row


def fmt(value, digits=3):
    if value is None:
        return "-"
    if isinstance(value, str):
        return value
    if isinstance(value, int):
        return str(value)
    if value >= 100:
        return f"{value:.0f}"
    return f"{value:.{digits}g}"


def format_table(rows):
    """The table as printed: one line per n_seg, then the notes."""
    head = ["n_seg", "DOF", "scene", "solver", "steps/s", "ms/step", "Newton/step", "fact/step",
            "energy+asm", "solve", "proof", "line srch", "rest", "1 f+s ms", "t/(fact*f+s)", "t/(Newton*f+s)",
            "f+s in step", "t/(Newton*f+s in step)", "peak MB", "noise"]
    keys = ["n_seg", "dof", "scene", "solver", "steps_per_s", "ms_per_step", "newton_per_step",
            "factorizations_per_step", "energy_assembly_ms", "solve_ms", "proof_ms", "line_search_ms", "rest_ms",
            "one_factor_solve_ms", "ratio_per_factorization", "ratio_per_newton", "in_step_factor_solve_ms",
            "ratio_per_newton_in_step", "peak_mb", "noise"]
    cells = [head] + [[fmt(r[k]) for k in keys] for r in rows]
    widths = [max(len(c[i]) for c in cells) for i in range(len(head))]
    lines = ["  ".join(c.rjust(w) if i < len(head) - 1 else c for i, (c, w) in enumerate(zip(line, widths)))
             for line in cells]
    lines.insert(1, "-" * len(lines[0]))
    return "\n".join(lines + [""] + notes(rows))


def notes(rows):
    out = ["energy+asm, solve, proof, line srch, rest: ms per step (an instrumented run of the same window);",
           "energy+asm: E, grad E and H at the line search's first trials, H's band or CSC form; solve: factorizations",
           "and triangular solves; proof: the rest of the conjugate-gradient convergence checks; line srch: CCD",
           "and halved trials;",
           "fact = factorizations per step: one per Newton direction, plus one per solve for the final",
           "convergence check unless that was shown without one (time_integrator.NewtonSystem);",
           "1 f+s = one factorization-and-solve of that step's matrix with the solver the simulator uses, timed",
           "right after each clean window (the median of several on the same matrix);",
           "f+s in step = the mean factorization plus the median triangular solve, as the instrumented window's",
           "steps ran them: the ratio beside it divides that window's time by them, so both were measured at",
           "the same moment (the machine's speed drifts between a window and a timing after it);",
           "drop: the lecture's default scene, steps 110.. after the impact; slide: square placed on the slope,",
           "sliding at 0.43 m/s (the speed after the impact), steps 5..; peak MB: the process's max RSS."]
    lecture = [r for r in rows if r.get("run_ms_per_step") is not None]
    if lecture:
        steps = lecture[0]["run_steps"]
        what = "3 s = 300 steps incl. the impact" if steps == RUN_STEPS["full"] else f"its first {steps} steps"
        out.append(f"Whole default run ({what}; median of {RUN_REPEATS} runs up to n_seg "
                   f"{RUN_REPEAT_MAX_N_SEG}, one above) vs the lecture's loop-based code:")
    for r in lecture:
        ms_per_newton = r["run_ms_per_step"] / r["run_newton_per_step"]
        line = (f"  n_seg {r['n_seg']:>3}: {1e3 / r['run_ms_per_step']:.0f} steps/s, {r['run_ms_per_step']:.3g} ms/step, "
                f"{r['run_newton_per_step']:.3g} "
                f"Newton/step, {ms_per_newton:.3g} ms/Newton")
        if r["lecture_ms_per_step"] is not None:
            line += f"; lecture {r['lecture_ms_per_step']:.4g} ms/step: {r['lecture_ms_per_step'] / r['run_ms_per_step']:.0f}x"
        if r["lecture_ms_per_newton"] is not None:
            line += (f"; lecture {r['lecture_ms_per_newton']:.3g} ms/Newton: "
                     f"{r['lecture_ms_per_newton'] / ms_per_newton:.0f}x")
        out.append(line)
    noisy = [str(r["n_seg"]) for r in rows if r["noise"] != "ok"]
    if noisy:
        out.append(f"NOISY machine for n_seg {', '.join(noisy)}: those timings do not mean much; rerun when it is quiet.")
    out.append(f"BLAS threads: OPENBLAS_NUM_THREADS={os.environ['OPENBLAS_NUM_THREADS']}")
    return out


def write_csv(path, rows):
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(COLUMNS)
    for r in rows:
        writer.writerow([f"{r[c]:.6g}" if isinstance(r.get(c), float) else ("" if r.get(c) is None else r[c])
                         for c in COLUMNS])
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w") as f:
        f.write(buffer.getvalue())


# ------------------------------------------------------------------------------------------------
# The live window keeps real time (python -m benchmarks.speed --window)
# ------------------------------------------------------------------------------------------------

WINDOW_N_SEGS = (4, 8)
WINDOW_PIXELS = 652         # the window's default side on a 1024x768 projector (viewer.window.FIT)


class MeteredClock:
    """The wall clock for the window's loop, adding up the time it sleeps (its idle time); it presses
    the close button once the run is over, and notes the lowest rate the window measured."""

    def __init__(self):
        self.slept, self.window, self.end, self.lowest_rate = 0.0, None, None, math.inf

    now = staticmethod(time.perf_counter)

    def sleep(self, seconds):
        rate = self.window.pacer.rate() if self.window.pacer.samples else None
        self.lowest_rate = min(self.lowest_rate, math.inf if rate is None else rate)
        if self.window.run.finished and self.end is None:
            self.end = time.perf_counter()
            self.window.pygame.event.post(self.window.pygame.event.Event(self.window.pygame.QUIT))
        start = time.perf_counter()
        time.sleep(seconds)
        self.slept += time.perf_counter() - start


def window_real_time(n_seg, speed=1.0, duration=3.0):
    """The default run (3 s) in the live window at `speed`, drawing included, under SDL's dummy video
    driver: wall seconds per simulated second (1/speed when it keeps up), CPU seconds per simulated
    second (what it needs of one core, whatever else the machine runs), the share of the wall time the
    loop was busy (not sleeping), frames drawn and those with the 'slower than real time' note, and
    the lowest rate the window measured (over its one-second spans, as a fraction of speed)."""
    os.environ["SDL_VIDEODRIVER"] = "dummy"
    from viewer import window
    scene = drop_scene(n_seg)
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
    return {"n_seg": n_seg, "speed": speed, "wall_per_simulated": wall / (steps * scene.h),
            "cpu_per_simulated": cpu / (steps * scene.h),
            "busy": 1.0 - min(clock.slept, wall) / wall, "frames": live.frames, "slow_frames": live.slow_frames,
            "lowest_rate": clock.lowest_rate}


def window_table(sizes=WINDOW_N_SEGS):
    """The window's real-time figures at speed 1, and flat out (speed 100: as fast as it can go)."""
    lines = [f"Live window ({WINDOW_PIXELS} px, SDL dummy driver, drawing included), the default 3 s run:",
             "  n_seg  speed  wall/simulated s  CPU/simulated s  busy  frames  frames 'slower'  lowest rate  "
             "-> x real time"]
    for n_seg in sizes:
        for speed in (1.0, 100.0):
            r = window_real_time(n_seg, speed)
            lines.append(f"  {n_seg:>5}  {speed:>5g}  {r['wall_per_simulated']:>16.3f}  {r['cpu_per_simulated']:>15.3f}  "
                         f"{100 * r['busy']:>3.0f}%  "
                         f"{r['frames']:>6}  {r['slow_frames']:>15}  {fmt(r['lowest_rate'], 2) if r['lowest_rate'] < math.inf else '-':>11}  "
                         f"{1 / r['wall_per_simulated']:>6.2f}")
    lines.append("CPU/simulated: CPU seconds per simulated second (below 1: one free core keeps real time);")
    lines.append("busy: share of the wall time not spent sleeping between frames; lowest rate: simulated over wall")
    lines.append("time over the window's one-second spans, / speed ('-': the run was shorter than a span); at speed")
    lines.append("100 the window steps flat out, so 'x real time' is the fastest it can run")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m benchmarks.speed", description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="smoke run: n_seg 4 and 8, few steps")
    ap.add_argument("--sizes", help="comma-separated n_seg values (default: all of the mode)")
    ap.add_argument("--csv", help="CSV path (default benchmarks/results/speed.csv, --quick: benchmarks/out/)")
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--window", action="store_true", help="only the live window's real-time figures (n_seg 4, 8)")
    args = ap.parse_args(argv)
    if args.window:
        print(window_table())
        return 0
    if args.worker:
        job = json.loads(args.worker)
        print(json.dumps(measure(job["n_seg"], *job["config"], run_steps=job["run_steps"])))
        return 0
    mode = "quick" if args.quick else "full"
    configs = QUICK if args.quick else FULL
    sizes = [int(s) for s in args.sizes.split(",")] if args.sizes else list(configs)
    rows = []
    for n_seg in sizes:
        config = configs.get(n_seg) or (("drop", 110, 10, 3, 5) if n_seg <= 32 else ("slide", 5, 3, 3, 3))
        rows.append(run_size(n_seg, config, mode))
        print(f"n_seg {n_seg}: {rows[-1]['ms_per_step']:.3g} ms/step", file=sys.stderr, flush=True)
    table = format_table(rows)
    print(table)
    path = args.csv or os.path.join(ROOT, "benchmarks", "out" if args.quick else "results",
                                    "speed-quick.csv" if args.quick else "speed.csv")
    write_csv(path, rows)
    print(f"CSV: {os.path.relpath(path, ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
