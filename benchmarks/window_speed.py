"""The live window keeps real time (`python -m benchmarks.speed --window`): the default scene in the
window, drawing included, at n_seg 4, 8 and 16, paced (speed 1) and flat out, on SDL's dummy driver
and on the display at $DISPLAY where there is one.
"""
import math
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

WINDOW_N_SEGS = (4, 8, 16)
WINDOW_PIXELS = 652         # the window's default side on a 1024x768 projector (viewer.demo.window.FIT)
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
    """A 3 s run of the default scene in the live window at `speed`, drawing included, on SDL video driver
    `driver` (the dummy one draws into memory; x11 shows it on $DISPLAY, a desktop or Xvfb): wall
    seconds per simulated second (1/speed when it keeps up), CPU seconds per simulated
    second (what it needs of one core, whatever else the machine runs), the share of the wall time the
    loop was busy (not sleeping), frames drawn and those with the 'slower than real time' note, and
    the lowest rate the window measured (over its one-second spans, as a fraction of speed)."""
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
    lines = [f"Live window ({WINDOW_PIXELS} px, drawing included; {where}), a 3 s run:",
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
