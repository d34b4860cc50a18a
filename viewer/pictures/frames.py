"""The frames of a run: when each is due (every `stride` steps of the smallest h, so that runs show
the same times), and writing one: a PNG of every run, an OBJ each, the page's figures."""
import math
from collections import namedtuple

import numpy as np

import square_mesh
from analysis import diagnostics
from viewer.output import files
from viewer.pictures import draw, page

# what the page shows beside frame `index` at time t: per run, its figures by name (page.figures)
FrameInfo = namedtuple("FrameInfo", "index t runs")


def frame_count(scenes, steps, stride):
    """How many frames runs of `steps` steps get: every `stride` steps of the least h, and the last
    (a stride longer than the runs: frame 0 and the last). The ratio is rounded up but for its
    last 1e-9 relative, the round-off of n h / (stride h_min)."""
    h_min = min(scene.h for scene in scenes)
    duration = max(n * scene.h for scene, n in zip(scenes, steps))
    return math.ceil(duration / (stride * h_min) * (1.0 - 1e-9)) + 1


def frame_steps(tracks, stride):
    """(j, each track's step for frame j): the last step it has reached by frame j's time; at the
    last frame at least its last step, so that each run takes every step it counts."""
    h_min = min(tr.scene.h for tr in tracks)
    duration = max(tr.steps * tr.scene.h for tr in tracks)
    last = frame_count([tr.scene for tr in tracks], [tr.steps for tr in tracks], stride) - 1
    for j in range(last + 1):
        t = min(j * stride * h_min, duration)
        targets = [math.floor(t / tr.scene.h + 1e-6) for tr in tracks]
        yield j, targets if j < last else [max(a, tr.steps) for a, tr in zip(targets, tracks)]


class FrameWriter:
    """Frame j of the tracks' current states into `folder`: one PNG with all of them, each one's
    OBJ, and its FrameInfo appended to `frame_log`; a signal waits until the frame is done."""

    def __init__(self, tracks, folder, forces, frame_log):
        self.tracks, self.folder, self.frame_log = tracks, folder, frame_log
        self.pygame = draw.load_pygame()
        self.fonts = draw.fonts(self.pygame)
        self.view = draw.View.of(tracks[0].scene)
        self.newton_per_metre = draw.newton_per_metre(tracks[0].scene) if forces else None
        # drawn and encoded in the same arrays frame after frame: a new megabyte array each frame
        # costs glibc an mmap and a page fault per 4 kB (benchmarks/README.md, frames)
        self.surface = self.pygame.Surface((self.view.size, self.view.height))
        self.rows = draw.new_rows(self.view.size, self.view.height)

    def write(self, j):
        """Frame j, then each track's OBJ (after its log row: the CSV is never behind)."""
        tracks, forces = self.tracks, self.newton_per_metre is not None
        self.view.follow(np.array([tr.samples.last.com for tr in tracks]))
        runs = [dict(frame_run(tr.scene, tr.x, tr.samples.last.report, tr.label, tr.color, forces),
                     marks=tr.marks) for tr in tracks]        # marks: the chalk's, else None
        t = max(tr.t for tr in tracks)
        surface, _ = draw.draw_frame(self.pygame, runs, t, self.view, self.fonts,
                                     self.newton_per_metre, surface=self.surface)
        png = draw.png_data(self.pygame, surface, rows=self.rows)
        with self.folder.signals.held():
            self.folder.write(files.frame_png(j), png)
            for tr in tracks:
                obj = square_mesh.obj_text(diagnostics.body(tr.scene, tr.x), *tr.scene.cells)
                self.folder.write(files.frame_obj(j, tr.tag), obj)
            self.frame_log.append(FrameInfo(j, t, [page.figures(tr.row) for tr in tracks]))


def frame_run(scene, x, report, label, color, forces):
    """One run as draw.draw_frame takes it; with `forces`, the contact forces at x and the friction
    force of the step that ended at x (its StepReport's, with the mu lambda and T it ended with)."""
    run = {"scene": scene, "x": x, "label": label, "color": color}
    if forces:
        run["normal"] = diagnostics.normal_forces(scene, x)
        friction = report.friction_force if report is not None else None
        run["friction"] = np.zeros_like(x) if friction is None else friction
    return run
