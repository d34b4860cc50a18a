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
import math
import os
import sys
import time
from collections import deque

import numpy as np

import time_integrator
from simulator import StepRecord
from viewer import draw, files, recording, run as orchestration

FPS = 60                  # frames drawn per second at most
MIN_FPS = 20              # ... and at least, when the steps fall behind (the other frames are dropped)
FRAME_BUDGET = 1.0 / 30   # s of stepping before the loop draws and reads the keys again
FIT = 0.85                # by default the window's side is this fraction of the display's smaller side,
                          # leaving room for the title bar and desktop panels (652 px on 1024x768)
MIN_SIZE, MAX_SIZE = 300, 16384   # px; 16384 is the largest texture common graphics drivers accept
DUE_SLACK = 1e-9          # of a step: t + h and the time due may differ by round-off
CATCH_UP = 0.1            # s of wall time the steps may fall behind and catch up (a slow step, a busy CPU)
SLOW = 0.9                # "slower than real time" below this fraction of the asked speed
ARROW = 0.12              # the longest drawn p is this fraction of the window
LEGEND_BOTTOM = 36 + 4 + 3 * 22   # px: below draw.draw_frame's legend of the force arrows (3 rows of 22 px)
# SDL's drivers that draw into memory only: it falls back to one of them when it finds no display
MEMORY_DRIVERS = ("dummy", "offscreen")

BLACK, GREY, RED, GREEN = (0, 0, 0), (170, 170, 170), (200, 0, 0), (0, 140, 0)


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
        self.x_prev = self.x         # x^{n-1}, for the friction force of the last step
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
            x, v, report = _run_out(self.iterates)
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
        self.x_prev, self.x, self.v = self.x, x, v
        self.iterates, self.iterate, self.iteration, self.iterates_wall = None, None, 0, 0.0
        return record


def _run_out(generator):
    """The value a generator returns, after running through what it still yields."""
    while True:
        try:
            next(generator)
        except StopIteration as done:
            return done.value


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
        self.progress = recording.Progress([self.track], log)
        self.writer = recording.FrameWriter([self.track], folder, plan.forces, self.frame_log) if plan.frames else None
        if self.writer is not None:
            self.writer.write(0)

    def record(self, record):
        """Write a completed step: its log.csv row, and its frame when one is due (frame j at step
        j stride, the last at the run's last step, as recording.frame_steps numbers them)."""
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
        self.font = pygame.font.Font(None, font_size(self.size))
        self.fonts = (self.font, pygame.font.Font(None, font_size(self.size, small=True)))
        self.playing, self.done = True, False
        self.failure = None         # the SimulationError that stopped the run, if one did
        self.write_error = None     # the OSError that stopped the files, if one did
        self.message = None         # what the last key did, shown until the next key
        self.slow = None            # the rate reached, when below SLOW of the asked speed
        self.slow_frames = 0        # frames drawn with the "slower than real time" note
        self.frames = 0
        self.drawn_at = -math.inf   # when the last frame was drawn

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
        """Hand a completed step to the files, if any; False for no step."""
        if record is not None and self.output is not None and self.write_error is None:
            try:
                self.output.record(record)
            except OSError as err:      # e.g. a full disk: the window goes on, the files stop
                self.write_error = err
                print(f"simulator.py: writing the files failed, none written after step {record.index}: "
                      f"{err.strerror or err}", file=self.log)
        return record is not None

    # -- drawing --------------------------------------------------------------------------------

    def draw(self):
        """The frame a run without the window writes (viewer.draw: the slope with its marks, the
        square, the contact forces), or the Newton iterate in progress instead of the forces; the
        window's status under the title and legend, the keys at the bottom."""
        run, pg = self.run, self.pygame
        x = run.shown_x
        self.view.follow(np.average(x, axis=0, weights=self.scene.m)[None])
        forces = self.newton_per_metre is not None and run.iterate is None
        runs = [recording.frame_run(self.scene, run.x_prev, x, self.label, draw.BLUE, forces)]
        surface = draw.draw_frame(pg, runs, run.t, self.view, self.fonts, self.newton_per_metre if forces else None)
        if run.iterate is not None:
            self.draw_iterate(surface, run.iterate)
        line, width = self.font.get_linesize(), self.size - 24
        top = LEGEND_BOTTOM if forces else 10 + line
        rows = [(row, color) for text, color in self.status_lines() for row in wrap(self.font, text, width)]
        for row, (text, color) in enumerate(rows):
            surface.blit(self.font.render(text, True, color), (12, top + row * line))
        bottom = [row for text in self.help_lines() for row in wrap(self.font, text, width)]
        for row, text in enumerate(reversed(bottom), start=1):
            surface.blit(self.font.render(text, True, GREY), (12, self.size - 6 - row * line))
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
        if run.iterate is not None:
            lines += [(text, BLACK) for text in iterate_lines(run, self.scene, self.arrow_scale(run.iterate))]
        return lines

    def help_lines(self):
        if self.stopped():
            return ["r: restart   q, Esc: quit"]
        if self.playing:
            return ["space: pause   r: restart   q, Esc: quit"]
        return ["space: play   right arrow: one step   n: one Newton iteration   r: restart   q, Esc: quit"]

    def arrow_scale(self, it):
        """p is drawn times this factor (1, 2 or 5 times a power of ten), the longest arrow about
        ARROW of the window."""
        longest = float(np.abs(it.p).max()) * self.view.scale
        return nice_below(ARROW * self.size / longest) if longest > 0.0 else 1.0

    def draw_iterate(self, surface, it):
        """x^i in grey under the iterate x^{i+1} = x^i + alpha p in blue; p at each node as a red
        arrow, with a ring where alpha_CCD p ends and a dot where alpha p ends (on the drawn scale)."""
        pg, view = self.pygame, self.view
        draw.draw_square(pg, surface, self.scene, it.x, view, GREY, nodes=False)
        draw.draw_square(pg, surface, self.scene, it.x_next, view)
        k = self.arrow_scale(it)
        tail, tip = view(it.x), view(it.x + k * it.p)
        ccd, accepted = view(it.x + k * it.alpha_ccd * it.p), view(it.x + k * it.alpha * it.p)
        heads = arrow_heads(tail, tip, 0.015 * self.size)
        for a, b, (w1, w2), c, d in zip(tail.tolist(), tip.tolist(), heads.tolist(), ccd.tolist(), accepted.tolist()):
            pg.draw.line(surface, RED, a, b, 2)
            pg.draw.polygon(surface, RED, [b, w1, w2])
            pg.draw.circle(surface, BLACK, c, 4, 1)
            pg.draw.circle(surface, GREEN, d, 3)


def iterate_lines(run, scene, scale):
    """The figures of Algorithm 4 for the iterate on screen."""
    it = run.iterate
    friction = ("lagged friction" if it.friction_update == 0 else
                f"friction update {it.friction_update}, Algorithm 5")
    verdict = "<=" if it.residual <= scene.tol else ">"
    return [f"step {run.index + 1}, Newton iteration {run.iteration} ({friction})",
            f"||p||_inf / h = {it.residual:.3g} m/s {verdict} tol = {scene.tol:g} m/s at x^i",
            f"CCD bound alpha_CCD = {it.alpha_ccd:.4g} (black rings)",
            f"accepted alpha = alpha_CCD / 2^{it.halvings} = {it.alpha:.4g} (green dots)",
            f"red: p at each node, drawn x{scale:g}; grey: x^i; blue: x^i + alpha p"]


def wrap(font, text, width):
    """`text` broken at spaces into rows at most `width` pixels wide (a longer word stays whole)."""
    rows, row = [], ""
    for word in text.split(" "):
        trial = f"{row} {word}" if row else word
        if row.strip() and font.size(trial)[0] > width:
            rows.append(row.rstrip())
            row = word
        else:
            row = trial
    return rows + [row]


def arrow_heads(tail, tip, length):
    """(N, 2, 2): the two back corners of each arrow's head, `length` pixels behind its tip."""
    d = tip - tail
    norm = np.hypot(d[:, 0], d[:, 1])[:, None]
    u = np.divide(d, norm, out=np.zeros_like(d), where=norm > 0)
    side = np.stack([-u[:, 1], u[:, 0]], axis=1)
    back = tip - length * u
    return np.stack([back + 0.5 * length * side, back - 0.5 * length * side], axis=1)


def nice_below(value):
    """The largest of 1, 2, 5 times a power of ten that is at most `value` (> 0)."""
    power = 10.0 ** math.floor(math.log10(value))
    return max(m * power for m in (1, 2, 5) if m * power <= value * (1 + 1e-12))


def font_size(size, small=False):
    """The frames' fonts (draw.fonts: 26 px, and 20 px for the small one) at 900 px, in proportion,
    and at least 14 (small: 12) px to stay readable."""
    return max(12, round(20 * size / draw.RESOLUTION)) if small else max(14, round(26 * size / draw.RESOLUTION))


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
    return orchestration.end(plan, signals, folder, [output.track] if output else [], output and output.frame_log,
                             failure, log, f"simulator.py: {steps} steps ({steps * scene.h:.2f} s) in the window{written}")
