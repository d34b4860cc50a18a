"""The run driver: scenes stepped side by side (a Track each), a log.csv row as each step ends."""
import contextlib
import types

import numpy as np

import square_mesh

from analysis import diagnostics, log, wear
from viewer.command.progress import Progress, step_warnings
from viewer.output import files
from viewer.command import frame_process
from viewer.pictures.frames import frame_steps

SNAPSHOT_EVERY = 0.1        # s of simulated time between the states kept for summary.png
MAX_SAMPLES, MAX_SNAPSHOTS = 100_000, 2_000     # kept for the pictures, however long the run


class History:
    """Items in bounded memory: all until `cap`, then every 2nd, 4th, ...; `last` the newest."""

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


# One state's figures, as log.COLUMN reads them (report None at t = 0; W and D in J, speeds in m/s)
Sample = types.SimpleNamespace


class Track:
    """One scene run into `folder`; `row`: its latest log row; `logged`: log.csv's last step."""

    def __init__(self, scene, steps, records, label, tag, color, folder):
        self.scene, self.steps, self.records = scene, steps, records
        self.label, self.tag, self.color, self.folder = label, tag, color, folder
        self.triangles = square_mesh.triangles(*scene.cells)
        self.tangent = diagnostics.tangent(scene)
        self.x, self.v = scene.x0, scene.v0
        self.step, self.friction_work, self.hand_work, self.surface_work = 0, 0.0, 0.0, 0.0
        self.contact_work = 0.0     # what held the contact's prescribed rows (its `work`)
        self.columns = log.columns(scene)
        self.marks = wear.Deposit() if scene.hand is not None else None   # the chalk's mark
        self.warned = set()         # the kinds of warning said so far
        self.rest_since = None      # t from which every contact node has stayed below eps_v: stuck
        self.csv = folder.open_log(files.log_csv(tag), ",".join(self.columns))
        self.samples = History(MAX_SAMPLES)
        self.snapshots = History(MAX_SNAPSHOTS)     # (t, x) every SNAPSHOT_EVERY s
        self._add(None, 0.0, 0.0, self.lambdas(self.x))

    @property
    def t(self):
        return self.step * self.scene.h

    def lambdas(self, x):
        """lambda_k at x (diagnostics.lambdas), the tip's normal force and the mark's; None without
        a hand."""
        return None if self.scene.hand is None else diagnostics.lambdas(self.scene, x)

    def _add(self, report, t, wall, lam):
        """The Sample of the current state (`lam`: its lambdas), logged at once."""
        scene, x, v = self.scene, self.x, self.v
        E = diagnostics.energies(scene, x, v, t)
        E0 = self.samples.items[0].energies["total"] if self.samples.items else E["total"]
        tip = diagnostics.tip_figures(scene, x, v, t, lam) if scene.hand is not None else {}
        contact = {} if scene.contact is None else scene.contact.figures(scene, x)
        v_s = scene.surface_velocity(t)
        velocities = diagnostics.contact_velocities(scene, x, v, v_s)      # along self.tangent
        speeds = np.abs(velocities)
        sticking, sliding = diagnostics.sticking_sliding(speeds, scene.epsv)
        sample = Sample(
            step=self.step, t=t, wall=wall, com=diagnostics.centre_of_mass(scene, x),
            v_tangential=float(diagnostics.centre_of_mass(scene, v) @ self.tangent),
            report=report,
            min_distance=report.min_distance if report else diagnostics.min_distance(scene, x),
            energies=E, friction_work=self.friction_work, hand_work=self.hand_work,
            surface_work=self.surface_work, heat=self.surface_work - self.friction_work,
            surface_speed=float(v_s @ self.tangent),
            contact_work=self.contact_work, numerical_dissipation=E0 + self.friction_work
            + self.hand_work + self.contact_work - E["total"],
            speeds=speeds, sticking=sticking, sliding=sliding,
            contact_velocity=float(velocities.mean()) if len(velocities) else 0.0,
            inverted=diagnostics.inverted_triangles(x, self.triangles), **tip, **contact)
        if not diagnostics.at_rest(sticking, sliding):
            self.rest_since = None
        elif self.rest_since is None:
            self.rest_since = t
        self.row = log.values(sample, self.columns)
        with self.folder.signals.held():        # the row and its count: both or neither
            self.csv.append(log.line(self.row))
            self.logged = sample.step
        self.samples.add(sample)
        if self.snapshots.last is None or t >= self.snapshots.last[0] + SNAPSHOT_EVERY - 1e-9:
            self.snapshots.add((t, x.copy()))
        return sample

    def take(self, record, progress):
        """Log the StepRecord of the step from the current state (the window hands them in)."""
        E_hand = self.samples.last.energies.get("hand")      # at x^n, known
        self.hand_work += diagnostics.hand_work(self.scene, self.x, record.t, E_hand)
        if self.scene.contact is not None:
            self.contact_work += self.scene.contact.work(self.scene, self.x, self.v, record.x)
        lam = self.lambdas(record.x)        # at x^{n+1}: the mark's and the state's
        if self.marks is not None:
            self.marks.step(self.scene, self.x, record.x, lam)      # what the tip left
        self.x, self.v, self.step = record.x, record.v, record.index + 1
        self.friction_work += record.report.friction_work
        self.surface_work += record.report.surface_work
        sample = self._add(record.report, record.t, record.wall, lam)
        said = step_warnings(self.scene, sample.step, sample.t, record.report, sample.inverted)
        for kind in [kind for kind in said if kind not in self.warned]:   # each kind said once
            progress.warn(self, said[kind])
        self.warned.update(said)
        progress.tick(self)

    def last_snapshot(self):
        """Keep the final state for summary.png, whenever it fell between two snapshots."""
        if self.snapshots.last[0] < self.t:
            self.snapshots.add((self.t, self.x.copy()))


def record(tracks, folder, stride, frames, forces, messages, frame_log):
    """Run every track to its end, all in a frame every `stride` steps when `frames` (frame_log,
    once each is written)."""
    writer = None
    progress = Progress(tracks, messages)
    try:
        if frames:
            with folder.signals.held():     # a writer made is a writer closed
                writer = frame_process.frame_writer(tracks, folder, forces, frame_log)
        for j, targets in frame_steps(tracks, stride):
            for track, target in zip(tracks, targets):
                while track.step < min(target, track.steps):
                    track.take(next(track.records), progress)
            if writer is not None:
                writer.write(j)
    except BaseException:
        if writer is not None:
            with contextlib.suppress(OSError):      # the run says the error that stopped it
                writer.close()
        raise
    if writer is not None:
        writer.close()          # every frame sent written, or its error raised
    for track in tracks:
        track.last_snapshot()
