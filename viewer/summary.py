"""summary.png: the whole motion at a glance, at a fixed scale so that two summaries compare.

Snapshots are taken from the states kept every 0.1 s (recording.SNAPSHOT_EVERY), each only once it
has moved clear of the previous one drawn, so they never overlap into a blur, each labelled with
its time; the last state always ends the row. The centre-of-mass path is drawn in red, and a 1 m
bar gives the scale: SCALE pixels per metre, unless the motion is too long for MAX_WIDTH pixels.
A comparison draws one panel per run, one above the other, all at the same scale.
"""
import numpy as np

from viewer import draw

SCALE = 100.0       # pixels per metre
MAX_WIDTH = 2400    # pixels; beyond, the scale shrinks (the same for every panel)
MARGIN = 0.6        # m of room around the motion
HEADER = 70         # pixels of text above each panel


def spaced(snapshots, gap=0.05):
    """The snapshots (t, x) to draw: the first, each next one whose bounding box is at least `gap`
    m clear of the last one kept, and the final state (replacing the last kept if they overlap)."""
    def clear(a, b):
        lo_a, hi_a, lo_b, hi_b = a.min(0), a.max(0), b.min(0), b.max(0)
        return bool(np.any(lo_b > hi_a + gap) or np.any(lo_a > hi_b + gap))
    kept = [snapshots[0]]
    for t, x in snapshots[1:-1]:
        if clear(kept[-1][1], x):
            kept.append((t, x))
    if len(snapshots) > 1:
        if len(kept) > 1 and not clear(kept[-1][1], snapshots[-1][1]):
            kept.pop()
        kept.append(snapshots[-1])
    return kept


def lighten(color):
    """The colour of the earlier snapshots: the run's colour, 55 % of the way to white."""
    return tuple(int(c + 0.55 * (255 - c)) for c in color)


def draw_summary(pygame, tracks, header):
    """summary.png's surface: `header` (lines of text) then one panel per track."""
    font, small = pygame.font.Font(None, 24), pygame.font.Font(None, 20)
    boxes = []
    for tr in tracks:
        pts = np.concatenate([x for _, x in tr.snapshots.all()] + [np.array([s.com for s in tr.samples.all()])])
        boxes.append((pts.min(axis=0) - MARGIN, pts.max(axis=0) + MARGIN))
    width_m = max(float(hi[0] - lo[0]) for lo, hi in boxes)
    scale = min(SCALE, MAX_WIDTH / width_m)
    width = int(max(width_m * scale, 700))
    heights = [int((hi[1] - lo[1]) * scale) + HEADER for lo, hi in boxes]
    top = 22 * len(header) + 34
    surface = pygame.Surface((width, top + sum(heights)))
    surface.fill((255, 255, 255))
    for row, text in enumerate(header):
        surface.blit(font.render(text, True, (0, 0, 0)), (12, 8 + 22 * row))
    _scale_bar(pygame, surface, small, scale, top - 26)
    for tr, (lo, hi), height in zip(tracks, boxes, heights):
        _panel(pygame, surface, font, small, tr, lo, hi, scale, top, width, height)
        top += height
    return surface


def _scale_bar(pygame, surface, font, scale, row):
    """A 1 m bar: every summary at SCALE px/m compares with every other."""
    pygame.draw.line(surface, (0, 0, 0), (12, row + 8), (12 + scale, row + 8), 3)
    surface.blit(font.render(f"1 m ({scale:g} pixels)", True, (0, 0, 0)), (20 + scale, row + 1))


def _panel(pygame, surface, font, small, track, lo, hi, scale, top, width, height):
    panel = surface.subsurface((0, top, width, height))
    view = draw.View(scale, width, height - HEADER)
    view.center = np.array([lo[0] + width / scale / 2, 0.5 * (lo[1] + hi[1])])
    sub = panel.subsurface((0, HEADER, width, height - HEADER))
    draw.draw_slope(pygame, sub, track.scene, view, (0, 0, 0), small)
    light = lighten(track.color)
    kept = spaced(track.snapshots.all())
    for i, (t, x) in enumerate(kept):
        draw.draw_square(pygame, sub, track.scene, x, view, track.color if i == len(kept) - 1 else light, nodes=False)
        label, px = small.render(f"t = {t:.1f} s", True, (0, 0, 0)), view(x)
        if i == len(kept) - 1:          # the last state: its label to the right, clear of any overlap
            sub.blit(label, (float(px[:, 0].max()) + 6, float(px[:, 1].mean())))
        else:
            sub.blit(label, (float(px[:, 0].mean()) - label.get_width() / 2, px[:, 1].min() - label.get_height() - 2))
    com = np.array([s.com for s in track.samples.all()])
    if len(com) > 1:
        pygame.draw.lines(sub, (220, 0, 0), False, view(com).tolist(), 2)
    panel.blit(font.render(track.label, True, track.color), (12, 8))
    panel.blit(small.render(f"red: centre-of-mass path; {track.step} steps, t = {track.t:.2f} s",
                            True, (0, 0, 0)), (12, 32))
