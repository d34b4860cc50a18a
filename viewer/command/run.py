"""A run of the command line, to files or in the window: its folder, its signals, its ending (at
most 3 lines, progress.folded) and an exit code, 0, 1, or 128 + a stopping signal's number: 130,
143, 129, 131 (docs/output.md, "How a run ends")."""
import collections
import contextlib
import signal
import sys
import time
from dataclasses import dataclass

import simulator
import time_integrator
from analysis.closing import closing_words
from scenes import UNITS
from viewer.command import progress, recording
from viewer.command.startup import EXIT_CODES, REASONS, WhileStarting
from viewer.output import files
from viewer.pictures import draw, run_pictures
from viewer.pictures.frames import frame_count


class Stopped(BaseException):
    """SIGINT (Ctrl+C), SIGTERM, SIGHUP or SIGQUIT (startup.EXIT_CODES): the run stops, says so
    in its ending and keeps what it wrote."""

    def __init__(self, signum):
        super().__init__(signum)
        self.code, self.reason = EXIT_CODES[signum], REASONS[signum]


class Signals:
    """`with Signals():` the signals of EXIT_CODES raise Stopped, at once or as `held()` ends.
    Each is noted before it is raised: CPython drops an exception raised in a handler inside some C
    code (an import's abc checks) or a weakref callback, so one noted and not yet raised is raised
    by the next `check()` (every `held()` ends with one: each step's log row, each file). One
    Stopped until the ending has said it (`said`): a signal meanwhile only waits."""

    def __init__(self):
        self.depth, self.pending, self.previous, self.unraisable = 0, None, {}, None
        self.raised = False         # a Stopped raised and not yet said

    def __enter__(self):
        with contextlib.suppress(ValueError):       # not the main thread: signals left alone
            self.previous = {signum: signal.signal(signum, self._handle) for signum in EXIT_CODES}
        self.unraisable, sys.unraisablehook = sys.unraisablehook, self._unraisable
        return self

    def __exit__(self, *exc):
        """The handlers handed back, signals only waiting meanwhile; start-up's, which would say
        'while starting; nothing written' after the run's ending, give way to SIG_IGN."""
        self.close()
        for signum, handler in self.previous.items():
            starting = isinstance(handler, WhileStarting)
            signal.signal(signum, signal.SIG_IGN if starting else handler)
        sys.unraisablehook = self.unraisable

    def _handle(self, signum, frame):
        self.pending = self.pending or signum
        if not self.depth and not self.raised:
            self.raised = True
            raise Stopped(self.pending)         # the first noted: a dropped one's, if any

    def _unraisable(self, unraisable):
        """A Stopped dropped in a weakref callback or __del__: no traceback, `check()` raises it."""
        if isinstance(unraisable.exc_value, Stopped):
            self.raised = False                 # the next signal raises it again
        else:
            self.unraisable(unraisable)

    def check(self):
        """Raise Stopped for a signal noted and not yet raised, unless a block holds it."""
        if self.depth == 0 and self.pending is not None:
            signum, self.pending, self.raised = self.pending, None, True
            raise Stopped(signum)

    @contextlib.contextmanager
    def held(self):
        """Signals wait until the block ends (a file written whole, pygame loaded)."""
        self.depth += 1
        try:
            yield
        finally:
            self.depth -= 1
        self.check()

    def said(self):
        """The run's ending says how it failed: a signal noted so far is not raised again, and
        the next one stops what is left (the last pictures)."""
        self.pending, self.raised = None, False

    def close(self):
        """The run is ending: from here on a signal only waits."""
        self.depth += 1


@dataclass
class Plan:
    """What the command line asks for (`out` None: a new folder under output/)."""
    scenes: list
    labels: list
    tags: list
    steps: list
    out: str
    stride: int
    frames: bool
    forces: bool
    said: str = None        # the run's first line (cli.decimal_comma), or None
    kind: str = "square"    # the --scene, as output/<kind>-<date>-<time> names it

    def folder(self, signals):
        """The run's folder (files.RunFolder.make), probed with the longest name of each kind."""
        last = frame_count(self.scenes, self.steps, self.stride) - 1
        names = [files.log_csv(tag) for tag in self.tags] + ["summary.png", "plots.png"]
        if self.scenes[0].hand is not None:
            names += [files.marks_csv(tag) for tag in self.tags]
        if self.frames:
            names += ["index.html", files.frame_png(last)]
            names += [files.frame_obj(last, tag) for tag in self.tags]
        return files.RunFolder.make(self.out, self.kind, names, signals)


def warn(plan, messages):
    """Each scene's warnings, one line each."""
    for label, scene in zip(plan.labels, plan.scenes):
        for warning in scene.warnings:
            progress.warning(messages, label if len(plan.scenes) > 1 else None, warning)


def summary_header(plan):
    """The parameters the runs share, a comparison's labels: summary.png's and the page's text."""
    scene, p = plan.scenes[0], plan.scenes[0].params
    solver = (f"h = {scene.h:g} s   k = {p['k']:g} N/m   dhat = {scene.dhat:g} m   kappa = "
              f"{scene.kappa:g}   eps_v = {scene.epsv:g} m/s   tol = {scene.tol:g} m/s")
    if scene.hand is not None:
        how = "dragged" if p["drag"] else "pushed"
        lines = [f"chalk {p['length'] * 100:g} x {p['width'] * 100:g} cm, {how} at tilt = "
                 f"{p['tilt']:g} deg   grip k_hand = {p['k_hand']:g} N/m   drive = {p['drive']:g} "
                 f"m/s   mu_s = {p['mu_s']:g}   mu = {scene.mu:g}   v_c = {p['v_c']:g} m/s", solver]
    elif plan.kind in UNITS:
        lines = [UNITS[plan.kind].HEADER.format(**p), solver]
    elif scene.surface is not None:
        lines = [f"dish {p['width'] * 100:g} x {p['height'] * 100:g} cm, {p['mass']:g} kg   cloth "
                 f"pulled L = {p['pull_length']:g} m at U = {p['pull_speed']:g} m/s from t = "
                 f"{p['t_pull']:g} s   mu = {scene.mu:g}", solver]
    else:
        normal = None if scene.n is None else [round(float(c), 4) for c in scene.n]
        lines = [f"mu = {scene.mu:g}   h = {scene.h:g} s   k = {p['k']:g} N/m   "
                 f"n_seg = {p['n_seg']}",
                 f"slope normal = {normal}   dhat = {scene.dhat:g} m   kappa = {scene.kappa:g}   "
                 f"eps_v = {scene.epsv:g} m/s"]
    if len(plan.scenes) > 1:
        lines.insert(0, "comparison: " + ", ".join(plan.labels) + "; otherwise as the first:")
    return lines


Failure = collections.namedtuple("Failure", "code text")     # how a run ended early
ENDINGS = (Stopped, OSError, time_integrator.SimulationError, ValueError)   # end a run early


def failure_of(err, plan, when=""):
    """The Failure an exception of ENDINGS ends a run with, `when` it came."""
    if isinstance(err, Stopped):
        return Failure(err.code, f"stopped: {err.reason}{when}")
    if isinstance(err, OSError):
        where = plan.out or "the run's folder"
        return Failure(1, f"error: {files.cannot_write(err, where)}")
    if isinstance(err, time_integrator.SimulationError):    # its figures after a '; '
        figures = f"; {err.figures_said}" if err.figures else ""
        return Failure(1, f"stopped: simulation failed: {err.what}{figures}")
    return Failure(1, f"stopped: {err}{when}")        # a number the checks did not foresee


def end(plan, signals, folder, tracks, frame_log, failure, messages, done):
    """How every run ends: the last pictures of the steps kept, then `say`; returns the exit code.
    A signal that comes between two steps of this, outside their try, is the run's ending too."""
    if failure is not None:
        signals.said()
    try:
        if tracks:
            try:
                for track in tracks:
                    track.last_snapshot()
                header = summary_header(plan)
                run_pictures.write(tracks, folder, plan.stride, plan.frames, frame_log, header,
                                   plan.kind)
            except ENDINGS as err:
                failure = failure or failure_of(err, plan, " while writing the last pictures")
        signals.close()
    except Stopped as err:          # came between two steps of the ending, outside their try
        failure = failure or failure_of(err, plan, " as the run ended")
    return say(plan, signals, folder, tracks, failure, messages, done)


def say(plan, signals, folder, tracks, failure, messages, done):
    """The logs closed, the folder's claim released, the ending (`done` if all went well and the
    folder is still there); returns the exit code. Signals only wait from here on."""
    signals.close()
    for track in tracks:
        track.csv.close()
    if folder is not None:
        folder.release()
    if failure is None and signals.pending is not None:        # came as the run was closing
        failure = failure_of(Stopped(signals.pending), plan, " as the run ended")
    if failure is None and folder is not None and folder.lost:
        failure = Failure(1, "error: the run's folder was deleted or moved")
    if failure is None:
        print(done, file=messages)
        return 0
    said = f"simulator.py: {failure.text}; {kept(tracks, folder, plan)}"
    print(progress.folded(said), file=messages)
    return failure.code


def kept(tracks, folder, plan):
    """'N steps kept in out/' (the last step log.csv holds; a comparison's logs, 'N to M' where
    they differ), the last pictures left out and its page's link where it was written; nothing
    kept where the folder disappeared."""
    if folder is not None and folder.lost:
        return f"nothing kept: {files.shown(folder.folder)}/ disappeared as the run wrote it"
    if not tracks:
        return "nothing written" + ("" if folder is None else f" in {files.shown(folder.folder)}/")
    fewest, most = min(track.logged for track in tracks), max(track.logged for track in tracks)
    steps = fewest if fewest == most else f"{fewest} to {most}"
    left_out = [name for name in run_pictures.names(tracks)
                if (plan.frames or name != "index.html") and name not in folder.written]
    said = f"; left out: {', '.join(left_out)}" if left_out else ""
    page = f"; the page: {folder.url('index.html')}" if "index.html" in folder.written else ""
    return f"{steps} steps kept in {files.shown(folder.folder)}/{said}{page}"


def to_files(plan, signals, messages=None):
    """Run the plan's scenes side by side into files, one closing line on `messages`; exit code."""
    messages = messages or sys.stderr
    folder = plan.folder(signals)       # ValueError: refused, nothing written
    tracks, frame_log, failure, done, start = [], [], None, None, time.perf_counter()
    try:
        if plan.said:
            print(plan.said, file=messages, flush=True)
        warn(plan, messages)
        with signals.held():            # pygame loads whole
            draw.load_pygame()
        for k, (scene, steps, label, tag) in enumerate(
                zip(plan.scenes, plan.steps, plan.labels, plan.tags)):
            records = simulator.simulate(scene, steps)
            color = draw.run_color(k)
            tracks.append(recording.Track(scene, steps, records, label, tag, color, folder))
        recording.record(tracks, folder, plan.stride, plan.frames, plan.forces, messages, frame_log)
        done = closing(plan, folder, tracks, time.perf_counter() - start)
        signals.check()
    except ENDINGS as err:          # the closing words too: a signal as they are found
        failure = failure_of(err, plan)
    try:
        return end(plan, signals, folder, tracks, frame_log, failure, messages, done)
    except Stopped as err:          # came as the ending began
        failure = failure or failure_of(err, plan, " as the run ended")
        return say(plan, signals, folder, tracks, failure, messages, done)


def closing(plan, folder, tracks, wall):
    """A finished run's closing in lines of at most progress.WIDTH columns (a path may run longer),
    3 at most where each run's words fit: what was simulated and the wall time; what it showed
    (closing_words, after it or on lines of their own, broken at their '; '); what was written
    and where."""
    words = f"; {closing_words(tracks)}" if tracks else ""
    return "\n".join([progress.folded(f"simulated {simulated(plan)} in {wall:.2f} s wall{words}"),
                      f"wrote {written(plan, folder, tracks)}{where(plan, folder)}"])


def simulated(plan):
    """'300 steps (3.00 s)', and for a comparison its runs'."""
    runs = [f"{steps} steps ({steps * scene.h:.2f} s)"
            for steps, scene in zip(plan.steps, plan.scenes)]
    if len(set(runs)) == 1:
        return runs[0] + (f" x {len(runs)} runs" if len(runs) > 1 else "")
    durations = {f"{steps * scene.h:.2f}" for steps, scene in zip(plan.steps, plan.scenes)}
    if len(durations) == 1:
        return f"{len(runs)} runs of {durations.pop()} s: {', '.join(map(str, plan.steps))} steps"
    return f"{len(runs)} runs: " + ", ".join(runs)


def written(plan, folder, tracks):
    """How many files a run that ends well has written: those so far and its last pictures."""
    last = [name for name in run_pictures.names(tracks) if plan.frames or name != "index.html"]
    return f"{len(folder.written | set(last))} files"


def where(plan, folder):
    """The run's page as a file:// URL (most terminals open it with a click; the folder is the
    page's), else its folder."""
    if plan.frames:
        return f", the page: {folder.url('index.html')}"
    return f" in {files.shown(folder.folder)}/"
