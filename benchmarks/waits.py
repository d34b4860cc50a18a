"""What a user waits for (benchmarks.speed --frames, --chalk, --window; benchmarks/README.md):
whole `python simulator.py` processes run in turn, and the live window paced and flat out."""
import csv
import functools
import glob
import itertools
import math
import os
import platform
import re
import statistics
import subprocess
import sys
import time

from benchmarks import tables
from benchmarks.tables import ROOT

FRAMES_TARGET = 1.5        # x --no-frames, wall time (issue 42; 3 in issue 16)
CHALK_TARGET = 3.0         # wall s per simulated s (issue 28)
RUNS = {"pushed": [], "dragged": ["--drag"], "pushed, from x^n": ["--newton-start", "x_n"],
        "dragged, from x^n": ["--drag", "--newton-start", "x_n"]}
TEXT = [("python", "python", ""), ("run", "run", ""), ("simulated s", "simulated_s", "g"),
        ("wall s", "wall_s", ".2f"), ("CPU s", "cpu_s", ".2f"),
        ("stepping wall s", "stepping_wall_s", ".2f"),
        ("wall / simulated s", "wall_per_simulated_s", ".2f"),
        ("Newton/step", "newton_per_step", ".2f"), ("noise", "noise", "")]
COLUMNS = [key for _, key, _ in TEXT]       # chalk-speed.csv's
CHALK_NOTE = """\
python simulator.py --scene chalk --no-frames [flags]: whole processes (import, steps, log.csv,
plots.png, summary.png), medians of {repeats} run alternately; stepping wall: the closing line's
figure. Target for the pushed 3 s default: at most {target:g} s of wall time per simulated second:
{verdict}."""
WINDOW_PIXELS = 652         # the window's default side on a 1024x768 projector
MEMORY_DRIVER = "dummy"     # SDL's driver that draws into memory only, no display needed
WINDOW_HEAD = ("  n_seg  driver  speed  wall/simulated s  CPU/simulated s  busy  frames  "
               "frames 'slower'  lowest rate  -> x real time")
WINDOW_ROW = ("  {n_seg:>5}  {driver:>6}  {speed:>5g}  {wall_per_simulated:>16.3f}  "
              "{cpu_per_simulated:>15.3f}  {busy:>4.0%}  {frames:>6}  {slow_frames:>15}  "
              "{lowest:>11}  {real_time:>6.2f}")
WINDOW_NOTE = """\
CPU/simulated: CPU seconds per simulated second (below 1: one free core keeps real time);
busy: share of the wall time not spent sleeping between frames; lowest rate: simulated over wall
time over the window's one-second spans, / speed ('-': the run was shorter than a span); at speed
100 the window steps flat out, so 'x real time' is the fastest it can run; dummy: SDL draws into
memory, x11: the frames shown on the display (the X server's own CPU time not included)"""


def run_simulator(flags, python=sys.executable):
    """One `python simulator.py *flags` process: wall, CPU and stepping wall s (its closing line),
    Newton iterations per step and simulated s (log.csv), frames written."""
    with tables.scratch("waits-") as out:
        wall, cpu, stderr = tables.run_process(
            [python, os.path.join(ROOT, "simulator.py"), "--out", out, *flags])
        with open(os.path.join(out, "log.csv")) as f:
            steps = list(csv.DictReader(f))[1:]         # row 0 is t = 0
        frames = len(glob.glob(os.path.join(out, "frame_*.png")))
    return {"wall_s": wall, "cpu_s": cpu,
            "stepping_wall_s": float(re.search(r"in ([0-9.]+) s wall", stderr).group(1)),
            "newton_per_step": statistics.mean(int(r["newton_iterations"]) for r in steps),
            "simulated_s": float(steps[-1]["t"]), "frames": frames}


def print_frames_overhead(repeats):
    """The default run with frames and with --no-frames, in turn: medians and their ratio."""
    done = tables.in_turn({"frames": functools.partial(run_simulator, []),
                           "no-frames": functools.partial(run_simulator, ["--no-frames"])}, repeats)
    walls = [[r["wall_s"] for r in results] for results in done.values()]
    cpus = [[r["cpu_s"] for r in results] for results in done.values()]
    with_frames, without = (statistics.median(w) for w in walls)
    cpu_frames, cpu_without = (statistics.median(c) for c in cpus)
    first, ratio = done["frames"][0], with_frames / without
    verdict = "met" if ratio <= FRAMES_TARGET else "NOT met"
    print(f"python simulator.py: {with_frames:.2f} s with {first['frames']} frames "
          f"({(first['frames'] - 1) / first['simulated_s']:.1f} per simulated second), "
          f"{without:.2f} s with --no-frames (whole processes, medians of {repeats}, run "
          f"alternately): {ratio:.2f}x (target <= {FRAMES_TARGET:g}x: {verdict}; "
          f"repeats spread {100 * max(map(tables.spread, walls)):.0f}%); CPU time "
          f"{cpu_frames:.2f} s against {cpu_without:.2f} s: {cpu_frames / cpu_without:.2f}x"
          f"{load_text()}")


def load_text():
    """'; load 6.1 on 2 cores' (the last minute's load average, as the runs end), where known."""
    if not hasattr(os, "getloadavg"):
        return ""
    return f"; load {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores"


def python_version(python):
    """The version of the interpreter `python`; ValueError unless it imports the requirements."""
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
    done = tables.in_turn({(python, name): functools.partial(
        run_simulator, ["--scene", "chalk", "--no-frames", *seconds, *flags], python)
        for python in pythons for name, flags in runs.items()}, repeats)
    rows = []
    for (python, name), results in done.items():
        row = {key: statistics.median(r[key] for r in results) for key in results[0]}
        walls, cpus = ([r[key] for r in results] for key in ("wall_s", "cpu_s"))
        rows.append({"python": f"{pythons[python]} {python}", "run": name, **row,
                     "wall_per_simulated_s": row["wall_s"] / row["simulated_s"],
                     "noise": tables.noise(walls, cpus)})
    return rows


def format_chalk_table(rows, repeats):
    if rows[0]["simulated_s"] == 3.0:       # the pushed default, per interpreter
        verdict = "; ".join(
            f"{'met' if r['wall_per_simulated_s'] <= CHALK_TARGET else 'NOT met'} with Python "
            f"{r['python'].split()[0]} ({r['wall_per_simulated_s']:.2f} s)"
            for r in rows if r["run"] == rows[0]["run"])
    else:
        verdict = "not judged: a short run's start-up weighs more per simulated second"
    note = CHALK_NOTE.format(repeats=repeats, target=CHALK_TARGET, verdict=verdict)
    return "\n".join(tables.text(TEXT, rows) + [note])


class MeteredClock:
    """The window loop's clock: adds up the time it sleeps, presses the close button once the run
    is over, and notes the lowest rate the window measured."""

    def __init__(self):
        self.slept, self.window, self.end, self.lowest_rate = 0.0, None, None, math.inf

    now = staticmethod(time.perf_counter)

    def sleep(self, seconds):
        pacer, pygame = self.window.pacer, self.window.pygame
        rate = pacer.rate() if pacer.samples else None
        self.lowest_rate = min(self.lowest_rate, math.inf if rate is None else rate)
        if self.end is not None:            # the run is over: the close button is on its way
            return
        if self.window.run.finished:
            self.end = time.perf_counter()
            pygame.event.post(pygame.event.Event(pygame.QUIT))
            return
        start = time.perf_counter()
        time.sleep(seconds)
        self.slept += time.perf_counter() - start


def window_real_time(n_seg, speed=1.0, duration=3.0, driver=MEMORY_DRIVER):
    """The live window's run of the default scene at `speed` on SDL's `driver`: wall and CPU s per
    simulated s, the share of wall time not sleeping, frames (and 'slower' ones), lowest rate."""
    os.environ["SDL_VIDEODRIVER"] = driver
    import simulator
    from viewer.demo import window
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
    wall, simulated = clock.end - start, steps * scene.h
    return {"n_seg": n_seg, "speed": speed, "driver": driver,
            "wall_per_simulated": wall / simulated, "cpu_per_simulated": cpu / simulated,
            "busy": 1.0 - min(clock.slept, wall) / wall, "frames": live.frames,
            "slow_frames": live.slow_frames, "lowest_rate": clock.lowest_rate}


def display_driver():
    """"x11" where $DISPLAY names a display SDL can open (a desktop, Xvfb), else None."""
    if not os.environ.get("DISPLAY"):
        return None
    code = "import pygame; pygame.display.init(); print(pygame.display.get_driver())"
    probe = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           env={**os.environ, "SDL_VIDEODRIVER": "x11",
                                "PYGAME_HIDE_SUPPORT_PROMPT": "1"}, timeout=60)
    return "x11" if probe.returncode == 0 and probe.stdout.strip() == "x11" else None


def window_table(sizes=(4, 8, 16)):
    """The window's figures at speed 1 and flat out (speed 100), on each driver found."""
    drivers = [MEMORY_DRIVER] + [d for d in [display_driver()] if d]
    where = (f"DISPLAY={os.environ.get('DISPLAY')}" if len(drivers) > 1
             else "no display found: dummy only")
    lines = [f"Live window ({WINDOW_PIXELS} px, drawing included; {where}), a 3 s run:",
             WINDOW_HEAD]
    for n_seg, driver, speed in itertools.product(sizes, drivers, (1.0, 100.0)):
        r = window_real_time(n_seg, speed, driver=driver)
        lowest = f"{r['lowest_rate']:.2g}" if r["lowest_rate"] < math.inf else "-"
        lines.append(WINDOW_ROW.format(**r, lowest=lowest, real_time=1 / r["wall_per_simulated"]))
    return "\n".join(lines + [WINDOW_NOTE])
