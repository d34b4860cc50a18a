"""The run driver: step one or more scenes side by side, logging each step as it ends.

A Track is one scene being run: it pulls StepRecords from simulator.simulate, turns each into a
Sample (one log.csv row, appended at once) and keeps what the plots, the summary and the page need.
`record` advances every track to each frame's time (frames.frame_steps), then has the frame drawn
with all of them (frames.FrameWriter), so a comparison (`--mu 0.1,0.11,0.2`) shows every run in each
frame. What a run says on the way (progress, warnings) is viewer.command.progress's; the pictures written at
its end, viewer.pictures'.
"""
from dataclasses import dataclass

import numpy as np

from analysis import diagnostics, log, wear
from viewer.output import files
from viewer.pictures.frames import FrameWriter, frame_steps
from viewer.command.progress import Progress, step_warnings

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
    """The figures of one state of a run (report is None for t = 0): log.COLUMN reads its named row."""
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
    hand_work: float = 0.0      # W_hand, summed over the steps so far (J; 0 without a hand)
    tip_x: float = None         # with a hand (the chalk): the tip's x (its lowest node), m
    tip_speed: float = None     # its speed along the board, m/s
    drive_speed: float = None   # the hand's targets' speed along the board over the last step, m/s
    normal_force: float = None  # the board's total normal force, N


class Track:
    """One scene being run: its records, its log.csv in `folder` (files.RunFolder), its samples and
    snapshots so far; `row` is the named row (log.values) of its latest state, `logged` the last step
    whose row log.csv holds."""

    def __init__(self, scene, steps, records, label, tag, color, folder):
        self.scene, self.steps, self.records = scene, steps, records
        self.label, self.tag, self.color, self.folder = label, tag, color, folder
        self.triangles = diagnostics.mesh_triangles(scene)
        self.tangent = diagnostics.tangent(scene)
        self.x = scene.x0
        self.v = scene.v0
        self.step, self.friction_work, self.hand_work = 0, 0.0, 0.0
        self.columns = log.columns(scene)       # log.csv's columns for this scene (with a hand: E_hand, W_hand, tip)
        self.marks = wear.Deposit() if scene.hand is not None else None   # the chalk's mark
        self.warned = set()         # the kinds of warning said so far (progress.step_warnings)
        self.rest_since = None      # t (s) from which every contact node has stayed below eps_v, so far
        self.csv, self.logged = folder.open_log(files.log_csv(tag), ",".join(self.columns)), None
        self.samples = History(MAX_SAMPLES)
        self.snapshots = History(MAX_SNAPSHOTS)     # (t, x) every SNAPSHOT_EVERY s of simulated time
        self._add(None, 0.0, 0.0)

    @property
    def t(self):
        return self.step * self.scene.h

    def _add(self, report, t, wall):
        """The Sample of the current state (after a step with `report`, or t = 0 without), logged at once."""
        scene, x, v = self.scene, self.x, self.v
        E = diagnostics.energies(scene, x, v, t)
        E0 = self.samples.items[0].energies["total"] if self.samples.items else E["total"]
        D = E0 + self.friction_work - E["total"] if scene.hand is None else \
            E0 + self.friction_work + self.hand_work - E["total"]
        tip = {}
        if scene.hand is not None:
            tip = diagnostics.tip_figures(scene, x, v, t)
        speeds = diagnostics.contact_speeds(scene, x, v)
        sticking, sliding = diagnostics.sticking_sliding(speeds, scene.epsv)
        sample = Sample(step=self.step, t=t, wall=wall, com=diagnostics.centre_of_mass(scene, x),
                        v_tangential=float(diagnostics.centre_of_mass(scene, v) @ self.tangent), report=report,
                        min_distance=report.min_distance if report else diagnostics.min_distance(scene, x),
                        energies=E, friction_work=self.friction_work,
                        numerical_dissipation=D, speeds=speeds, hand_work=self.hand_work, **tip,
                        sticking=sticking, sliding=sliding,
                        inverted=diagnostics.inverted_triangles(x, self.triangles))
        resting = diagnostics.at_rest(sticking, sliding)
        self.rest_since = (t if self.rest_since is None else self.rest_since) if resting else None
        self.row = log.values(sample, self.columns)           # the state's named figures, as log.csv writes them
        with self.folder.signals.held():        # the row and its count: both or neither
            self.csv.append(log.line(self.row))
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
        self.hand_work += diagnostics.hand_work(self.scene, self.x, self.t, record.t,      # from x^n, whose
                                                self.samples.last.energies.get("hand"))     # E_hand is known
        if self.marks is not None:
            self.marks.step(self.scene, self.x, record.x)       # what the tip left over the step
        self.x, self.v, self.step = record.x, record.v, record.index + 1
        self.friction_work += record.report.friction_work
        sample = self._add(record.report, record.t, record.wall)
        for kind, text in step_warnings(self.scene, sample.step, sample.t, record.report, sample.inverted).items():
            if kind not in self.warned:         # each kind said once, the first time
                self.warned.add(kind)
                progress.warn(self, text)
        progress.tick(self)

    def last_snapshot(self):
        """Keep the final state for summary.png, whenever it fell between two snapshots."""
        if self.snapshots.last[0] < self.t:
            self.snapshots.add((self.t, self.x.copy()))


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
