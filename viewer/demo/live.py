"""The live demo without its window: the run one step or one Newton iteration at a time, paced to
wall-clock time, what the keys do to it, its files (--out) and its warnings. No pygame here: the
window (viewer.demo.window) reads the keys, calls these and draws; tests drive them with a fake clock.

The run is deterministic: after a restart the steps computed again are the same, so the files hold
each step once, the furthest the run got.
"""
import sys
import time
from collections import deque

import time_integrator
from simulator import StepRecord
from analysis import diagnostics, wear
from viewer.pictures import draw, frames
from viewer.command import progress, recording

FRAME_BUDGET = 1.0 / 30   # s of stepping before the loop draws and reads the keys again
DUE_SLACK = 1e-9          # of a step: t + h and the time due may differ by round-off
CATCH_UP = 0.1            # s of wall time the steps may fall behind and catch up (a slow step, a busy CPU)
SLOW = 0.9                # "slower than real time" below this fraction of the asked speed


class WallClock:
    """Wall-clock time for the pacing; tests hand the demo a fake clock with the same two methods."""
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
        # with a hand (the chalk): its mark on the board so far, as recording.Track.marks keeps it
        self.marks = wear.Deposit() if self.scene.hand is not None else None

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
        record = StepRecord(self.index, time_integrator.step_time(self.scene, self.index), x, v, report,
                            wall + self.iterates_wall)
        self.index += 1
        if self.marks is not None:
            self.marks.step(self.scene, self.x, x)
        self.report, self.x, self.v = report, x, v
        self.iterates, self.iterate, self.iteration, self.iterates_wall = None, None, 0, 0.0
        return record


def tip_lines(scene, x, v, t):
    """The chalk's figures of the state (x, v) at time t, for the window's status, as its log.csv has
    them (diagnostics.tip_figures): the tip's place along the board and its speed, stuck or slipping as
    diagnostics.tip_stuck has it, the hand's drive speed and the board's normal force."""
    f, stuck = diagnostics.tip_figures(scene, x, v, t), diagnostics.tip_stuck(scene, x, v)
    speed, epsv = f"{f['tip_speed'] * 1e3:.3g} mm/s", f"eps_v = {scene.epsv * 1e3:g} mm/s"
    state = (f"off the board (d >= dhat): {speed}" if stuck is None else
             f"stuck: {speed} < {epsv}" if stuck else f"slipping: {speed} >= {epsv}")
    return [f"tip at {f['tip_x'] * 100:.2f} cm, {state}",
            f"the hand's drive {f['drive_speed'] * 1e3:.3g} mm/s, the board's normal force {f['normal_force']:.3g} N"]


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
    """What a run without the window writes, written by the same code (viewer.command.recording, frames) into
    `folder` (files.RunFolder): log.csv a row as each step ends, a frame and OBJ every `stride`
    steps (unless --no-frames), and at the end summary.png, plots.png and index.html. Each step is
    written once: the steps computed again after a restart (r) are the same numbers and are not
    written again, so the files hold the furthest the run got."""

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
# The demo: what play and the keys do
# ------------------------------------------------------------------------------------------------

class LiveDemo:
    """The run in play or paused, at `speed` times the wall clock, and what each key does to it: play
    and pause, one time step, one Newton iteration, restart. Completed steps go to `output` (the Files,
    or None); what a run to files warns about is noted in `warnings` (kind -> text) and, where the
    files have not said it, on `log`. viewer.demo.window.LiveWindow draws it and reads the keys."""

    def __init__(self, scene, steps, speed=1.0, output=None, clock=None, log=None):
        self.scene, self.log = scene, log or sys.stderr
        self.clock = clock or WallClock()
        self.run = LiveRun(scene, steps)
        self.speed, self.output = speed, output
        self.pacer = Pacer(self.clock, speed, scene.h)
        self.playing, self.done = True, False
        self.failure = None         # the SimulationError that stopped the run, if one did
        self.write_error = None     # the OSError that stopped the files, if one did
        self.message = None         # what the last key did, shown until the next key
        self.slow = None            # the rate reached, when below SLOW of the asked speed
        self.warnings = {f"scene {i}": text for i, text in enumerate(scene.warnings)}   # kind -> text
        self.triangles = diagnostics.mesh_triangles(scene)

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
        """What a run to files warns about (progress.step_warnings), noted the first time: Newton at
        float64's round-off floor, a mesh folded over."""
        inverted = diagnostics.inverted_triangles(record.x, self.triangles)
        for kind, text in progress.step_warnings(self.scene, record.index + 1, record.t, record.report,
                                                 inverted).items():
            self.note(kind, text)

    def note(self, kind, text):
        """A warning, the first of its kind: shown under the caption from now on, and on stderr (where
        the files, with --out, have not said it already)."""
        if kind in self.warnings:
            return
        self.warnings[kind] = text
        if self.output is None or kind == "slow":
            print(f"simulator.py: warning: {text}", file=self.log, flush=True)
