"""The live demo without its window (no pygame): the run, its pacing, keys, files and warnings."""
import contextlib
import sys
import time
from collections import deque
from types import SimpleNamespace

import time_integrator
from simulator import StepRecord
from analysis import closing, diagnostics, wear
from viewer.pictures import draw
from viewer.command import frame_process, progress, recording

FRAME_BUDGET = 1.0 / 30   # s of stepping before the loop draws and reads the keys again
DUE_SLACK = 1e-9          # of a step: t + h and the time due may differ by round-off
CATCH_UP = 0.1            # s of wall time the steps may fall behind and catch up
SLOW = 0.9                # "slower than real time" below this fraction of the asked speed


class LiveRun:
    """The state after `index` steps, and the step in progress, whole or by Newton iteration."""

    def __init__(self, scene, steps):
        self.scene, self.steps = scene, steps
        self.restart()

    def restart(self):
        self.index, self.x, self.v = 0, self.scene.x0.copy(), self.scene.v0.copy()
        self.report = None          # the last step's StepReport
        self.marks = wear.Deposit() if self.scene.hand is not None else None   # as Track.marks
        self._end_iterates()

    def _end_iterates(self):
        # the generator of the step begun by n, its last NewtonIterate, their count, s computing
        self.iterates, self.iterate, self.iteration, self.wall = None, None, 0, 0.0

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
        """Complete the current step (finishing one begun by n); returns its StepRecord."""
        start = time.perf_counter()
        if self.iterates is None:
            x, v, report = time_integrator.step(self.scene, self.x, self.v, step_index=self.index)
        else:
            x, v, report = time_integrator.run_out(self.iterates)
        return self._advance(x, v, report, time.perf_counter() - start)

    def newton_iteration(self):
        """The next Newton iterate, self.iterate: None, or the StepRecord when the step is done."""
        if self.iterates is None:
            self.iterates = time_integrator.newton_iterates(self.scene, self.x, self.v,
                                                            step_index=self.index)
        start = time.perf_counter()
        try:
            self.iterate = next(self.iterates)
        except StopIteration as done:
            return self._advance(*done.value, time.perf_counter() - start)
        self.wall += time.perf_counter() - start
        self.iteration += 1
        return None

    def _advance(self, x, v, report, wall):
        """Take x^{n+1}, v^{n+1}; the step's record, with the seconds computing it took."""
        t = time_integrator.step_time(self.scene, self.index)
        record = StepRecord(self.index, t, x, v, report, wall + self.wall)
        if self.marks is not None:
            self.marks.step(self.scene, self.x, x)
        self.index, self.report, self.x, self.v = self.index + 1, report, x, v
        self._end_iterates()
        return record


def tip_lines(scene, x, v, t):
    """The chalk's figures as log.csv has them (diagnostics.tip_figures, tip_stuck)."""
    f = diagnostics.tip_figures(scene, x, v, t, diagnostics.lambdas(scene, x))
    stuck = diagnostics.tip_stuck(scene, x, v)
    speed, epsv = f"{f['tip_speed'] * 1e3:.3g} mm/s", f"eps_v = {scene.epsv * 1e3:g} mm/s"
    state = (f"off the board (d >= dhat): {speed}" if stuck is None else
             f"stuck: {speed} < {epsv}" if stuck else f"slipping: {speed} >= {epsv}")
    return [f"tip at {f['tip_x'] * 100:.2f} cm, {state}",
            f"the hand's drive {f['drive_speed'] * 1e3:.3g} mm/s, "
            f"the board's normal force {f['normal_force']:.3g} N"]


class Pacer:
    """Simulated time due, t_0 + speed (now - wall_0); the rate reached over `span` s of play."""

    def __init__(self, clock, speed, h):
        self.clock, self.speed = clock, speed
        self.span = max(1.0, 40 * h / speed)    # a rate over half of it is within 5 % (one step)
        self.samples = deque()                  # (wall, t) at each frame of play
        self.start(0.0)

    def start(self, t, fresh=True):
        """Play from simulated time t now; `fresh` (not after falling behind): measure afresh."""
        self.wall_0, self.t_0 = self.clock.now(), t
        if fresh:
            self.samples.clear()

    def due(self):
        return self.t_0 + self.speed * (self.clock.now() - self.wall_0)

    def sample(self, t):
        now = self.clock.now()
        self.samples.append((now, t))
        while now - self.samples[0][0] > self.span:
            self.samples.popleft()

    def rate(self):
        """The rate; None before half a span of play."""
        (wall_a, t_a), (wall_b, t_b) = self.samples[0], self.samples[-1]
        if wall_b - wall_a < 0.5 * self.span:
            return None
        return (t_b - t_a) / (wall_b - wall_a) / self.speed


class Files:
    """What a run without the window writes, by its code, each step once (r recomputes the same);
    its frames in the frames' process, as a run's (close() waits for them)."""

    def __init__(self, plan, folder, log):
        self.plan, self.frame_log = plan, []
        self.track = recording.Track(plan.scenes[0], plan.steps[0], None, plan.labels[0], "",
                                     draw.run_color(0), folder)
        self.progress = progress.Progress([self.track], log)
        self.writer = None
        if plan.frames:
            with folder.signals.held():         # a writer made is a writer closed
                self.writer = frame_process.frame_writer([self.track], folder, plan.forces,
                                                         self.frame_log)
            try:
                self.writer.write(0)
            except BaseException:
                with contextlib.suppress(OSError):      # the caller says the error
                    self.close()
                raise

    def close(self):
        """Every frame sent written and counted, or its OSError raised; the writer ended."""
        writer, self.writer = self.writer, None
        if writer is not None:
            writer.close()

    def record(self, record):
        """A step's log.csv row, and frame j at step j stride (and the last step)."""
        track, stride = self.track, self.plan.stride
        if record.index == track.step:          # else computed before a restart: written then
            track.take(record, self.progress)
            if self.writer is not None and (track.step % stride == 0 or track.step == track.steps):
                self.writer.write(-(-track.step // stride))


def files_stopped(step, err):
    """The line saying the window's files stopped at `step`: a write failed with OSError `err`."""
    return (f"simulator.py: writing the files failed, none written after step {step}: "
            f"{err.strerror or err}")


class Unwritten:
    """Where the window's own recording.Track writes and says: nothing (its RunFolder, log file and
    Progress at once); the Track keeps the states closing.closing_words reads."""

    def __init__(self):
        self.signals = SimpleNamespace(held=contextlib.nullcontext)

    def open_log(self, name, header):
        return self

    def append(self, line):
        pass

    def warn(self, track, text):
        pass

    def tick(self, track):
        pass


class LiveDemo:
    """The run at `speed` times the wall clock, what each key does; its steps go to `output`."""

    def __init__(self, scene, steps, speed=1.0, output=None, clock=None, log=None):
        self.scene, self.speed, self.output, self.log = scene, speed, output, log or sys.stderr
        # the wall clock (tests hand the demo a fake one with these two methods)
        self.clock = clock or SimpleNamespace(now=time.perf_counter, sleep=time.sleep)
        self.run, self.pacer = LiveRun(scene, steps), Pacer(self.clock, speed, scene.h)
        self.playing, self.done = True, False
        self.failure = self.write_error = None     # what stopped the run, the files (if any)
        self.message = self.slow = None             # the last key's message; the rate, < SLOW
        self.warnings = {f"scene {i}": text for i, text in enumerate(scene.warnings)}
        self.track = self.result = None     # the run's states (recording.Track), closing_words
        self.new_track()

    def new_track(self):
        """The states from t = 0 on, kept as a run's are; the result said once the run ends."""
        self.track = recording.Track(self.scene, self.run.steps, None, "", "", draw.run_color(0),
                                     Unwritten())
        self.track.marks = None     # the chalk's mark: the run's own (LiveRun.marks), not twice
        self.result = None

    def stopped(self):
        """At the end of the run, or after a failed step: nothing to play or step."""
        return self.run.finished or self.failure is not None

    def toggle_pause(self):
        self.playing = not self.playing and not self.stopped()
        self.pacer.start(self.run.t)

    def restart(self):
        """Back to the initial state; playing if it was playing or had stopped, else paused."""
        self.playing = self.playing or self.stopped()
        self.run.restart()
        self.new_track()
        self.failure = self.slow = None
        self.pacer.start(0.0)

    def play(self):
        """Take the steps due, for FRAME_BUDGET s at most; over CATCH_UP behind, go on from here."""
        deadline, h = self.clock.now() + FRAME_BUDGET, self.scene.h
        while not self.run.finished and self.run.t + h <= self.pacer.due() + DUE_SLACK * h:
            if not self.one_step() or self.clock.now() > deadline:
                break
        if self.pacer.due() - self.run.t > max(2 * h, self.speed * CATCH_UP):
            self.pacer.start(self.run.t + h, fresh=False)   # too far behind: one step owed
        self.pacer.sample(self.run.t)
        rate = self.pacer.rate()
        self.slow = rate if rate is not None and rate < SLOW else None
        if self.slow is not None:
            self.note("slow", f"the window ran slower than real time: "
                              f"{self.slow * self.speed:.2g}x (asked {self.speed:g}x)")
        if self.stopped():
            self.playing = False

    def one_step(self):
        """Complete the current time step; False when there was none to take or it failed."""
        return self._take(self.run.step) is not None

    def one_newton_iteration(self):
        record = self._take(self.run.newton_iteration)
        if record is not None:
            self.message = (f"step {record.index + 1} done: Newton converged, ||p||_inf / h = "
                            f"{record.report.residual:.3g} <= tol = {self.scene.tol:g} m/s")

    def _take(self, action):
        """`action` unless stopped; the step it completes to the warnings and files; its record."""
        try:
            record = None if self.stopped() else action()
        except time_integrator.SimulationError as err:
            self.failure, self.playing, record = err, False, None
            print(progress.wrapped(f"simulator.py: simulation failed: {err}"), file=self.log)
        if record is None:
            return None
        self.track.take(record, self.track.folder)
        if self.run.finished:           # what the closing says (the window shows it)
            self.result = closing.closing_words([self.track])
        inverted = self.track.samples.last.inverted
        for kind, text in progress.step_warnings(self.scene, record.index + 1, record.t,
                                                 record.report, inverted).items():
            self.note(kind, text)
        if self.output is not None and self.write_error is None:
            try:
                self.output.record(record)
            except OSError as err:      # e.g. a full disk: the window goes on, the files stop
                self.write_error = err
                print(files_stopped(record.index, err), file=self.log)
        return record

    def note(self, kind, text):
        """A warning, the first of its kind: on screen, and on `log` unless the files say it."""
        if kind not in self.warnings and (self.output is None or kind == "slow"):
            print(progress.wrapped(f"simulator.py: warning: {text}"), file=self.log, flush=True)
        self.warnings.setdefault(kind, text)
