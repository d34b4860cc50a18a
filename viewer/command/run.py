"""A run of the command line, to files or in the window: the folder it owns, its signals, its ending.

Whatever ends a run, it ends in one line on stderr and an exit code: 0 when done; 1 after a failed
step or a failed write (a full disk); 130 after Ctrl+C and 143 after SIGTERM. Ctrl+C and SIGTERM
raise `Stopped` wherever the run is, except while a file is being written or pygame loads
(`Signals.held`), which they let finish first: every file stays whole and no temporary is left.
After a failed step or a signal the run still writes its last pictures for the steps it kept; a
second signal leaves out those not yet written, and the line says which.
"""
import contextlib
import signal
import sys
import threading
import time
from dataclasses import dataclass

import numpy as np

import simulator
import time_integrator
from viewer.pictures import draw, run_pictures
from viewer.output import files
from viewer.command import recording
from viewer.pictures.frames import frame_count
from analysis.closing import closing_words
from viewer.command.startup import EXIT_CODES, REASONS

class Stopped(BaseException):
    """SIGINT (Ctrl+C) or SIGTERM: the run stops, says so in one line and keeps what it wrote."""

    def __init__(self, signum):
        super().__init__(signum)
        self.code, self.reason = EXIT_CODES[signum], REASONS[signum]


class Signals:
    """While a run is on (`with Signals() as signals:`), SIGINT and SIGTERM raise Stopped, at once or,
    inside `held()`, as it ends. Handlers can only be set from the main thread: from another (a
    notebook's), signals are left as they are."""

    def __init__(self):
        self.depth, self.pending, self.previous = 0, None, {}

    def __enter__(self):
        if threading.current_thread() is threading.main_thread():
            self.previous = {signum: signal.signal(signum, self._handle) for signum in EXIT_CODES}
        return self

    def __exit__(self, *exc):
        for signum, handler in self.previous.items():
            signal.signal(signum, handler)

    def _handle(self, signum, frame):
        if self.depth:
            self.pending = self.pending or signum
        else:
            raise Stopped(signum)

    @contextlib.contextmanager
    def held(self):
        """Signals wait until the block ends (a file written whole, pygame loaded), then stop the run."""
        self.depth += 1
        try:
            yield
        finally:
            self.depth -= 1
        if self.depth == 0 and self.pending is not None:
            signum, self.pending = self.pending, None
            raise Stopped(signum)

    def close(self):
        """The run is ending: from here on a signal only waits (until the handlers are restored)."""
        self.depth += 1


@dataclass
class Plan:
    """What the command line asks for: one scene or a comparison's, each with its label, file tag and
    number of steps; where to write, a frame every `stride` steps (of the smallest h), what to draw."""
    scenes: list
    labels: list
    tags: list
    steps: list
    out: str                # the folder --out names (new or empty), or None: a new one under output/
    stride: int
    frames: bool
    forces: bool
    said: str = None        # what the run says first (cli.decimal_comma), or None

    def names(self):
        """The longest names of each kind this run writes (files.run_names)."""
        frames = frame_count(self.scenes, self.steps, self.stride)
        return files.run_names(self.tags, frames, self.frames, marks=self.scenes[0].hand is not None)

    def folder(self, signals):
        """The run's folder (files.RunFolder), made: `out`, or a new output/<scene>-<date>-<time>."""
        kind = "chalk" if self.scenes[0].hand is not None else "square"
        return files.RunFolder.make(self.out, kind, self.names(), signals)


def warn(plan, messages):
    """Each scene's warnings (what its results cannot be trusted for), one line each."""
    for label, scene in zip(plan.labels, plan.scenes):
        for warning in scene.warnings:
            who = f"{label}: " if len(plan.scenes) > 1 else ""
            print(f"simulator.py: warning: {who}{warning}", file=messages, flush=True)


def load_pygame(signals):
    """pygame, loaded whole: a signal while it loads waits until it has."""
    with signals.held():
        return draw.load_pygame()


def write_error(err, plan):
    """A failed write (a full disk, a folder gone) as the one line's text: the file it names, else
    the run's folder."""
    where = err.filename or plan.out or "the run's folder"
    return f"error: cannot write {where}: {err.strerror or err}"


def summary_header(plan):
    """The parameters the runs share, and for a comparison what differs: summary.png's and the page's text."""
    scene, p = plan.scenes[0], plan.scenes[0].params
    if scene.hand is not None:
        lines = [f"chalk {p['length'] * 100:g} x {p['width'] * 100:g} cm, {'dragged' if p['drag'] else 'pushed'} "
                 f"at tilt = {p['tilt']:g} deg   grip k_hand = {p['k_hand']:g} N/m   drive = {p['drive']:g} m/s   "
                 f"mu_s = {p['mu_s']:g}   mu = {scene.mu:g}   v_c = {p['v_c']:g} m/s",
                 f"h = {scene.h:g} s   k = {p['k']:g} N/m   dhat = {scene.dhat:g} m   kappa = {scene.kappa:g}   "
                 f"eps_v = {scene.epsv:g} m/s   tol = {scene.tol:g} m/s"]
        return (["comparison: " + ", ".join(plan.labels) + "; otherwise as the first:"] if len(plan.scenes) > 1
                else []) + lines
    lines = [f"mu = {scene.mu:g}   h = {scene.h:g} s   k = {p['k']:g} N/m   n_seg = {p['n_seg']}",
             f"slope normal = {None if scene.n is None else np.round(scene.n, 4).tolist()}   "
             f"dhat = {scene.dhat:g} m   kappa = {scene.kappa:g}   eps_v = {scene.epsv:g} m/s"]
    if len(plan.scenes) > 1:
        lines.insert(0, "comparison: " + ", ".join(plan.labels) + "; otherwise as the first:")
    return lines


@dataclass
class Failure:
    """How a run ended early: its exit code and its line; `pictures`: whether the last pictures may
    still be written (not after a failed write: the disk is full, or the folder gone)."""
    code: int
    text: str
    pictures: bool = True


ENDINGS = (Stopped, OSError, time_integrator.SimulationError, ValueError)   # what ends a run early


def failure_of(err, plan):
    """The Failure an exception of ENDINGS ends a run with."""
    if isinstance(err, Stopped):
        return Failure(err.code, f"stopped: {err.reason}")
    if isinstance(err, OSError):
        return Failure(1, write_error(err, plan), pictures=False)
    if isinstance(err, time_integrator.SimulationError):
        return Failure(1, f"stopped: simulation failed: {err}")
    return Failure(1, f"stopped: {err}")        # a ValueError: a number the checks did not foresee


def end(plan, signals, folder, tracks, frame_log, failure, messages, done):
    """How every run ends, to files or in the window: the last pictures for the steps kept (a signal
    now leaves out those not yet written), the files closed, one line on `messages` (`done` after a
    run that ended well); returns the exit code."""
    if tracks and (failure is None or failure.pictures):
        try:
            for track in tracks:
                track.last_snapshot()
            run_pictures.write(tracks, folder, plan.stride, plan.frames, frame_log, summary_header(plan))
        except Stopped as stopped:
            failure = failure or Failure(stopped.code, f"stopped: {stopped.reason} while writing the last pictures")
        except ENDINGS as err:
            failure = failure or failure_of(err, plan)
    signals.close()
    for track in tracks:
        track.csv.close()
    if failure is None and signals.pending is not None:        # arrived as the run was closing
        failure = Failure(EXIT_CODES[signals.pending], f"stopped: {REASONS[signals.pending]} as the run ended")
    if failure is None:
        print(done, file=messages)
        return 0
    print(f"simulator.py: {failure.text}; {kept(tracks, folder, plan)}", file=messages)
    return failure.code


def kept(tracks, folder, plan):
    """'N steps kept in out/' (the last step log.csv holds), and which of the last pictures were left
    out, if any."""
    if not tracks:
        return "nothing written" + (f" in {folder.folder}/" if folder is not None else "")
    steps = min(track.logged or 0 for track in tracks)
    left_out = [name for name in run_pictures.names(tracks)
                if (plan.frames or name != "index.html") and name not in folder.written]
    return f"{steps} steps kept in {folder.folder}/" + (f"; left out: {', '.join(left_out)}" if left_out else "")


def to_files(plan, signals, messages=None):
    """Run the plan's scenes side by side to their ends, writing frames, OBJs and log rows as they go,
    then the last pictures; one closing line on `messages` (stderr). Returns the exit code."""
    messages = messages or sys.stderr
    folder = plan.folder(signals)       # ValueError: refused, nothing written
    tracks, frame_log, failure, start = [], [], None, time.perf_counter()
    try:
        if plan.said:
            print(plan.said, file=messages, flush=True)
        warn(plan, messages)
        load_pygame(signals)
        for k, (scene, steps, label, tag) in enumerate(zip(plan.scenes, plan.steps, plan.labels, plan.tags)):
            tracks.append(recording.Track(scene, steps, simulator.simulate(scene, steps), label, tag,
                                          draw.run_color(k), folder))
        recording.record(tracks, folder, plan.stride, plan.frames, plan.forces, messages, frame_log)
    except ENDINGS as err:
        failure = failure_of(err, plan)
    wall = time.perf_counter() - start
    rest = f"; {closing_words(tracks)}" if tracks else ""
    return end(plan, signals, folder, tracks, frame_log, failure, messages,
               f"simulated {simulated(plan)} in {wall:.2f} s wall{rest}; {written(plan)} in "
               f"{where(plan, folder)}")


def simulated(plan):
    """'300 steps (3.00 s)', and for a comparison its runs'."""
    runs = [f"{steps} steps ({steps * scene.h:.2f} s)" for steps, scene in zip(plan.steps, plan.scenes)]
    if len(runs) == 1:
        return runs[0]
    return f"{runs[0]} x {len(runs)} runs" if len(set(runs)) == 1 else f"{len(runs)} runs: " + ", ".join(runs)


def written(plan):
    """What a run that ends well has written, in words."""
    logs = "log.csv" if len(plan.scenes) == 1 else "a log per run (" + ", ".join(
        files.log_csv(tag) for tag in plan.tags) + ")"
    if plan.scenes[0].hand is not None:
        logs += ", marks.csv" if len(plan.scenes) == 1 else ", the marks (" + ", ".join(
            files.marks_csv(tag) for tag in plan.tags) + ")"
    return (f"frames, OBJs, {logs}, plots.png, summary.png and index.html" if plan.frames
            else f"{logs}, plots.png and summary.png")


def where(plan, folder):
    """The run's folder as the closing line names it, and its page as a file:// URL (a click in most
    terminals opens it) when it has one."""
    return f"{folder.folder}/" + (f": {folder.url('index.html')}" if plan.frames else "")
