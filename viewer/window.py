"""The live window, `python simulator.py --window`: the run as it is computed, paced to wall-clock time,
for an instructor to drive in front of a class, down to one Newton iteration.

Keys: space pauses and resumes; while paused, the right arrow advances one time step and n one Newton
iteration of the current step (the iterate, the direction p at each node, the CCD bound on alpha, the
accepted alpha after halving, ||p||_inf / h against tol: Algorithm 4 happening); r restarts from the
initial state; Esc, q or the window's close button end the run. At the end of the run the window
stays open on the last frame until closed.

The frames are drawn by viewer.draw, as in the files (the slope's marks, the contact forces). Files
are written only when --out is given: then those of a run without the window, by viewer.recording,
each step once (the run is deterministic: after a restart the steps computed again are the same).
"""
import contextlib
from dataclasses import dataclass
import math
import os
import sys
import time
from collections import deque

import numpy as np

import BarrierEnergy
import time_integrator
from simulator import StepRecord
from viewer import diagnostics, draw, files, frames, progress, recording, run as orchestration

FPS = 60                  # frames drawn per second at most
MIN_FPS = 20              # ... and at least, when the steps fall behind (the other frames are dropped)
FRAME_BUDGET = 1.0 / 30   # s of stepping before the loop draws and reads the keys again
FIT = 0.85                # by default the window's side is this fraction of the display's smaller side,
                          # leaving room for the title bar and desktop panels (652 px on 1024x768)
MIN_SIZE, MAX_SIZE = 300, 16384   # px; 16384 is the largest texture common graphics drivers accept
DUE_SLACK = 1e-9          # of a step: t + h and the time due may differ by round-off
CATCH_UP = 0.1            # s of wall time the steps may fall behind and catch up (a slow step, a busy CPU)
SLOW = 0.9                # "slower than real time" below this fraction of the asked speed
HINT = 0.035              # the Newton view's arrows (the direction of p) are this fraction of the window long,
HINT_FLOOR = 0.01         # ... drawn where |p_k| is at least this fraction of the largest
INSET = 0.4               # the Newton view's inset: its width at most this fraction of the window's,
MIN_INSET = 0.25          # ... and at least this, over the square where there is no more room beside it,
INSET_TALL = 0.6          # ... its height at most this fraction of the window's,
INSET_FILL = 0.75         # ... the node's x^i, x^i + p (and its foot on the slope) filling this much of it,
SLOPE_REACH = 1.5         # ... the slope framed where the node is within this many |p_k| of it (the CCD
                          #     bound can only come from a node within |p_k| / 0.9)
MAX_ZOOM = 1e4            # ... magnified at most this much (p_k = 0 would ask for infinitely much)
ZOOMS = (1, 2, 3, 5)      # ... by one of these times a power of ten
GROUND = (219, 219, 255)  # the inset's tint below the slope
# SDL's drivers that draw into memory only: it falls back to one of them when it finds no display
MEMORY_DRIVERS = ("dummy", "offscreen")

# the colours of text have a WCAG contrast ratio of at least 4.5:1 against the white background (AA for
# text, tests/test_window.py): black 21, RED 6.1, GREEN 5.1, KEYS 5.9, draw.BLUE 8.6; GREY (2.3:1) draws
# only the iterate x^i
BLACK, GREY, RED, GREEN = (0, 0, 0), (170, 170, 170), (200, 0, 0), (0, 128, 0)
KEYS = (100, 100, 100)    # the key hints at the bottom


class WallClock:
    """Wall-clock time for the pacing; tests hand the window a fake clock with the same two methods."""
    now = staticmethod(time.perf_counter)
    sleep = staticmethod(time.sleep)


# ------------------------------------------------------------------------------------------------
# The run: where it is, one step or one Newton iteration at a time
# ------------------------------------------------------------------------------------------------

class LiveRun:
    """The state (x, v) after `index` time steps, and the Newton iterations of the step in progress.

    A step is taken whole by `time_integrator.step`, or one Newton iteration at a time by the
    generator `time_integrator.newton_iterates` (the same step, so the same x^{n+1})."""

    def __init__(self, scene, steps):
        self.scene, self.steps = scene, steps
        self.restart()

    def restart(self):
        self.index, self.x, self.v = 0, self.scene.x0.copy(), self.scene.v0.copy()
        self.report = None          # the last step's StepReport (its friction force), None at t = 0
        self.iterates = None        # the generator of the step in progress, after n
        self.iterate = None         # its last NewtonIterate
        self.iteration = 0          # how many it has yielded
        self.iterates_wall = 0.0    # the seconds computing them took

    @property
    def t(self):
        return self.index * self.scene.h

    @property
    def finished(self):
        return self.index >= self.steps

    @property
    def shown_x(self):
        """What the window draws: the last Newton iterate within a step, else x^n."""
        return self.x if self.iterate is None else self.iterate.x_next

    def step(self):
        """Complete the current time step (finishing one begun by n); returns its StepRecord."""
        start = time.perf_counter()
        if self.iterates is None:
            x, v, report = time_integrator.step(self.scene, self.x, self.v, step_index=self.index)
        else:
            x, v, report = time_integrator.run_out(self.iterates)
        return self._advance(x, v, report, time.perf_counter() - start)

    def newton_iteration(self):
        """One Newton iteration of the current step: the StepRecord when that completes the step
        (Newton converged at the last iterate), else None (the iterate is in `self.iterate`)."""
        if self.iterates is None:
            self.iterates = time_integrator.newton_iterates(self.scene, self.x, self.v, step_index=self.index)
        start = time.perf_counter()
        try:
            self.iterate = next(self.iterates)
            self.iteration += 1
            return None
        except StopIteration as done:
            x, v, report = done.value
            return self._advance(x, v, report, 0.0)
        finally:
            self.iterates_wall += time.perf_counter() - start

    def _advance(self, x, v, report, wall):
        """The step is done: x^{n+1}, v^{n+1}; its record, with the seconds computing it took (those
        of its iterations too, when n took them one at a time)."""
        record = StepRecord(self.index, (self.index + 1) * self.scene.h, x, v, report, wall + self.iterates_wall)
        self.index += 1
        self.report, self.x, self.v = report, x, v
        self.iterates, self.iterate, self.iteration, self.iterates_wall = None, None, 0, 0.0
        return record


# ------------------------------------------------------------------------------------------------
# Pacing: simulated time at `speed` times wall-clock time
# ------------------------------------------------------------------------------------------------

class Pacer:
    """Simulated time due now: t_0 + speed (now - wall_0), from the last (re)start at (wall_0, t_0).

    The loop takes the steps whose end is due, catching up after a slow step; where it falls further
    behind than CATCH_UP it goes on from where it is instead (no rush to catch up), and `rate()` says
    how fast it went: simulated seconds per wall second over the last `span` seconds of play, as a
    fraction of `speed`."""

    def __init__(self, clock, speed, h):
        self.clock, self.speed = clock, speed
        self.span = max(1.0, 40 * h / speed)    # a rate over half of it is within 5 % (one step)
        self.samples = deque()                  # (wall, t) at each frame of play
        self.start(0.0)

    def start(self, t):
        """Play from simulated time t now (at a resume, a restart, or after falling behind)."""
        self.wall_0, self.t_0 = self.clock.now(), t

    def due(self):
        return self.t_0 + self.speed * (self.clock.now() - self.wall_0)

    def forget(self):
        """Pauses and restarts are not play: the rate is measured afresh after them."""
        self.samples.clear()

    def sample(self, t):
        now = self.clock.now()
        self.samples.append((now, t))
        while now - self.samples[0][0] > self.span:
            self.samples.popleft()

    def rate(self):
        """Simulated over wall time across the last span of play, / speed; None before a span."""
        (wall_a, t_a), (wall_b, t_b) = self.samples[0], self.samples[-1]
        if wall_b - wall_a < 0.5 * self.span:
            return None
        return (t_b - t_a) / (wall_b - wall_a) / self.speed


# ------------------------------------------------------------------------------------------------
# Files, only with --out
# ------------------------------------------------------------------------------------------------

class Files:
    """What a run without the window writes, written by the same code (viewer.recording) into `folder`
    (files.OutputFolder): log.csv a row as each step ends, a frame and OBJ every `stride` steps (unless
    --no-frames), and at the end summary.png, plots.png and index.html. Each step is written once: the
    steps computed again after a restart (r) are the same numbers and are not written again, so the
    files hold the furthest the run got."""

    def __init__(self, plan, folder, log):
        self.plan, self.frame_log = plan, []
        self.track = recording.Track(plan.scenes[0], plan.steps[0], None, plan.labels[0], "", draw.run_color(0), folder)
        self.progress = progress.Progress([self.track], log)
        self.writer = frames.FrameWriter([self.track], folder, plan.forces, self.frame_log) if plan.frames else None
        if self.writer is not None:
            self.writer.write(0)

    def record(self, record):
        """Write a completed step: its log.csv row, and its frame when one is due (frame j at step
        j stride, the last at the run's last step, as frames.frame_steps numbers them)."""
        track, stride = self.track, self.plan.stride
        if record.index != track.step:          # computed before a restart: written then
            return
        track.take(record, self.progress)
        if self.writer is not None and (track.step % stride == 0 or track.step == track.steps):
            self.writer.write(-(-track.step // stride))


# ------------------------------------------------------------------------------------------------
# The window
# ------------------------------------------------------------------------------------------------

class LiveWindow:
    """The demo loop: read the keys, take the steps that are due, draw, wait for the next frame."""

    def __init__(self, pygame, screen, scene, steps, speed=1.0, output=None, clock=None, log=None,
                 label=None, forces=True):
        self.pygame, self.screen, self.scene, self.log = pygame, screen, scene, log or sys.stderr
        self.size = screen.get_width()
        self.clock = clock or WallClock()
        self.run = LiveRun(scene, steps)
        self.speed, self.output = speed, output     # output: the Files written, or None
        self.label = label or f"mu = {scene.mu:g}"
        self.newton_per_metre = draw.newton_per_metre(scene) if forces else None
        self.pacer = Pacer(self.clock, speed, scene.h)
        self.view = draw.View(draw.SCALE * self.size / draw.RESOLUTION, self.size)   # the lecture's 4.5 m across
        self.fonts = draw.fonts(pygame, self.size)      # the frames' (title, text), at the window's size
        self.font = self.fonts[1]                       # the status lines and the key hints
        self.playing, self.done = True, False
        self.failure = None         # the SimulationError that stopped the run, if one did
        self.write_error = None     # the OSError that stopped the files, if one did
        self.message = None         # what the last key did, shown until the next key
        self.slow = None            # the rate reached, when below SLOW of the asked speed
        self.slow_frames = 0        # frames drawn with the "slower than real time" note
        self.warnings = {f"scene {i}": text for i, text in enumerate(scene.warnings)}   # kind -> text
        self.triangles = diagnostics.mesh_triangles(scene)
        self.frames = 0
        self.drawn_at = -math.inf   # when the last frame was drawn
        self.inset = None           # the Newton view's Inset, as last drawn

    # -- the loop -------------------------------------------------------------------------------

    def loop(self):
        """Run until Esc, q or the close button; the exit code: 0, or 1 after a failed step or write."""
        self.pacer.start(self.run.t)
        while not self.done:
            started = self.clock.now()
            events = self.pygame.event.get()
            for event in events:
                self.handle(event)
            playing = self.playing and not self.done
            if playing:
                self.play()
            if events or self.frames == 0 or (playing and self.frame_due()):   # else nothing changed
                self.draw()
            self.clock.sleep(max(0.0, started + 1.0 / FPS - self.clock.now()))
        return 0 if self.failure is None and self.write_error is None else 1

    def handle(self, event):
        pg = self.pygame
        if event.type == pg.QUIT or (event.type == pg.KEYDOWN and event.key in (pg.K_ESCAPE, pg.K_q)):
            self.done = True
        elif event.type == pg.KEYDOWN:
            self.message = None
            if event.key == pg.K_SPACE:
                self.toggle_pause()
            elif event.key == pg.K_r:
                self.restart()
            elif event.key == pg.K_RIGHT and not self.playing:
                self.one_step()
            elif event.key == pg.K_n and not self.playing:
                self.one_newton_iteration()

    def frame_due(self):
        """Draw after this play? Yes while the steps keep up (FPS a second at most); when they are
        behind, only every 1/MIN_FPS s: the time goes to the steps (frames dropped, not simulated time)."""
        behind = self.pacer.due() - self.run.t >= self.scene.h
        return not behind or self.stopped() or self.clock.now() - self.drawn_at >= 1.0 / MIN_FPS

    def stopped(self):
        """At the end of the run, or after a failed step: nothing to play or step."""
        return self.run.finished or self.failure is not None

    def toggle_pause(self):
        self.playing = not self.playing and not self.stopped()
        self.pacer.start(self.run.t)
        self.pacer.forget()

    def restart(self):
        """Back to the initial state; playing on if it was playing or had stopped, else paused."""
        self.playing = self.playing or self.stopped()
        self.run.restart()
        self.failure = self.slow = None
        self.pacer.start(0.0)
        self.pacer.forget()

    def play(self):
        """Take the steps due by now (for at most FRAME_BUDGET of wall time), then note the rate."""
        deadline = self.clock.now() + FRAME_BUDGET
        while not self.run.finished and self.run.t + self.scene.h <= self.pacer.due() + DUE_SLACK * self.scene.h:
            if not self.one_step() or self.clock.now() > deadline:
                break
        if self.pacer.due() - self.run.t > max(2 * self.scene.h, self.speed * CATCH_UP):
            self.pacer.start(self.run.t + self.scene.h)         # too far behind: one step owed, no more
        self.pacer.sample(self.run.t)
        rate = self.pacer.rate()
        self.slow = rate if rate is not None and rate < SLOW else None
        if self.slow is not None:
            self.note("slow", f"the window ran slower than real time: {self.slow * self.speed:.2g}x (asked "
                              f"{self.speed:g}x)")
        if self.stopped():
            self.playing = False

    def one_step(self):
        """Complete the current time step; False when there was none to take or it failed."""
        if self.stopped():
            return False
        return self._keep(self._attempt(self.run.step))

    def one_newton_iteration(self):
        if self.stopped():
            return
        record = self._attempt(self.run.newton_iteration)
        if record is not None:
            self.message = (f"step {record.index + 1} done: Newton converged, ||p||_inf / h = "
                            f"{record.report.residual:.3g} <= tol = {self.scene.tol:g} m/s")
            self._keep(record)

    def _attempt(self, action):
        try:
            return action()
        except time_integrator.SimulationError as err:
            self.failure = err
            self.playing = False
            print(f"simulator.py: simulation failed: {err}", file=self.log)
            return None

    def _keep(self, record):
        """Hand a completed step to the files, if any, and note what the run to files warns about; False
        for no step."""
        if record is not None:
            self.check(record)
        if record is not None and self.output is not None and self.write_error is None:
            try:
                self.output.record(record)
            except OSError as err:      # e.g. a full disk: the window goes on, the files stop
                self.write_error = err
                print(f"simulator.py: writing the files failed, none written after step {record.index}: "
                      f"{err.strerror or err}", file=self.log)
        return record is not None

    def check(self, record):
        """What a run to files warns about, noted the first time: Newton at float64's round-off floor, a
        mesh folded over."""
        inverted = diagnostics.inverted_triangles(record.x, self.triangles)
        for kind, text in progress.step_warnings(self.scene, record.index + 1, record.t, record.report, inverted).items():
            self.note(kind, text)

    def note(self, kind, text):
        """A warning, the first of its kind: shown under the caption from now on, and on stderr (where
        the files, with --out, have not said it already)."""
        if kind in self.warnings:
            return
        self.warnings[kind] = text
        if self.output is None or kind == "slow":
            print(f"simulator.py: warning: {text}", file=self.log, flush=True)

    # -- drawing --------------------------------------------------------------------------------

    def draw(self):
        """The frame a run without the window writes (viewer.draw: the slope with its marks, the
        square, the contact forces), or the Newton iterate in progress instead of the forces; the
        window's status under the title and legend, the keys at the bottom; within a Newton step, the
        inset (self.inset) in the room between them."""
        run, pg = self.run, self.pygame
        x = run.shown_x
        self.view.follow(np.average(x, axis=0, weights=self.scene.m)[None])
        forces = self.newton_per_metre is not None and run.iterate is None
        runs = [frames.frame_run(self.scene, x, run.report, self.label, draw.BLUE, forces)]
        surface, top = draw.draw_frame(pg, runs, run.t, self.view, self.fonts,
                                       self.newton_per_metre if forces else None)
        if run.iterate is not None:
            self.draw_iterate(surface, run.iterate)
        line, width = self.font.get_linesize(), self.size - 24
        rows = [(row, color) for text, color in self.status_lines() for row in draw.wrap(self.font, text, width)]
        for row, (text, color) in enumerate(rows):
            surface.blit(self.font.render(text, True, color), (12, top + row * line))
        bottom = [row for text in self.help_lines() for row in draw.wrap(self.font, text, width)]
        for row, text in enumerate(reversed(bottom), start=1):
            surface.blit(self.font.render(text, True, KEYS), (12, self.size - 6 - row * line))
        self.inset = None
        if run.iterate is not None:
            self.inset = self.draw_inset(surface, run.iterate, top + len(rows) * line + 8,
                                         self.size - 6 - len(bottom) * line - 8)
        self.screen.blit(surface, (0, 0))
        pg.display.flip()
        self.frames += 1
        self.slow_frames += self.slow is not None
        self.drawn_at = self.clock.now()

    def status_lines(self):
        """(text, colour) under the caption: what the window is doing, the Newton iterate's figures."""
        run, lines = self.run, []
        if self.failure is not None:
            lines.append((f"step failed: {self.failure}", RED))
        elif run.finished:
            lines.append((f"end of the run ({run.steps} steps)", BLACK))
        elif self.playing:
            lines.append((f"playing at {self.speed:g}x real time", BLACK))
            if self.slow is not None:
                lines.append((f"slower than real time: {self.slow * self.speed:.2g}x (asked {self.speed:g}x)", RED))
        else:
            lines.append((f"paused {'in' if run.iterate is not None else 'before'} step {run.index + 1}", BLACK))
        if self.write_error is not None:
            lines.append((f"files stopped: {self.write_error.strerror or self.write_error}", RED))
        if self.message:
            lines.append((self.message, GREEN))
        lines += [(f"warning: {text}", RED) for kind, text in self.warnings.items() if kind != "slow"]
        if run.iterate is not None:
            lines += [(text, BLACK) for text in iterate_lines(run, self.scene)]
        return lines

    def help_lines(self):
        if self.stopped():
            return ["r: restart   q, Esc: quit"]
        if self.playing:
            return ["space: pause   r: restart   q, Esc: quit"]
        return ["space: play   right arrow: one step   n: one Newton iteration   r: restart   q, Esc: quit"]

    def draw_iterate(self, surface, it):
        """The main view of a Newton iterate: x^i in grey under x^{i+1} = x^i + alpha p in blue, and
        at each node an arrow of fixed length in the direction of p (where |p_k| is at least
        HINT_FLOOR of the largest): a hint of direction only, p itself is too short to see here."""
        pg, view = self.pygame, self.view
        draw.draw_square(pg, surface, self.scene, it.x, view, GREY, nodes=False)
        draw.draw_square(pg, surface, self.scene, it.x_next, view)
        size = np.hypot(it.p[:, 0], it.p[:, 1])
        shown = (size > 0.0) & (size >= HINT_FLOOR * size.max())
        tail = view(it.x[shown])
        direction = it.p[shown] / size[shown, None] * [1.0, -1.0]        # y grows downwards on screen
        tip = tail + HINT * self.size * direction
        heads = draw.arrow_heads(tail, tip, 0.012 * self.size)
        for a, b, (w1, w2) in zip(tail.tolist(), tip.tolist(), heads.tolist()):
            pg.draw.line(surface, RED, a, b, 2)
            pg.draw.polygon(surface, RED, [b, w1, w2])

    def draw_inset(self, surface, it, top, bottom):
        """The inset of a Newton iterate between rows `top` and `bottom`, beside the square on the
        side with more room (over it only where that room is under MIN_INSET of the window), its node
        circled and labelled in the main view; returns its Inset (None where the text leaves no room)."""
        px = self.view(it.x)
        room_left, room_right = px[:, 0].min(), self.size - px[:, 0].max()
        width = int(min(INSET * self.size, max(max(room_left, room_right) - 24, MIN_INSET * self.size)))
        height = int(min(INSET_TALL * self.size, bottom - top))
        big, small = self.fonts
        notes = [(row, color) for text, color in inset_notes(self.scene, it) for row in draw.wrap(small, text, width - 16)]
        line = small.get_linesize()
        header, footer = 8 + big.get_linesize() + len(notes) * line, 12 + line
        if height < header + footer + line:                    # no room left under the text
            return None
        rect = (12 if room_left > room_right else self.size - 12 - width, int(top), width, height)
        inset = newton_inset(self.scene, it, self.view, rect, header, footer)
        node = px[inset.node]
        label = self.fonts[1].render(f"node {inset.node}", True, BLACK, (255, 255, 255))    # on white: over a number too
        width_px, height_px = label.get_size()
        out = np.where(node >= px.mean(axis=0), 1, -1)           # the label off the node, away from the square
        self.pygame.draw.circle(surface, BLACK, node.tolist(), 9, 1)
        surface.blit(label, (node[0] + out[0] * (6 + width_px / 2) - width_px / 2,
                             node[1] + out[1] * (14 + height_px / 2) - height_px / 2))
        draw_inset(self.pygame, surface.subsurface(inset.rect), self.scene, it, inset, self.fonts, notes)
        return inset


@dataclass(frozen=True)
class Inset:
    """The Newton view's inset: one node of the iterate and the slope, magnified together, so that
    p, the CCD bound and the accepted step are seen at their true size against the slope. Pixels are
    the inset's own, from its top-left corner."""
    rect: tuple             # (left, top, width, height) in the window, px
    node: int               # the node magnified
    why: str                # why that node: it sets alpha_CCD, or it is the nearest to the slope
    view: draw.View         # world to the inset's pixels, at `magnification` times the window's scale
    magnification: float
    points: dict            # name -> (2,) world position of the node: x^i, x^i + p, ... (Algorithm 4)
    markers: dict           # name -> (2,) the same in the inset's pixels, where they are drawn
    slope: tuple            # the slope's line as drawn: its two ends in the inset's pixels (None: not drawn)
    distance: float         # the node's distance to the slope at x^i, m (inf without a slope)

    @property
    def title(self):
        """The inset's first line: the node and the magnification."""
        return f"node {self.node}, x{self.magnification:g}"


def focus_node(scene, it):
    """The node the inset magnifies, and why: the one whose approach to the slope sets alpha_CCD
    (Algorithm 4, line 1) when the CCD bound cuts the step, else the one nearest the slope (without
    a slope, the lowest)."""
    if "barrier" not in scene.terms:
        return int(np.argmin(it.x[:, 1])), "the lowest"
    if it.alpha_ccd < 1.0:
        return int(np.argmax(BarrierEnergy.approach_rates(it.x, scene.n, scene.o, it.p))), "sets alpha_CCD"
    return int(np.argmin(BarrierEnergy.distances(it.x, scene.n, scene.o))), "nearest the slope"


def newton_inset(scene, it, view, rect, header=0, footer=0):
    """The Inset of a Newton iterate in `rect` (its height cut to what the framed points need, at
    least half its width): its focus node's x^i, x^i + p, x^i + alpha_CCD p, x^i + alpha p and the
    slope (where the node is within SLOPE_REACH |p_k| of it), framed to fill INSET_FILL of the inset's
    rows between `header` and `footer` pixels from its top and bottom, at a magnification of `view`'s
    scale of one of ZOOMS times a power of ten, at most MAX_ZOOM."""
    k, why = focus_node(scene, it)
    x, p = it.x[k], it.p[k]
    points = {"x^i": x, "x^i + p": x + p, "x^i + alpha_CCD p": x + it.alpha_ccd * p,
              "x^i + alpha p": x + it.alpha * p}
    framed, d = [x, x + p], slope_distance(scene, x)
    with_slope = frames_slope(d, p)
    if with_slope:
        framed.append(x - d * scene.n)                          # its foot on the slope
    lo, hi = np.min(framed, axis=0), np.max(framed, axis=0)
    width, height = rect[2:]
    room = np.array([width, height - header - footer])          # px, across and down
    extent = (hi - lo) * view.scale                            # px, at the window's scale
    fit = min((INSET_FILL * room[extent > 0] / extent[extent > 0]).tolist(), default=MAX_ZOOM)
    magnification = draw.nice_number(min(fit, MAX_ZOOM), ZOOMS)
    room[1] = min(room[1], max(0.5 * width, extent[1] * magnification / INSET_FILL))
    height = int(header + room[1] + footer)                   # no taller than the framed points need
    rect = (*rect[:3], height)
    inset_view = draw.View(view.scale * magnification, width, height)
    middle = header + 0.5 * room[1]                             # the row the framed points centre on
    inset_view.center = 0.5 * (lo + hi) + [0.0, (middle - 0.5 * height) / inset_view.scale]
    markers = {name: inset_view(point) for name, point in points.items()}
    return Inset(rect, k, why, inset_view, magnification, points, markers,
                 draw.slope_ends(scene, inset_view) if with_slope else None, d)


def slope_distance(scene, x):
    """The distance d = n^T (x - o) of one point x to the slope, m (inf without a slope)."""
    if "barrier" not in scene.terms:
        return math.inf
    return float(BarrierEnergy.distances(x[None], scene.n, scene.o)[0])


def frames_slope(d, p):
    """Does the inset frame the slope with a node at distance d whose step is p? Where d is within
    SLOPE_REACH |p|."""
    return d <= SLOPE_REACH * float(np.hypot(*p))


def inset_notes(scene, it):
    """(text, colour) under the inset's title: why its node; where the slope is when it is out of
    frame; and what the thin lines are, so that a spring lying along the slope is not read as it."""
    k, why = focus_node(scene, it)
    d = slope_distance(scene, it.x[k])
    notes = [(f"({why})", BLACK)]
    if math.isfinite(d) and not frames_slope(d, it.p[k]):
        notes.append((f"the slope: {length_text(d)} below x^i, out of frame", draw.BLUE))
    return notes + [("thin lines: springs", BLACK)]


def draw_inset(pygame, surface, scene, it, inset, fonts, notes):
    """The inset on its own `surface`: the slope (tinted below), the springs of x^i (grey) and
    x^{i+1} (blue) about the node, p as a red arrow from x^i, a black ring at x^i + alpha_CCD p, a
    green dot at x^i + alpha p, all in one magnified frame; the node and the magnification at the
    top with `notes` (rows of (text, colour)) under them, a scale bar at the bottom, a border."""
    view, m = inset.view, inset.markers
    width, height = surface.get_size()
    surface.fill((255, 255, 255))
    if inset.slope is not None:
        a, b = inset.slope
        below = 2 * (width + height) * np.array([-scene.n[0], scene.n[1]])    # -n on screen, far
        pygame.draw.polygon(surface, GROUND, [a.tolist(), b.tolist(), (b + below).tolist(), (a + below).tolist()])
        pygame.draw.line(surface, draw.BLUE, a.tolist(), b.tolist(), 3)
    draw.draw_square(pygame, surface, scene, it.x, view, GREY, nodes=False)
    draw.draw_square(pygame, surface, scene, it.x_next, view, nodes=False)
    tail, tip = m["x^i"], m["x^i + p"]
    r = max(3, round(0.016 * width))                                        # px, the markers' radius
    pygame.draw.line(surface, RED, tail.tolist(), tip.tolist(), 3)
    if np.hypot(*(tip - tail)) > 1.0:
        pygame.draw.polygon(surface, RED, [tip.tolist()] + draw.arrow_heads(tail[None], tip[None], 3 * r)[0].tolist())
    pygame.draw.circle(surface, GREY, tail.tolist(), r)
    pygame.draw.circle(surface, BLACK, m["x^i + alpha_CCD p"].tolist(), r + 2, 2)
    pygame.draw.circle(surface, GREEN, m["x^i + alpha p"].tolist(), r)
    big, small = fonts
    surface.blit(big.render(inset.title, True, BLACK), (8, 6))
    row = 6 + big.get_linesize()
    for text, color in notes:
        surface.blit(small.render(text, True, color), (8, row))
        row += small.get_linesize()
    metres = draw.nice_number(0.3 * width / view.scale)
    bar, y = metres * view.scale, height - 6 - small.get_linesize() // 2
    pygame.draw.line(surface, BLACK, (8, y), (8 + bar, y), 3)
    surface.blit(small.render(length_text(metres), True, BLACK), (14 + bar, y - small.get_linesize() // 2))
    pygame.draw.rect(surface, BLACK, surface.get_rect(), 2)


def length_text(metres):
    """A length in m, mm or micrometres (um), to 3 digits."""
    if metres >= 1.0:
        return f"{metres:.3g} m"
    return f"{metres * 1e3:.3g} mm" if metres >= 1e-3 else f"{metres * 1e6:.3g} um"


def iterate_lines(run, scene):
    """The figures of Algorithm 4 for the iterate on screen, and what the colours show."""
    it = run.iterate
    friction = ("lagged friction" if it.friction_update == 0 else
                f"friction update {it.friction_update}, Algorithm 5")
    verdict = "<=" if it.residual <= scene.tol else ">"
    return [f"step {run.index + 1}, Newton iteration {run.iteration} ({friction})",
            f"||p||_inf / h = {it.residual:.3g} m/s {verdict} tol = {scene.tol:g} m/s at x^i",
            f"CCD bound alpha_CCD = {it.alpha_ccd:.4g} (black ring: x^i + alpha_CCD p)",
            f"accepted alpha = alpha_CCD / 2^{it.halvings} = {it.alpha:.4g} (green dot: x^i + alpha p)",
            "grey: x^i; blue: x^i + alpha p; red: the direction of p at each node",
            "inset: one node and the slope magnified together, p (red) to scale"]


# ------------------------------------------------------------------------------------------------
# Opening the display, and the command line's entry point
# ------------------------------------------------------------------------------------------------

def display_problem(driver, requested):
    """Why a window on SDL video driver `driver` would show nothing, or None. SDL falls back to a driver
    that draws into memory when it finds no display; that is fine only when asked for by name
    (SDL_VIDEODRIVER=dummy, as the tests and benchmarks run)."""
    if driver in MEMORY_DRIVERS and driver != requested:
        where = os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
        found = f"none at DISPLAY={where}" if where else "DISPLAY is not set"
        return (f"no display to open the window on ({found}; SDL fell back to its {driver!r} driver): "
                f"run on a desktop, under Xvfb, or without --window")
    return None


@contextlib.contextmanager
def c_stderr_hidden():
    """SDL's C code writes its probes' complaints ("XDG_RUNTIME_DIR is invalid") straight to file
    descriptor 2; hide them while the display opens, so a failure reads as one line."""
    sys.stderr.flush()
    saved = os.dup(2)
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 2)
        yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)


def open_display():
    """pygame with its display initialized on a real screen; ValueError when there is none."""
    requested = os.environ.get("SDL_VIDEODRIVER")
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    os.environ.setdefault("SDL_VIDEO_CENTERED", "1")
    import pygame
    try:
        with c_stderr_hidden():
            pygame.display.init()
    except pygame.error as err:
        raise ValueError(f"no display to open the window on (SDL: {err}): run on a desktop, under Xvfb, "
                         f"or without --window") from None
    problem = display_problem(pygame.display.get_driver(), requested)
    if problem:
        pygame.display.quit()
        raise ValueError(problem)
    pygame.font.init()
    return pygame


def window_size(size, pygame):
    """--size (checked by run_window), or the largest square that fits the display: FIT of its smaller side."""
    if size is not None:
        return int(size)
    info = pygame.display.Info()
    if info.current_w > 0 and info.current_h > 0:
        return max(MIN_SIZE, int(FIT * min(info.current_w, info.current_h)))
    return draw.RESOLUTION


def check_size(value):
    """--size as a whole number of pixels in [MIN_SIZE, MAX_SIZE]; ValueError otherwise."""
    if not (math.isfinite(value) and float(value).is_integer() and MIN_SIZE <= value <= MAX_SIZE):
        raise ValueError(f"size must be a whole number of pixels in [{MIN_SIZE}, {MAX_SIZE}] (the window's "
                         f"side), got {value:g}")
    return int(value)


def check_speed(value):
    """--speed (default 1): simulated seconds per wall-clock second, finite and > 0; ValueError otherwise."""
    if value is None:
        return 1.0
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"speed must be a finite number > 0 (simulated seconds per second), got {value:g}")
    return value


def run_window(plan, speed, size, signals, clock=None, log=None):
    """`python simulator.py --window`: check the flags, open the window, run the demo until closed;
    with --out (plan.out), write what a run without the window writes, as it does. Returns the exit
    code: 0; 1 after a failed step or write; 130 after Ctrl+C; 143 after SIGTERM."""
    speed, log = check_speed(speed), log or sys.stderr
    if size is not None:
        check_size(size)
    with signals.held():                        # SDL starts after the run's signal handlers: they stay ours
        pygame = open_display()                 # before anything is written
    try:
        return _demo(pygame, plan, speed, size, signals, clock or WallClock(), log)
    finally:
        pygame.display.quit()


def _demo(pygame, plan, speed, size, signals, clock, log):
    """The window on the display, with the files when --out is given, until it is closed; the run ends
    as a run without the window does (viewer.run.end)."""
    scene = plan.scenes[0]
    folder = files.OutputFolder.claim(plan.out, plan.names(), signals) if plan.out is not None else None
    output, window, failure = None, None, None
    try:
        orchestration.warn(plan, log)
        screen = pygame.display.set_mode((window_size(size, pygame),) * 2)
        pygame.display.set_caption(f"simulator.py: mu = {scene.mu:g}, n_seg = {scene.n_seg}")
        if folder is not None:
            output = Files(plan, folder, log)
        window = LiveWindow(pygame, screen, scene, plan.steps[0], speed, output, clock, log, plan.labels[0],
                            plan.forces)
        window.loop()
        failure = window.write_error or window.failure
        failure = failure and orchestration.failure_of(failure, plan)
    except orchestration.ENDINGS as err:         # Ctrl+C, SIGTERM; starting the files (frame 0)
        failure = orchestration.failure_of(err, plan)
    steps = window.run.index if window else 0
    written = f"; {orchestration.written(plan)} in {plan.out}/" if output else ""
    done = f"simulator.py: {steps} steps ({steps * scene.h:.2f} s) in the window{written}"
    return orchestration.end(plan, signals, folder, [output.track] if output else [], output and output.frame_log,
                             failure, log, done)
