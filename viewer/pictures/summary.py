"""summary.png: the whole motion at a glance, a panel per run of time-labelled snapshots clear of
each other, at a fixed scale so that summaries compare (docs/output.md); `plan` places it all."""
from collections import namedtuple

import numpy as np

from analysis import closing, stick_slip
from viewer.pictures import draw

SCALE = 100.0       # pixels per metre
MAX_WIDTH = 2400    # pixels; beyond, the scale shrinks (the same for every panel)
MIN_WIDTH = 700     # pixels
MAX_HEIGHT = 1600   # pixels of a panel's motion and slope; beyond, the scale shrinks, as for width
MARGIN = 0.6        # m of room around the motion
HEADER = 70         # pixels of text above each panel
GAP = 4             # pixels between the drawn snapshots (with their labels)
TWO_DIGITS = range(10, 100)     # a scale too long for SCALE is rounded down to two digits
BLACK, PATH = (0, 0, 0), (220, 0, 0)

# a state drawn with its label; box: (left, top, right, bottom) px of both, under the panel's header
Snapshot = namedtuple("Snapshot", "t x label label_at box")
# a run's panel: its top row in the picture, its height, its view (under its header), its Snapshots
Panel = namedtuple("Panel", "track top height view snapshots")
# summary.png's size, the first panel's top row, px/m, the Panels and the header's lines of text
Plan = namedtuple("Plan", "width height top scale panels lines")


def spaced(boxes, gap=GAP):
    """The indices of the snapshots to draw, of boxes (K, 4) px: the first, each next one clear by
    `gap` of all kept, and the last, which drops those it is not clear of but the first."""
    boxes = np.asarray(boxes, dtype=float)

    def clear_of(i, kept):
        a, b = boxes[i], boxes[kept]
        return ((b[:, 0] > a[2] + gap) | (a[0] > b[:, 2] + gap)
                | (b[:, 1] > a[3] + gap) | (a[1] > b[:, 3] + gap))
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
    """Each snapshot (t, x) a Snapshot: its label centred above it, the last one's to its right;
    a label wider than the room beside its snapshot slid inside the view's columns."""
    out = []
    for i, (t, x) in enumerate(snapshots):
        px, text = view(x), time_label(t)
        (w, h), (left, top), (right, bottom) = font.size(text), px.min(axis=0), px.max(axis=0)
        if i == len(snapshots) - 1:
            at = (right + 6, 0.5 * (top + bottom) - h / 2)
        else:
            at = (min(max(0.5 * (left + right) - w / 2, 0.0), view.size - w), top - h - 2)
        box = [min(left, at[0]), min(top, at[1]), max(right, at[0] + w), max(bottom, at[1] + h)]
        out.append(Snapshot(t, x, text, at, np.array(box)))
    return out


def slope_room(scene, lo, hi, unit, scale, label_h):
    """The box (lo, hi), m, grown to hold the slope between columns lo[0] and hi[0] and, under
    it, its ticks (0.08 `unit` m at most) and numbers (`label_h` + 4 px), as draw_slope draws."""
    if scene.n is None or scene.n[1] == 0.0:
        return lo, hi
    y = scene.o[1] - scene.n[0] / scene.n[1] * (np.array([lo[0], hi[0]]) - scene.o[0])
    return (np.array([lo[0], min(lo[1], y.min() - 0.08 * unit - (label_h + 4) / scale)]),
            np.array([hi[0], max(hi[1], y.max())]))


def header_lines(tracks, header):
    """summary.png's lines of text: `header`, then what the square's sticking and creep, the
    chalk's stick-slip and the dish's travel count (each run's figures: panel_words)."""
    if tracks[0].scene.hand is not None:
        first, second = stick_slip.definition(tracks[0].scene)
        return header + ["stick-slip, " + first, second]
    if tracks[0].scene.surface is not None:
        return header + ["travel: " + closing.counted(tracks[0].scene)]
    return header + [closing.counted(tracks[0].scene)]


def panel_words(track):
    """Under a panel's label: the chalk's stick-slip, the dish's travel, a pushed scene's words,
    the square's sticking and creep (analysis/closing.py)."""
    return closing.closing_words([track])


def plan(pygame, tracks, header):
    """summary.png's Plan under `header` (lines; header_lines adds what the runs showed): as wide
    as the motion at the scale, and as its widest line of text."""
    small, font = pygame.font.Font(None, 20), pygame.font.Font(None, 24)
    header = header_lines(tracks, header)
    z = draw.zoom(tracks[0].scene)      # 1 for the square; the chalk is drawn 20x closer
    boxes = []
    for tr in tracks:
        com = np.array([s.com for s in tr.samples.all()])
        pts = np.concatenate([x for _, x in tr.snapshots.all()] + [com])
        boxes.append((pts.min(axis=0) - MARGIN / z, pts.max(axis=0) + MARGIN / z))
    label_w, label_h = small.size(time_label(max(tr.t for tr in tracks)))
    right_room = label_w + 12                   # px right of the motion, for the last label
    width_m = max(float(hi[0] - lo[0]) for lo, hi in boxes)
    scale = SCALE * z
    if width_m * scale + right_room > MAX_WIDTH:
        scale = draw.nice_number((MAX_WIDTH - right_room) / width_m, TWO_DIGITS)
    tall = max(float(np.ptp(slope_room(tr.scene, lo, hi, 1.0 / z, scale, label_h), axis=0)[1])
               for tr, (lo, hi) in zip(tracks, boxes))
    if tall * scale > MAX_HEIGHT:       # a body far above its slope: both in view, smaller
        scale = draw.nice_number(MAX_HEIGHT / tall, TWO_DIGITS)
    words = [w for w in map(panel_words, tracks) if w]
    texts = [font.size(text)[0] for text in header] + [small.size(w)[0] for w in words]
    across = int(width_m * scale + right_room)          # px: the motion, and the last label
    width = max(across, MIN_WIDTH, min(max(texts) + 24, MAX_WIDTH))
    top = 22 * len(header) + 34
    panels, row = [], top
    for tr, (lo, hi) in zip(tracks, boxes):
        hi = lo + [across / scale, hi[1] - lo[1]]
        lo, hi = slope_room(tr.scene, lo, hi, 1.0 / z, scale, label_h)
        height = int((hi[1] - lo[1]) * scale) + label_h + 4 + HEADER    # the labels on top
        view = draw.View(scale, across, height - HEADER, unit=1.0 / z)
        middle = 0.5 * (lo[1] + hi[1]) + (label_h + 4) / 2 / scale
        view.center = np.array([lo[0] + across / scale / 2, middle])
        candidates = labelled(view, small, tr.snapshots.all())
        kept = spaced([s.box for s in candidates])
        panels.append(Panel(tr, row, height, view, [candidates[i] for i in kept]))
        row += height
    return Plan(width, row, top, scale, panels, header)


def draw_summary(pygame, tracks, header):
    """summary.png's surface: the header's lines (header_lines), the scale bar, a panel per run."""
    font, small = pygame.font.Font(None, 24), pygame.font.Font(None, 20)
    layout = plan(pygame, tracks, header)
    surface = pygame.Surface((layout.width, layout.height))
    surface.fill(draw.WHITE)
    for row, text in enumerate(layout.lines):
        surface.blit(font.render(text, True, BLACK), (12, 8 + 22 * row))
    metres = 1.0 / draw.zoom(tracks[0].scene)       # 1 m; for the chalk 5 cm
    length, row = layout.scale * metres, layout.top - 26
    pygame.draw.line(surface, BLACK, (12, row + 8), (12 + length, row + 8), 3)
    text = f"{draw.length_text(metres, metres)} ({length:.3g} pixels)"
    surface.blit(small.render(text, True, BLACK), (20 + length, row + 1))
    for panel in layout.panels:
        draw_panel(pygame, surface, font, small, panel, layout.width)
    return surface


def draw_panel(pygame, surface, font, small, panel, width):
    """One run: its label and figures, the slope, the snapshots (the last in full colour, the
    others 55 % of the way to white) with their times, the centre-of-mass path; a grasp's pads
    where the last snapshot has them."""
    track, view = panel.track, panel.view
    area = surface.subsurface((0, panel.top, width, panel.height))
    sub = area.subsurface((0, HEADER, view.size, panel.height - HEADER))     # the motion
    draw.draw_slope(pygame, sub, track.scene, view, BLACK, small)
    light = tuple(int(c + 0.55 * (255 - c)) for c in track.color)
    if track.scene.pushed is not None:
        draw.draw_pushed(pygame, sub, track.scene, panel.snapshots[-1].x, view)
    for snap in panel.snapshots:
        color = track.color if snap is panel.snapshots[-1] else light
        draw.draw_square(pygame, sub, track.scene, snap.x, view, color, nodes=False)
        sub.blit(small.render(snap.label, True, BLACK), snap.label_at)
    com = np.array([s.com for s in track.samples.all()])
    if len(com) > 1:
        pygame.draw.lines(sub, PATH, False, view(com).tolist(), 2)
    area.blit(font.render(track.label, True, track.color), (12, 8))
    steps = f"red: centre-of-mass path; {track.step} steps, t = {track.t:.2f} s"
    area.blit(small.render(steps, True, BLACK), (12, 32))
    words = panel_words(track)
    if words:
        area.blit(small.render(words, True, BLACK), (12, 50))
