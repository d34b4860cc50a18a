"""The frames of a run: when each is due (every `stride` steps of the smallest h, so that runs show
the same times), and writing one: a PNG of every run, an OBJ each, the page's figures."""
import math
import struct
import zlib
from collections import namedtuple

import numpy as np

import square_mesh
from analysis import diagnostics
from viewer.output import files
from viewer.pictures import draw, page

# what the page shows beside frame `index` at time t: per run, its figures by name (page.figures)
FrameInfo = namedtuple("FrameInfo", "index t runs")
BAND = 16       # rows of a frame deflated alone, a piece kept while its pixels stay the same


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


# what a frame is drawn from, the scenes aside (Painter's): frame j at time t, the points the
# view follows, each run's frame_run dict without its scene (with its marks)
Frame = namedtuple("Frame", "index t follow runs")


def frame_of(tracks, j, forces):
    """Frame j of the tracks' current states."""
    runs = [dict(frame_run(tr.scene, tr.x, tr.samples.last.report, tr.label, tr.color, forces),
                 marks=tr.marks) for tr in tracks]        # marks: the chalk's, else None
    for run in runs:
        del run["scene"]        # the Painter's: given once, not with every frame
    return Frame(j, max(tr.t for tr in tracks), np.array([tr.samples.last.com for tr in tracks]),
                 runs)


def frame_files(j, tags):
    """The files of frame j: its PNG, then the OBJ of each run (by its tag)."""
    return [files.frame_png(j), *(files.frame_obj(j, tag) for tag in tags)]


def info_of(tracks, frame):
    """The FrameInfo the page shows beside `frame`: each track's figures (its last log row)."""
    return FrameInfo(frame.index, frame.t, [page.figures(tr.row) for tr in tracks])


class Painter:
    """Frames of the runs of `scenes` drawn and encoded (their OBJs named by `tags`): one view that
    follows them, one surface and BandedPng kept from frame to frame."""

    def __init__(self, scenes, tags, forces):
        self.scenes, self.tags = scenes, tags
        self.pygame = draw.load_pygame()
        self.fonts = draw.fonts(self.pygame)
        self.view = draw.View.of(scenes[0])
        self.newton_per_metre = draw.newton_per_metre(scenes[0]) if forces else None
        # drawn and encoded in the same arrays frame after frame: a new megabyte array each frame
        # costs glibc an mmap and a page fault per 4 kB (benchmarks/README.md, frames)
        self.surface = self.pygame.Surface((self.view.size, self.view.height))
        self.png = BandedPng(self.view.size, self.view.height)

    def paint(self, frame):
        """[(file name, its bytes or text)] of `frame`: its PNG, then each run's OBJ."""
        self.view.follow(frame.follow)
        runs = [dict(run, scene=scene) for run, scene in zip(frame.runs, self.scenes)]
        surface, _ = draw.draw_frame(self.pygame, runs, frame.t, self.view, self.fonts,
                                     self.newton_per_metre, surface=self.surface)
        objs = [square_mesh.obj_text(diagnostics.body(run["scene"], run["x"]), *run["scene"].cells)
                for run in runs]
        data = [self.png.data(self.pygame, surface), *objs]
        return list(zip(frame_files(frame.index, self.tags), data))


class FrameWriter:
    """Frame j of the tracks' current states into `folder` in this process (a Painter's files),
    its FrameInfo appended to `frame_log`; a signal waits until the frame is done."""

    def __init__(self, tracks, folder, forces, frame_log):
        self.tracks, self.folder, self.forces, self.frame_log = tracks, folder, forces, frame_log
        self.painter = Painter([tr.scene for tr in tracks], [tr.tag for tr in tracks], forces)

    def write(self, j):
        """Frame j (each OBJ after its track's log row: the CSV is never behind)."""
        frame = frame_of(self.tracks, j, self.forces)
        made = self.painter.paint(frame)
        with self.folder.signals.held():
            for name, data in made:
                self.folder.write(name, data)
            self.frame_log.append(info_of(self.tracks, frame))

    def close(self):
        """Nothing waits: each frame was written as write returned."""


def frame_run(scene, x, report, label, color, forces):
    """One run as draw.draw_frame takes it; with `forces`, the contact forces at x and the friction
    force of the step that ended at x (its StepReport's, with the mu lambda and T it ended with)."""
    run = {"scene": scene, "x": x, "label": label, "color": color}
    if forces:
        run["normal"] = diagnostics.normal_forces(scene, x)
        friction = report.friction_force if report is not None else None
        run["friction"] = np.zeros_like(x) if friction is None else friction
    return run


class BandedPng:
    """draw.png_data's 8-bit PNG of a picture width x height, its rows deflated BAND at a time
    (`deflated`), the pieces joined into one zlib stream (`zlib_stream`). A band whose pixels are
    the last picture's keeps its piece and palette indices; a piece depends on its band's pixels
    alone, so the bytes do not depend on the pictures before."""

    def __init__(self, width, height):
        self.width, self.height = width, height
        self.pixels = np.zeros((height, width), np.uint32)      # the last picture's
        self.changed = np.empty((height, width), bool)
        self.rows = np.zeros((height, 1 + width), np.uint8)     # kept: filter byte 0, indices
        self.scratch = np.empty((2, height, width), np.uint32)   # draw.palette_indices'
        self.starts = np.arange(0, height, BAND)
        self.pieces = [None] * len(self.starts)     # per band: `deflated`'s, None before the first

    def data(self, pygame, surface):
        """The PNG of `surface`: the bands whose pixels changed since the last call made anew."""
        pixel = pygame.surfarray.pixels2d(surface).T        # a view, [y, x]
        np.not_equal(pixel, self.pixels, out=self.changed)
        new = np.logical_or.reduceat(self.changed.any(axis=1), self.starts)
        new = np.flatnonzero(new | [piece is None for piece in self.pieces])
        gaps = np.flatnonzero(np.diff(new) > 1)         # runs of adjacent new bands: a call each
        firsts, lasts = np.r_[new[:1], new[gaps + 1]], np.r_[new[gaps], new[-1:]]
        for first, last in zip(firsts.tolist(), lasts.tolist()):
            y = slice(first * BAND, min((last + 1) * BAND, self.height))
            draw.palette_indices(pixel[y], surface.get_shifts(), self.rows[y, 1:],
                                 self.scratch[:, :y.stop - y.start])
            self.pixels[y] = pixel[y]
        del pixel                                           # unlocks the surface
        for k in new.tolist():
            self.pieces[k] = deflated(self.rows[k * BAND:(k + 1) * BAND])
        return draw.png(self.width, self.height, zlib_stream(self.pieces), draw.PALETTE)


def deflated(rows):
    """(bytes, adler32, length) of `rows`: raw deflate of them alone (no history before them; runs
    of a byte only, zlib's Z_RLE, level 1), ended byte-aligned by a sync flush."""
    deflate = zlib.compressobj(1, zlib.DEFLATED, -15, 8, zlib.Z_RLE)
    return deflate.compress(rows) + deflate.flush(zlib.Z_SYNC_FLUSH), zlib.adler32(rows), rows.size


def zlib_stream(pieces):
    """One zlib stream (RFC 1950) of `deflated` pieces in turn: its header (deflate, 32 kB window,
    fastest), the pieces, an empty last block, the adler32 of all their bytes."""
    adler = 1
    for _, piece_adler, length in pieces:
        adler = adler32_joined(adler, piece_adler, length)
    return b"".join([b"\x78\x01", *(data for data, _, _ in pieces), b"\x03\x00",
                     struct.pack(">I", adler)])


def adler32_joined(first, second, length):
    """adler32 of bytes X then Y from X's and Y's (Y `length` bytes long). adler32 = B << 16 | A,
    A = 1 + the sum of the bytes, B = the sum of A after each byte (mod 65521, RFC 1950); joined,
    A = A_X + A_Y - 1 and B = B_X + B_Y + length (A_X - 1)."""
    a1, b1, a2, b2 = first & 0xFFFF, first >> 16, second & 0xFFFF, second >> 16
    return (b1 + b2 + length * (a1 - 1)) % 65521 << 16 | (a1 + a2 - 1) % 65521
