"""The frames of a run: when each is due, and writing it: one PNG with every run's square, an OBJ per
run, and what the page shows beside it.

Frames come every `stride` steps of the smallest h (so a comparison of time steps shows the runs at
the same times), numbered 0, 1, 2, ..., the last at the end of the longest run.
"""
import math
from dataclasses import dataclass

import numpy as np

import square_mesh
from analysis import diagnostics
from viewer.pictures import draw, page
from viewer.output import files


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
    """What the page shows beside frame j at time t: per track, its figures by name (page.figures)."""
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
        self.view = draw.View.of(tracks[0].scene)
        self.newton_per_metre = draw.newton_per_metre(tracks[0].scene) if forces else None

    def write(self, j):
        """Frame j with every track, then each track's OBJ (after its log rows: the CSV is never behind)."""
        tracks, forces = self.tracks, self.newton_per_metre is not None
        self.view.follow(np.array([tr.samples.last.com for tr in tracks]))
        runs = [frame_run(tr.scene, tr.x, tr.samples.last.report, tr.label, tr.color, forces) for tr in tracks]
        for run, tr in zip(runs, tracks):
            run["marks"] = tr.marks if tr.scene.hand is not None else None
        surface, _ = draw.draw_frame(self.pygame, runs, max(tr.t for tr in tracks), self.view, self.fonts,
                                     self.newton_per_metre)
        with self.folder.signals.held():
            self.folder.write(files.frame_png(j), draw.png_data(self.pygame, surface))
            for tr in tracks:
                self.folder.write(files.frame_obj(j, tr.tag), square_mesh.obj_text(tr.x, *tr.scene.cells))
            self.frame_log.append(FrameInfo(j, max(tr.t for tr in tracks), [page.figures(tr.row) for tr in tracks]))


def frame_count(scenes, steps, stride):
    """How many frames frame_steps gives for runs of `steps` steps: every `stride` steps of the smallest
    h, and the last state."""
    h_min = min(scene.h for scene in scenes)
    return math.ceil(max(n * scene.h for scene, n in zip(scenes, steps)) / (stride * h_min) - 1e-9) + 1


def frame_run(scene, x, report, label, color, forces):
    """One run as draw.draw_frame takes it; with `forces`, the contact forces at x and the friction
    force of the step that ended at x (its StepReport's: with the mu*lambda and T it ended with)."""
    run = {"scene": scene, "x": x, "label": label, "color": color}
    if forces:
        run["normal"] = diagnostics.normal_forces(scene, x)
        friction = report.friction_force if report is not None else None
        run["friction"] = np.zeros_like(x) if friction is None else friction
    return run
