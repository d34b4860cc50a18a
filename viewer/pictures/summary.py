"""summary.png: the whole motion at a glance, at a fixed scale so that two summaries compare.

Snapshots are taken from the states kept every 0.1 s (recording.SNAPSHOT_EVERY), each labelled with
its time. One is drawn only where it and its label are clear (by GAP pixels) of every one drawn
before; the last state is always drawn, its label to its right, and the snapshots it is not clear
of are left out, but the first: so no two drawn snapshots or labels overlap, except the first and
the last when the body ends within its own size of where it started. The centre-of-mass path is
drawn in red, and a 1 m bar gives the scale: SCALE pixels per metre, unless the motion is too long
for MAX_WIDTH pixels (then a round number of pixels, two digits). The slope and its numbers are
drawn across the motion only (with MARGIN), each panel tall enough for them. A comparison draws one
panel per run, one above the other, all at the same scale. The header says what the runs showed:
when the square came to rest; for the chalk how its stick-slip is counted, each run's figures in its
own panel. The picture is as wide as its widest line of text (up to MAX_WIDTH). Everything drawn is
placed by `plan`.
"""
from dataclasses import dataclass

import numpy as np

from analysis import closing, stick_slip
from viewer.pictures import draw

SCALE = 100.0       # pixels per metre
MAX_WIDTH = 2400    # pixels; beyond, the scale shrinks (the same for every panel)
MIN_WIDTH = 700     # pixels
MARGIN = 0.6        # m of room around the motion
HEADER = 70         # pixels of text above each panel
GAP = 4             # pixels between the drawn snapshots (with their labels)
TWO_DIGITS = range(10, 100)     # a scale too long for SCALE is rounded down to two digits (38 px/m)


@dataclass
class Snapshot:
    """A state drawn in a panel, with its label: `box` (left, top, right, bottom) holds both, in the
    panel's pixels (below its header)."""
    t: float
    x: np.ndarray
    label: str
    label_at: tuple
    box: np.ndarray


@dataclass
class Panel:
    """One run's panel: its top row in the picture, its height, its view (below the header) and the
    snapshots drawn, first to last."""
    track: object
    top: int
    height: int
    view: draw.View
    snapshots: list


@dataclass
class Plan:
    """Where everything of summary.png goes: its size, the scale (pixels per metre) and the panels."""
    width: int
    height: int
    top: int            # the first panel's top row, below the header lines and the scale bar
    scale: float
    panels: list
    lines: list         # the header's lines of text (header_lines)


def spaced(boxes, gap=GAP):
    """Which snapshots to draw, given each one's box (K, 4): left, top, right, bottom in pixels. The
    first; each next one clear by `gap` of every one kept; and the last, which drops every kept one
    it is not clear of but the first. Returns their indices, in order."""
    boxes = np.asarray(boxes, dtype=float)

    def clear_of(i, kept):
        a, b = boxes[i], boxes[kept]
        return (b[:, 0] > a[2] + gap) | (a[0] > b[:, 2] + gap) | (b[:, 1] > a[3] + gap) | (a[1] > b[:, 3] + gap)
    kept = [0]
    for i in range(1, len(boxes) - 1):
        if clear_of(i, kept).all():
            kept.append(i)
    last = len(boxes) - 1
    if last > 0:
        kept = [0] + [i for i, clear in zip(kept[1:], clear_of(last, kept[1:])) if clear] + [last]
    return kept


def time_label(t):
    return f"t = {t:.1f} s"


def labelled(view, font, snapshots):
    """Each snapshot (t, x) as a Snapshot: its label centred above it, the last one's to its right."""
    out = []
    for i, (t, x) in enumerate(snapshots):
        px, text = view(x), time_label(t)
        (w, h), (left, top), (right, bottom) = font.size(text), px.min(axis=0), px.max(axis=0)
        if i == len(snapshots) - 1:
            at = (right + 6, 0.5 * (top + bottom) - h / 2)
        else:
            at = (0.5 * (left + right) - w / 2, top - h - 2)
        box = np.array([min(left, at[0]), min(top, at[1]), max(right, at[0] + w), max(bottom, at[1] + h)])
        out.append(Snapshot(t, x, text, at, box))
    return out


def slope_room(scene, lo, hi, unit, scale, label_h):
    """The box (lo, hi), m, grown to hold the slope between the columns lo[0] and hi[0] (a straight
    line, highest and lowest at those ends) and under it, its ticks (at most 0.08 `unit` m) and
    numbers (`label_h` px and 2 px either side, at `scale` px/m), as draw.draw_slope draws them."""
    if scene.n is None or scene.n[1] == 0.0:
        return lo, hi
    y = scene.o[1] - scene.n[0] / scene.n[1] * (np.array([lo[0], hi[0]]) - scene.o[0])
    return (np.array([lo[0], min(lo[1], y.min() - 0.08 * unit - (label_h + 4) / scale)]),
            np.array([hi[0], max(hi[1], y.max())]))


def header_lines(tracks, header):
    """summary.png's lines of text above the scale bar: `header`, then what the runs showed: when the square
    came to rest (closing.closing_note, each run's); for the chalk what its stick-slip counts, each run's
    own figures in its panel (panel_words)."""
    if tracks[0].scene.hand is not None:
        first, second = stick_slip.definition(tracks[0].scene)
        return header + ["stick-slip, " + first, second]
    return header + [closing.closing_note(tracks)]


def panel_words(track):
    """The line a run's panel adds under its label and steps: the chalk's stick-slip (stick_slip.words, as
    the closing line says it), or none (the square's rest is in the header)."""
    return stick_slip.words(stick_slip.of_track(track)) if track.scene.hand is not None else None


def plan(pygame, tracks, header):
    """The layout of summary.png for `tracks` under `header` (lines of text, followed by what the runs
    showed: header_lines): as wide as the motion at the scale, and as its widest line of text."""
    small, font = pygame.font.Font(None, 20), pygame.font.Font(None, 24)
    header = header_lines(tracks, header)
    z = draw.zoom(tracks[0].scene)      # 1 for the square; the chalk is drawn 20x closer
    boxes = []
    for tr in tracks:
        pts = np.concatenate([x for _, x in tr.snapshots.all()] + [np.array([s.com for s in tr.samples.all()])])
        boxes.append((pts.min(axis=0) - MARGIN / z, pts.max(axis=0) + MARGIN / z))
    label_w, label_h = small.size(time_label(max(tr.t for tr in tracks)))
    right_room = label_w + 12                   # px right of the motion, for the last state's label
    width_m = max(float(hi[0] - lo[0]) for lo, hi in boxes)
    scale = SCALE * z if width_m * SCALE * z + right_room <= MAX_WIDTH else \
        draw.nice_number((MAX_WIDTH - right_room) / width_m, TWO_DIGITS)
    texts = [font.size(text)[0] for text in header] + [small.size(w)[0] for w in map(panel_words, tracks) if w]
    width = int(max(width_m * scale + right_room, MIN_WIDTH, min(max(texts, default=0) + 24, MAX_WIDTH)))
    top = 22 * len(header) + 34
    across = int(width_m * scale + right_room)          # px: the motion, and the last state's label
    panels, row = [], top
    for tr, (lo, hi) in zip(tracks, boxes):
        hi = lo + [across / scale, hi[1] - lo[1]]
        lo, hi = slope_room(tr.scene, lo, hi, 1.0 / z, scale, label_h)
        height = int((hi[1] - lo[1]) * scale) + label_h + 4 + HEADER      # room for the labels on top
        view = draw.View(scale, across, height - HEADER, unit=1.0 / z)
        middle = 0.5 * (lo[1] + hi[1]) + (label_h + 4) / 2 / scale
        view.center = np.array([lo[0] + across / scale / 2, middle])
        candidates = labelled(view, small, tr.snapshots.all())
        kept = spaced([s.box for s in candidates])
        panels.append(Panel(tr, row, height, view, [candidates[i] for i in kept]))
        row += height
    return Plan(width, row, top, scale, panels, header)


def lighten(color):
    """The colour of the earlier snapshots: the run's colour, 55 % of the way to white."""
    return tuple(int(c + 0.55 * (255 - c)) for c in color)


def draw_summary(pygame, tracks, header):
    """summary.png's surface: `header` (lines of text) and what the runs showed (header_lines), the 1 m bar,
    then one panel per track."""
    font, small = pygame.font.Font(None, 24), pygame.font.Font(None, 20)
    layout = plan(pygame, tracks, header)
    surface = pygame.Surface((layout.width, layout.height))
    surface.fill((255, 255, 255))
    for row, text in enumerate(layout.lines):
        surface.blit(font.render(text, True, (0, 0, 0)), (12, 8 + 22 * row))
    _scale_bar(pygame, surface, small, layout.scale, layout.top - 26, 1.0 / draw.zoom(tracks[0].scene))
    for panel in layout.panels:
        _panel(pygame, surface, font, small, panel, layout.width)
    return surface


def _scale_bar(pygame, surface, font, scale, row, metres=1.0):
    """A 1 m bar (`metres`: 5 cm for the chalk): every summary at SCALE px/m compares with every other."""
    length = scale * metres
    pygame.draw.line(surface, (0, 0, 0), (12, row + 8), (12 + length, row + 8), 3)
    text = "1 m" if metres == 1.0 else f"{round(metres * 100, 6):g} cm"
    surface.blit(font.render(f"{text} ({length:.3g} pixels)", True, (0, 0, 0)), (20 + length, row + 1))


def _panel(pygame, surface, font, small, panel, width):
    """One run: its label and figures, the slope, the snapshots (the last in full colour) with their
    times, the centre-of-mass path."""
    track, view = panel.track, panel.view
    area = surface.subsurface((0, panel.top, width, panel.height))
    sub = area.subsurface((0, HEADER, view.size, panel.height - HEADER))     # across the motion
    draw.draw_slope(pygame, sub, track.scene, view, (0, 0, 0), small)
    light = lighten(track.color)
    for i, snap in enumerate(panel.snapshots):
        last = i == len(panel.snapshots) - 1
        draw.draw_square(pygame, sub, track.scene, snap.x, view, track.color if last else light, nodes=False)
        sub.blit(small.render(snap.label, True, (0, 0, 0)), snap.label_at)
    com = np.array([s.com for s in track.samples.all()])
    if len(com) > 1:
        pygame.draw.lines(sub, (220, 0, 0), False, view(com).tolist(), 2)
    area.blit(font.render(track.label, True, track.color), (12, 8))
    area.blit(small.render(f"red: centre-of-mass path; {track.step} steps, t = {track.t:.2f} s",
                           True, (0, 0, 0)), (12, 32))
    words = panel_words(track)
    if words:
        area.blit(small.render(words, True, (0, 0, 0)), (12, 50))
