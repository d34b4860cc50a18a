"""The live window keeps real time (`python -m benchmarks.speed --window`): the default scene in
the window, drawing included, at n_seg 4, 8 and 16, paced (speed 1) and flat out (speed 100), on
SDL's dummy driver and on the display at $DISPLAY where there is one.
"""
import math
import os
import subprocess
import sys
import time

from benchmarks import ROOT

WINDOW_N_SEGS = (4, 8, 16)
WINDOW_PIXELS = 652         # the window's default side on a 1024x768 projector
MEMORY_DRIVER = "dummy"     # SDL's driver that draws into memory only, no display needed
NOTE = """\
CPU/simulated: CPU seconds per simulated second (below 1: one free core keeps real time);
busy: share of the wall time not spent sleeping between frames; lowest rate: simulated over wall
time over the window's one-second spans, / speed ('-': the run was shorter than a span); at speed
100 the window steps flat out, so 'x real time' is the fastest it can run; dummy: SDL draws into
memory, x11: the frames shown on the display (the X server's own CPU time not included)"""


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
    """A run of `duration` s of the default scene in the live window at `speed` on SDL's `driver`:
    wall and CPU s per simulated s, the share of wall time busy (not sleeping), frames drawn and
    those noted 'slower than real time', and the lowest one-second rate (a fraction of speed)."""
    os.environ["SDL_VIDEODRIVER"] = driver
    sys.path.insert(0, ROOT)
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


def window_table(sizes=WINDOW_N_SEGS):
    """The window's figures at speed 1 and flat out (speed 100), on each driver found."""
    drivers = [MEMORY_DRIVER] + [d for d in [display_driver()] if d]
    where = (f"DISPLAY={os.environ.get('DISPLAY')}" if len(drivers) > 1
             else "no display found: dummy only")
    lines = [f"Live window ({WINDOW_PIXELS} px, drawing included; {where}), a 3 s run:",
             "  n_seg  driver  speed  wall/simulated s  CPU/simulated s  busy  frames  "
             "frames 'slower'  lowest rate  -> x real time"]
    for n_seg in sizes:
        for driver in drivers:
            for speed in (1.0, 100.0):
                r = window_real_time(n_seg, speed, driver=driver)
                lowest = f"{r['lowest_rate']:.2g}" if r["lowest_rate"] < math.inf else "-"
                lines.append(
                    f"  {n_seg:>5}  {driver:>6}  {speed:>5g}  {r['wall_per_simulated']:>16.3f}  "
                    f"{r['cpu_per_simulated']:>15.3f}  {100 * r['busy']:>3.0f}%  "
                    f"{r['frames']:>6}  {r['slow_frames']:>15}  {lowest:>11}  "
                    f"{1 / r['wall_per_simulated']:>6.2f}")
    return "\n".join(lines + [NOTE])
