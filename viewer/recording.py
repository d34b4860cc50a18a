"""Step one or more scenes side by side and write what a run shows: log.csv rows, frames and OBJs.

A Track is one scene being run: it pulls StepRecords from simulator.simulate, turns each into a
Sample (one log.csv row, appended at once) and keeps what the plots, the summary and the page need.
`record` advances every track to each frame's time, then draws the frame with all of them, so a
comparison (`--mu 0.1,0.11,0.2`) shows every run in each frame. Frames come every `stride` steps
of the smallest h, numbered 0, 1, 2, ...
"""
import math
import time
from dataclasses import dataclass

import numpy as np

import square_mesh
from viewer import diagnostics, draw, files, log, page, plots, summary

PROGRESS_EVERY = 2.0        # s of wall time: a progress line at least this often, whatever the run's length
SNAPSHOT_EVERY = 0.1        # s of simulated time between the states kept for summary.png
MAX_SAMPLES, MAX_SNAPSHOTS = 100_000, 2_000     # kept for the pictures, however long the run


class History:
    """What a run keeps for its pictures, in bounded memory whatever its length: every item until
    `cap`, then every other one (the first kept) and from then on every 2nd, 4th, ... new one.
    `last` is always the newest item; `all()` the kept ones and the newest."""

    def __init__(self, cap):
        self.items, self.cap, self.every, self.seen, self.last = [], cap, 1, 0, None

    def add(self, item):
        self.last = item
        if self.seen % self.every == 0:
            self.items.append(item)
            if len(self.items) > self.cap:
                self.items, self.every = self.items[::2], 2 * self.every
        self.seen += 1

    def all(self):
        return self.items if self.items[-1] is self.last else self.items + [self.last]


@dataclass
class Sample:
    """The figures of one state of a run: one log.csv row (report is None for t = 0)."""
    step: int
    t: float
    wall: float
    com: np.ndarray
    v_tangential: float         # centre-of-mass velocity along the slope's tangent, m/s
    report: object
    min_distance: float
    energies: dict
    friction_work: float        # W_friction, summed over the steps so far (J, <= 0)
    numerical_dissipation: float  # D = E(0) + W_friction - E: what implicit Euler has taken out (J)
    speeds: np.ndarray          # tangential speeds of the contact nodes (m/s)
    sticking: int
    sliding: int
    inverted: int               # mesh triangles with negative signed area


class Track:
    """One scene being run: its records, its log.csv in `folder` (files.OutputFolder), its samples and
    snapshots so far. `logged` is the last step whose row log.csv holds."""

    def __init__(self, scene, steps, records, label, tag, color, folder):
        self.scene, self.steps, self.records = scene, steps, records
        self.label, self.tag, self.color, self.folder = label, tag, color, folder
        self.triangles = diagnostics.mesh_triangles(scene)
        self.tangent = diagnostics.tangent(scene)
        self.x = scene.x0
        self.v = scene.v0
        self.step, self.friction_work, self.inverted_at, self.stalled_at = 0, 0.0, None, None
        self.rest_since = None      # t (s) from which every contact node has stayed below eps_v, so far
        self.csv, self.logged = folder.open_log(files.log_csv(tag), ",".join(log.COLUMNS)), None
        self.samples = History(MAX_SAMPLES)
        self.snapshots = History(MAX_SNAPSHOTS)     # (t, x) every SNAPSHOT_EVERY s of simulated time
        self._add(None, 0.0, 0.0)

    @property
    def t(self):
        return self.step * self.scene.h

    def _add(self, report, t, wall):
        """The Sample of the current state (after a step with `report`, or t = 0 without), logged at once."""
        scene, x, v = self.scene, self.x, self.v
        E = diagnostics.energies(scene, x, v)
        E0 = self.samples.items[0].energies["total"] if self.samples.items else E["total"]
        speeds = diagnostics.contact_speeds(scene, x, v)
        sticking, sliding = diagnostics.sticking_sliding(speeds, scene.epsv)
        sample = Sample(step=self.step, t=t, wall=wall, com=np.average(x, axis=0, weights=scene.m),
                        v_tangential=float(np.average(v, axis=0, weights=scene.m) @ self.tangent), report=report,
                        min_distance=report.min_distance if report else diagnostics.min_distance(scene, x),
                        energies=E, friction_work=self.friction_work,
                        numerical_dissipation=E0 + self.friction_work - E["total"], speeds=speeds,
                        sticking=sticking, sliding=sliding,
                        inverted=diagnostics.inverted_triangles(x, self.triangles))
        resting = diagnostics.at_rest(sticking, sliding)
        self.rest_since = (t if self.rest_since is None else self.rest_since) if resting else None
        with self.folder.signals.held():        # the row and its count: both or neither
            self.csv.append(log.row(sample))
            self.logged = sample.step
        self.samples.add(sample)
        if self.snapshots.last is None or t >= self.snapshots.last[0] + SNAPSHOT_EVERY - 1e-9:
            self.snapshots.add((t, x.copy()))
        return sample

    def advance(self, target, progress):
        """Step until `target` steps are done (or the scene's last step), logging each step."""
        while self.step < min(target, self.steps):
            self.take(next(self.records), progress)

    def take(self, record, progress):
        """Log the StepRecord of the step from the current state (the live window hands them in)."""
        self.x, self.v, self.step = record.x, record.v, record.index + 1
        self.friction_work += record.report.friction_work
        sample = self._add(record.report, record.t, record.wall)
        if sample.inverted and self.inverted_at is None:
            self.inverted_at = sample
            progress.warn_inverted(self, sample)
        if record.report.stalled and self.stalled_at is None:
            self.stalled_at = sample
            progress.warn_stalled(self, sample)
        progress.tick(self)

    def last_snapshot(self):
        """Keep the final state for summary.png, whenever it fell between two snapshots."""
        if self.snapshots.last[0] < self.t:
            self.snapshots.add((self.t, self.x.copy()))


class Progress:
    """Progress lines on `log`: every tenth of the first run and at least every PROGRESS_EVERY s of
    wall time, whatever the run's length (a run of 1e308 steps says how far it got)."""

    def __init__(self, tracks, log):
        self.log, self.tracks = log, tracks
        self.last = time.perf_counter()
        self.tenth = max(1, tracks[0].steps // 10)

    def tick(self, track):
        now = time.perf_counter()
        if (track is self.tracks[0] and track.step % self.tenth == 0) or now - self.last > PROGRESS_EVERY:
            self.last = now
            parts = [f"{tr.label + ': ' if len(self.tracks) > 1 else ''}newton={tr.samples.last.report.newton_iterations}"
                     f"  residual={tr.samples.last.report.residual:.1e}  min_d={tr.samples.last.min_distance:.2e}"
                     for tr in self.tracks if tr.samples.last.report is not None]
            print(f"step {track.step}/{track.steps}  t={track.t:.2f}s  " + "  ".join(parts), file=self.log, flush=True)

    def warn_stalled(self, track, sample):
        self.warn(track, stalled_warning(sample.step, sample.t, sample.report.residual, track.scene.tol))

    def warn_inverted(self, track, sample):
        self.warn(track, inverted_warning(sample.step, sample.t, sample.inverted, len(track.triangles)))

    def warn(self, track, text):
        who = f"{track.label}: " if len(self.tracks) > 1 else ""
        print(f"simulator.py: warning: {who}{text}", file=self.log, flush=True)


def rest_words(tracks):
    """When each run came to rest (every contact node below eps_v from then on, as log.csv's
    contacts_sliding says), in words: 'came to rest at t = 5.53 s', or 'still sliding at t = 3.00 s'."""
    def words(track):
        if track.rest_since is None:
            return f"{'still sliding' if track.samples.last.sliding else 'not at rest'} at t = {track.t:.2f} s"
        return f"came to rest at t = {track.rest_since:.2f} s"
    if len(tracks) == 1:
        return "the square " + words(tracks[0])
    return "; ".join(f"{track.label}: {words(track)}" for track in tracks)


def stalled_warning(step, t, residual, tol):
    """The first step Newton stopped at float64's round-off floor, in words."""
    return (f"at step {step} (t = {t:.2f} s) Newton stopped at float64's round-off floor, residual {residual:.2g} "
            f"m/s above tol = {tol:g} m/s (E can no longer resolve a smaller step); the run goes on, such steps "
            f"are flagged newton_stalled in log.csv")


def inverted_warning(step, t, inverted, triangles):
    """The first step the mesh folded over, in words."""
    return (f"at step {step} (t = {t:.2f} s) {inverted} of {triangles} mesh triangles are inverted (the square "
            f"folded over; the mass-spring model has no inversion barrier): use a stiffer --k or a smaller --h")


def frame_steps(tracks, stride):
    """Frame j's target step for each track: every `stride` steps of the smallest h, up to the end."""
    h_min = min(tr.scene.h for tr in tracks)
    duration = max(tr.steps * tr.scene.h for tr in tracks)
    for j in range(frame_count([tr.scene for tr in tracks], [tr.steps for tr in tracks], stride)):
        t = min(j * stride * h_min, duration)
        targets = []
        for tr in tracks:
            q = t / tr.scene.h
            targets.append(round(q) if abs(q - round(q)) < 1e-6 else math.floor(q))
        yield j, targets


@dataclass
class FrameInfo:
    """What the page shows beside frame j: per track, (step, t, newton, residual, min_d, sticking, sliding)."""
    index: int
    t: float
    runs: list


class FrameWriter:
    """Frame j of the tracks' current states: one PNG with all of them, each one's OBJ, and the
    FrameInfo the page shows beside it (appended to `frame_log` once they are written into `folder`);
    a signal waits until the frame is done."""

    def __init__(self, tracks, folder, forces, frame_log):
        self.tracks, self.folder, self.frame_log = tracks, folder, frame_log
        self.pygame = draw.load_pygame()
        self.fonts = draw.fonts(self.pygame)
        self.view = draw.View()
        self.newton_per_metre = draw.newton_per_metre(tracks[0].scene) if forces else None

    def write(self, j):
        """Frame j with every track, then each track's OBJ (after its log rows: the CSV is never behind)."""
        tracks, forces = self.tracks, self.newton_per_metre is not None
        self.view.follow(np.array([tr.samples.last.com for tr in tracks]))
        runs = [frame_run(tr.scene, tr.x, tr.samples.last.report, tr.label, tr.color, forces) for tr in tracks]
        surface, _ = draw.draw_frame(self.pygame, runs, max(tr.t for tr in tracks), self.view, self.fonts,
                                     self.newton_per_metre)
        with self.folder.signals.held():
            self.folder.write(files.frame_png(j), draw.png_data(self.pygame, surface))
            for tr in tracks:
                self.folder.write(files.frame_obj(j, tr.tag), square_mesh.obj_text(tr.x, tr.scene.n_seg))
            self.frame_log.append(FrameInfo(j, max(tr.t for tr in tracks), [_figures(tr) for tr in tracks]))


def frame_count(scenes, steps, stride):
    """How many frames frame_steps gives for runs of `steps` steps: every `stride` steps of the smallest
    h, and the last state."""
    h_min = min(scene.h for scene in scenes)
    return math.ceil(max(n * scene.h for scene, n in zip(scenes, steps)) / (stride * h_min) - 1e-9) + 1


def record(tracks, folder, stride, frames, forces, messages, frame_log):
    """Run every track to its end, writing log rows as steps end and a frame (and OBJs) every
    `stride` steps when `frames`; appends a FrameInfo per frame to `frame_log`."""
    writer = FrameWriter(tracks, folder, forces, frame_log) if frames else None
    progress = Progress(tracks, messages)
    for j, targets in frame_steps(tracks, stride):
        for tr, target in zip(tracks, targets):
            tr.advance(target, progress)
        if writer is not None:
            writer.write(j)
    for tr in tracks:
        tr.last_snapshot()


def _figures(track):
    """The figures the page shows for a track's latest state (page.FIGURES; None where there is none)."""
    s = track.samples.last
    residual = s.report.residual if s.report else math.nan
    return [s.step, round(s.t, 6), s.report.newton_iterations if s.report else 0,
            float(f"{residual:.3e}") if math.isfinite(residual) else None,
            float(f"{s.min_distance:.4e}") if math.isfinite(s.min_distance) else None, s.sticking, s.sliding]


def frame_run(scene, x, report, label, color, forces):
    """One run as draw.draw_frame takes it; with `forces`, the contact forces at x and the friction
    force of the step that ended at x (its StepReport's: with the mu*lambda and T it ended with)."""
    run = {"scene": scene, "x": x, "label": label, "color": color}
    if forces:
        run["normal"] = diagnostics.normal_forces(scene, x)
        friction = report.friction_force if report is not None else None
        run["friction"] = np.zeros_like(x) if friction is None else friction
    return run


def finish(tracks, folder, stride, frames, frame_log, header):
    """The pictures of the whole run, from what the tracks kept, each written whole as it is done:
    summary.png, plots.png and, when frames were written, index.html to play them."""
    pygame = draw.load_pygame()
    header = header + [rest_words(tracks) + " (every contact below eps_v from then on)"]
    folder.write("summary.png", draw.png_data(pygame, summary.draw_summary(pygame, tracks, header), exact=True))
    surface, axis = plots.draw_plots(pygame, tracks)
    folder.write("plots.png", draw.png_data(pygame, surface, exact=True))
    if frames:
        fps = 1.0 / (stride * min(tr.scene.h for tr in tracks))
        title = "Square on a slope: " + ", ".join(tr.label for tr in tracks)
        folder.write("index.html", page.page_html(title, [tr.label for tr in tracks], frame_log, fps, axis,
                                                  surface.get_width(), note=" ".join(header),
                                                  rest=[tr.rest_since for tr in tracks]))
