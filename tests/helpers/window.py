"""The live window as the tests drive it: events posted into its loop under SDL's dummy driver, a
fake wall clock (ScriptClock) so nothing waits on real time, and what the window's tests read."""
import csv
import io
import random

import numpy as np
import pytest

import simulator
import time_integrator
from viewer.command import cli, run
from viewer.demo import window

H = simulator.DEFAULTS["h"]
needs_newton_hook = pytest.mark.skipif(
    not hasattr(time_integrator, "newton_iterates"),
    reason="time_integrator.newton_iterates (the Newton-iteration hook) not there yet")


def pygame():
    import pygame
    return pygame


def post(event_type, **attributes):
    pygame().event.post(pygame().event.Event(event_type, **attributes))


def press(key_name):
    pg = pygame()
    post(pg.KEYDOWN, key=getattr(pg, key_name))


class ScriptClock:
    """A fake wall clock for the window's loop: sleep() moves it on, then runs the test's script up
    to its next `yield` (one frame of the loop), where the script posts events and checks the
    window. When the script ends, the close button is pressed; a loop outliving max_frames fails."""

    def __init__(self, script=None, max_frames=20000):
        self.t, self.script, self.frames, self.max_frames = 0.0, script, 0, max_frames
        self.frame_end = 0.0                # the time the last frame's sleep began

    def now(self):
        return self.t

    def sleep(self, seconds):
        self.frame_end = self.t
        self.t += seconds
        self.frames += 1
        assert self.frames < self.max_frames, "the window's loop did not end"
        if self.script is not None:
            try:
                next(self.script)
            except StopIteration:
                self.script = None
                post(pygame().QUIT)



class LoadedClock(ScriptClock):
    """A ScriptClock on a loaded machine: each reading finds it moved on by a random while, up to
    `most` s (seeded), as if the steps, the drawing and other processes took that time; the loop
    falls behind, drops the window's frames and catches up as on a busy machine."""

    def __init__(self, script=None, seed=0, most=0.05, max_frames=20000):
        super().__init__(script, max_frames)
        self.rng, self.most = random.Random(seed), most

    def now(self):
        self.t += self.rng.uniform(0.0, self.most)
        return self.t

def live_window(scene=None, steps=300, speed=1.0, size=400, recorder=None):
    """A LiveWindow on the dummy display with a ScriptClock (give it its script, then loop())."""
    pg = window.open_display()
    screen = pg.display.set_mode((size, size))
    clock = ScriptClock()
    scene = scene or simulator.build_scene()
    return window.LiveWindow(pg, screen, scene, steps, speed, recorder, clock), clock


def frames_until(condition, limit=5000):
    """Yield frames until condition() holds."""
    for _ in range(limit):
        if condition():
            return
        yield
    raise AssertionError("condition never reached")


def run_window(argv, **kw):
    """viewer.demo.window.run_window as the command line calls it, for `argv`."""
    (args,) = cli.parse_command_line(argv)
    with run.Signals() as signals:
        return window.run_window(cli.plan_from_args([args]), args.speed, args.size, signals, **kw)


def hidden(folder):
    """The folder's names starting with '.': temporary files left over."""
    return [p.name for p in folder.iterdir() if p.name.startswith(".")]


def read_log(folder):
    with open(folder / "log.csv") as f:
        return list(csv.DictReader(f))


def differing_pixels(a, b):
    """Where two pictures (arrays [x, y, rgb], or PNG bytes) differ, in words: how many pixels, the
    box holding them, the first one's colour in each; what a failed comparison says."""
    if isinstance(a, bytes):
        a, b = (pygame().surfarray.array3d(pygame().image.load(io.BytesIO(p))) for p in (a, b))
    if a.shape != b.shape:
        return f"sizes differ: {a.shape} and {b.shape}"
    where = np.argwhere((a != b).any(axis=2))
    if not len(where):
        return "no pixel differs"
    (x0, y0), (x1, y1), (x, y) = where.min(axis=0), where.max(axis=0), where[0]
    return (f"{len(where)} px differ in x {x0}..{x1}, y {y0}..{y1}; first ({x}, {y}): "
            f"{tuple(a[x, y].tolist())} against {tuple(b[x, y].tolist())}")
