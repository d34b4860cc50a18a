"""What a run says on stderr as it goes, to files or in the window: progress lines and warnings."""
import re
import textwrap
import time

import square_mesh

PROGRESS_EVERY = 2.0        # s of wall time: a progress line at least this often
WIDTH = 100                 # columns: every line a run prints fits (a path the user gave may not)


class Progress:
    """Progress lines at every tenth of the first run and at least every PROGRESS_EVERY s; the line
    of step N waits until every run has logged its own step N (or ended)."""

    def __init__(self, tracks, log):
        self.log, self.tracks = log, tracks
        self.last = time.perf_counter()
        self.tenth = max(1, tracks[0].steps // 10)
        self.due = {}               # step N -> {track index: its figures at step N}, not yet said

    def tick(self, track):
        """`track` has just logged its step `track.step`."""
        now = time.perf_counter()
        if track.step % self.tenth == 0:
            self.due.setdefault(track.step, {})
        going = [tr.step for tr in self.tracks if tr.step < tr.steps]
        if now - self.last > PROGRESS_EVERY and going:      # the next step all runs going reach
            self.last = now
            self.due.setdefault(1 + max(going), {})
        if track.step in self.due:
            self.due[track.step][self.tracks.index(track)] = self.words(track)
        for n in sorted(self.due):
            if all(k in self.due[n] or tr.step == tr.steps for k, tr in enumerate(self.tracks)):
                self.say(n, self.due.pop(n))

    def words(self, track):
        """One run's figures of the step it has just logged: (t, newton, residual, min_d)."""
        last = track.samples.last
        return (track.t, last.report.newton_iterations, last.report.residual, last.min_distance)

    def say(self, n, runs):
        """The line of step n, within WIDTH columns: the first run's step count and time, and the
        run's figures; a comparison's Newton iterations run by run ('-': a run already ended), its
        largest residual and its least min_d (and each run's t where the runs' h differ); where
        that is wider than WIDTH, the least to the most of them ('newton=1-6')."""
        first = self.tracks[min(runs)]
        _, newton, residual, min_d = zip(*runs.values())
        line = f"step {n}/{first.steps}  t={n * first.scene.h:.2f}s  "
        if len(self.tracks) == 1:
            print(f"{line}newton={newton[0]}  residual={residual[0]:.1e}  min_d={min_d[0]:.2e}",
                  file=self.log, flush=True)
            return
        each = [runs.get(k) for k in range(len(self.tracks))]
        ts, counts = ([None if r is None else r[k] for r in each] for k in (0, 1))
        tail = f"  residual<={max(residual):.1e}  min_d>={min(min_d):.2e}"
        for say in (listed, span):          # run by run; where that is too wide, least to most
            t = say(ts, ".2f") if len({tr.scene.h for tr in self.tracks}) > 1 else (
                f"{n * first.scene.h:.2f}")
            line = f"step {n}/{first.steps}  t={t}s  newton={say(counts, 'd')}{tail}"
            if columns(line) <= WIDTH:
                break
        print(line, file=self.log, flush=True)

    def warn(self, track, text):
        warning(self.log, track.label if len(self.tracks) > 1 else None, text)


def listed(figures, form):
    """Each run's figure in `form`, '-' for a run already ended (None): '1,2,-'."""
    return ",".join("-" if f is None else format(f, form) for f in figures)


def span(figures, form):
    """The least to the most of the figures (None aside) in `form`: '1-6'; '3' where they agree."""
    low, high = (format(f(x for x in figures if x is not None), form) for f in (min, max))
    return low if low == high else f"{low}-{high}"


def warning(log, label, text):
    """One warning, after the run's label in a comparison: lines of at most WIDTH columns, broken
    between words (a path stays whole), the next ones indented."""
    said = f"simulator.py: warning: {label + ': ' if label else ''}{text}"
    print(wrapped(said), file=log, flush=True)


def columns(line):
    """The columns `line` takes, its paths aside (a word with two slashes): a path may run longer
    than WIDTH."""
    return len(re.sub(r"\S*[/\\]\S*[/\\]\S*", "", line))


def folded(text):
    """`text`'s parts (separated by '; ') in lines of at most WIDTH columns (paths aside), broken
    only between two parts."""
    lines = []
    for part in text.split("; "):
        if lines and columns(f"{lines[-1]}; {part}") <= WIDTH:
            lines[-1] += f"; {part}"
        else:
            lines.append(part)
    return "\n".join(lines)


def wrapped(text, indent="  "):
    """`text` in lines of at most WIDTH columns, broken at spaces only: a word longer (a path the
    user gave) runs on."""
    return "\n".join(textwrap.wrap(text, WIDTH, subsequent_indent=indent, break_long_words=False,
                                   break_on_hyphens=False))


def step_warnings(scene, step, t, report, inverted):
    """The warnings about the step that ended at `step`, by kind: "inverted", "stalled"."""
    said, at = {}, f"at step {step} (t = {t:.2f} s)"
    if inverted:
        cells = len(square_mesh.triangles(*scene.cells))
        said["inverted"] = (f"{at} {inverted} of {cells} mesh triangles are inverted ({scene.body} "
                            f"folded over, docs/limits.md): use a stiffer --k or a smaller --h")
    if report.stalled:
        said["stalled"] = (f"{at} Newton stopped at float64's round-off floor, residual "
                           f"{report.residual:.2g} m/s above tol = {scene.tol:g} m/s; the run goes "
                           f"on (newton_stalled in log.csv)")
    return said
