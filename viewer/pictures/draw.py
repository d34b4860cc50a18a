"""One frame, drawn by pygame on an off-screen surface, in the lecture's style (white, the slope as
a line, springs and nodes in blue), with what explains the motion: marks every 0.5 m along the slope,
the contact forces as arrows, and one colour per run when runs are compared.

PNG files are saved with 8-bit colour and zlib at its fastest level (encode_png): about 5 ms a
frame instead of 20-25 ms with pygame.image.save, which is what lets a default run write 33 frames per
simulated second at under 3x the time of the same run without frames (benchmarks/speed.py --frames).
"""
import io
import math
import os
import struct
import zlib

import numpy as np

import FrictionEnergy
import square_mesh
from viewer.pictures import marks as tip_marks

RESOLUTION = 900            # pixels, square frames
SCALE = 200.0               # pixels per metre, the lecture's
BLUE = (0, 0, 255)
# the live window's colours; those of its text have a WCAG contrast ratio of at least 4.5:1 against the
# white background (AA for text, tests/viewer/demo/test_window.py): BLACK 21, RED 6.1, GREEN 5.1, BLUE 8.6,
# window.KEYS 5.9; GREY (2.3:1) draws only the Newton view's iterate x^i
BLACK, GREY, RED, GREEN = (0, 0, 0), (170, 170, 170), (200, 0, 0), (0, 128, 0)
# colours of PALETTE (below), so that frames show them exactly
RUN_COLORS = [BLUE, (255, 146, 0), (0, 146, 0), (219, 0, 170), (146, 73, 0), (0, 182, 255), (109, 109, 85)]
# the forces' colours, far from every run's (tests/viewer/command/test_run_outputs.py measures the distance in CIELAB):
# friction was dark green (0, 109, 0), which a comparison's third run (0, 146, 0) all but repeated
NORMAL_COLOR, FRICTION_COLOR = (219, 0, 0), (0, 0, 0)
MARK_SPACING = 0.5          # m between marks along the slope
ARROW_PER_WEIGHT = 1.0      # m of arrow for a force equal to the weight of the (first) square, M |g|
FRICTION_ZOOM = 5.0         # friction arrows drawn this much longer (|F| <= mu lambda, mu ~ 0.1)
ARROW_FIT = 0.75            # m: no arrow longer (3/4 of the square); the scale coarsens instead
HAND_COLOR = (73, 0, 85)    # the chalk's hand, its targets and springs (its marks' colours: viewer.pictures.marks)
MIN_CAP_HEIGHT = 0.022      # of the picture's height: no capital letter drawn is shorter (16 arcminutes from
                            # 4 screen heights in the default window: docs/live-demo.md, "Readable")
TITLE_SCALE = 1.2           # the title's capitals this much taller


def load_pygame():
    """pygame, with the dummy video driver unless one is set (no display needed), and its fonts."""
    os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    import pygame
    pygame.font.init()
    return pygame


def run_color(i):
    return RUN_COLORS[i % len(RUN_COLORS)]


def zoom(scene):
    """How much closer than the lecture's SCALE a scene is drawn: 1 for the square (metres), and for a
    smaller body (the chalk) a round factor that draws it about 2 m of the lecture's scale across (20
    for the 9 cm chalk: 4000 px/m, the chalk 360 px long)."""
    if "n_seg" in scene.params:                 # the square
        return 1.0
    return nice_number(2.0 / float(np.hypot(*np.ptp(scene.x0, axis=0))))


class View:
    """Maps world coordinates to pixels. Pans only once the followed point is `margin` m from the
    view's centre, and zooms out (never in) when the points followed no longer fit. `unit`: the metres
    that stand for one of the lecture's (1 for the square, 1 / zoom for the chalk): margins, the
    slope's marks and the arrows scale with it."""

    def __init__(self, scale=SCALE, size=RESOLUTION, height=None, unit=1.0):
        self.scale, self.size, self.center, self.unit = scale, size, np.zeros(2), unit
        self.height = size if height is None else height
        self.arrow_factor = 1.0     # the arrows' scale, coarsened as they need (arrow_factor)

    @classmethod
    def of(cls, scene, size=RESOLUTION, height=None):
        """The view of a scene at the lecture's SCALE times its zoom, in a picture `size` px across: the
        frames' view (RESOLUTION px), or the live window's, which shows what a frame shows at its size."""
        z = zoom(scene)
        view = cls(SCALE * z * size / RESOLUTION, size, height, 1.0 / z)
        if scene.hand is not None:          # the board low in the picture, the chalk under the legends
            view.center = np.array([float(scene.x0[:, 0].mean()), 0.25 * view.size / view.scale])
        return view

    def follow(self, points, margin=1.2, room=1.5):
        """Keep the points (k, 2), e.g. the runs' centres of mass, in view, `room` m from the border:
        pan once their middle is `margin` m from the centre, and zoom out if they spread too far."""
        margin, room = margin * self.unit, room * self.unit
        lo, hi = points.min(axis=0), points.max(axis=0)
        self.scale = min(self.scale, self.size / (float((hi - lo).max()) + 2 * room))
        offset = 0.5 * (lo + hi) - self.center
        half = self.size / (2 * self.scale) - room / 2
        self.center = np.clip(self.center + offset - np.clip(offset, -margin, margin), hi - half, lo + half)

    def __call__(self, p):
        q = (np.asarray(p) - self.center) * self.scale
        return np.stack([self.size / 2 + q[..., 0], self.height / 2 - q[..., 1]], axis=-1)


def slope_span(scene, view):
    """(t, s_lo, s_hi): the slope's unit tangent and the arc lengths from o between which it is drawn,
    a view's width either side of the point of the slope nearest the view's centre."""
    tangent = FrictionEnergy.tangent(scene.n)
    reach = view.size / view.scale
    s_center = float(np.dot(view.center - scene.o, tangent))
    return tangent, s_center - reach, s_center + reach


def slope_ends(scene, view):
    """The pixels of the two ends of the slope's line as draw_slope draws it (None without a slope)."""
    if scene.n is None:
        return None
    tangent, s_lo, s_hi = slope_span(scene, view)
    return view(scene.o + s_lo * tangent), view(scene.o + s_hi * tangent)


def draw_slope(pygame, surface, scene, view, color=BLUE, font=None, marks=True):
    """The slope as a line through the view, with a tick every MARK_SPACING m of arc length from o
    (a number every metre when a font is given, where it fits whole; no ticks unless `marks`), so
    motion stays visible when the view follows. Returns the lowest row of pixels drawn (None without a slope)."""
    if scene.n is None:
        return None
    a, b = slope_ends(scene, view)
    pygame.draw.aaline(surface, color, a.tolist(), b.tolist())
    lowest = max(a[1], b[1])
    if not marks:
        return lowest
    tangent, s_lo, s_hi = slope_span(scene, view)
    spacing = MARK_SPACING * view.unit
    first = np.ceil(s_lo / spacing)
    units = MARK_SPACING * np.arange(first, first + (s_hi - s_lo) / spacing + 1)    # in units: multiples of 0.5
    s = units * view.unit
    feet = scene.o + s[:, None] * tangent
    whole = np.remainder(units, 1.0) == 0.0     # units are multiples of 0.5, exact in binary
    tick = view.unit * np.where(whole, 0.08, 0.04)[:, None]  # m, longer at whole units
    for foot, end, metres, u in zip(view(feet).tolist(), view(feet - tick * scene.n).tolist(), s.tolist(),
                                    units.tolist()):
        pygame.draw.line(surface, color, foot, end, 2)
        lowest = max(lowest, end[1])
        if font is not None and float(u).is_integer():
            label = font.render(f"{metres:g} m" if view.unit == 1.0 else f"{round(metres * 100, 6):g} cm", True, color)
            left = end[0] - label.get_width() / 2
            if 0 <= left <= surface.get_width() - label.get_width():      # whole or not at all
                surface.blit(label, (left, end[1] + 2))
                lowest = max(lowest, end[1] + 2 + label.get_height())
    return lowest


def draw_square(pygame, surface, scene, x, view, color=BLUE, nodes=True):
    """Springs as the mesh's polylines (one pygame call per row, column or diagonal), and the nodes
    as dots of a tenth of the spacing, when that is at least a pixel."""
    px = view(x)
    for line in square_mesh.polylines(*scene.cells):
        pygame.draw.aalines(surface, color, False, px[line].tolist())
    radius = int(0.1 * spacing(scene) * view.scale)
    if nodes and radius >= 1:
        for q in px.tolist():
            pygame.draw.circle(surface, color, q, radius)


def spacing(scene):
    """The mesh's node spacing, m: the square's side_len / n_seg; else the shortest spring's rest length."""
    p = scene.params
    return p["side_len"] / p["n_seg"] if "n_seg" in p else float(np.sqrt(scene.l2.min()))


def reference_force(scene):
    """The force an arrow of ARROW_PER_WEIGHT (lecture) m stands for, N, and its words: the square's weight
    M |g| (|g| = 9.81 m/s^2 without gravity); with a hand (the chalk, whose weight is 1/700 of it), one
    held node's press, k_hand times the press depth (1 N by default; the board's normal force is about 2 N)."""
    if scene.hand is not None:
        return scene.hand.k_hand * scene.params["press"], "one held node's press"
    return float(scene.m.sum() * np.hypot(*scene.g)) or float(scene.m.sum() * 9.81), "the weight M|g|"


def friction_zoom(scene):
    """How much longer friction arrows are drawn: FRICTION_ZOOM for the square (mu ~ 0.1), 1 for the chalk."""
    return FRICTION_ZOOM if scene.hand is None else 1.0


def newton_per_metre(scene):
    """The arrows' scale: reference_force per ARROW_PER_WEIGHT m (divided by zoom for the chalk)."""
    return reference_force(scene)[0] / (ARROW_PER_WEIGHT / zoom(scene))


def arrow_heads(tail, head, length):
    """(K, 2, 2): the two back corners of each arrow's head, from pixels `tail` to `head` (K, 2), `length`
    pixels behind its tip and as wide as half that either side (an arrow of no length: its tip)."""
    back = (tail - head) / np.maximum(np.hypot(*(tail - head).T), 1e-9)[:, None]      # unit, pixels
    side = np.stack([-back[:, 1], back[:, 0]], axis=1)
    corner = head + length * back
    return np.stack([corner + 0.5 * length * side, corner - 0.5 * length * side], axis=1)


def arrow_factor(runs, newton_per_metre, view):
    """How many times more newtons a metre of arrow stands for than newton_per_metre
    (ARROW_PER_WEIGHT m per reference force) in this frame: 1, or where an arrow of `runs` (normal;
    friction drawn friction_zoom longer) would be longer than ARROW_FIT m (times view.unit), the
    smallest of 2, 5, 10, 20, ... that brings it within (the impact: 2). Kept in view.arrow_factor:
    as the view's zoom, it coarsens and never refines, so the frames after the impact compare."""
    longest = max(max(np.hypot(*run["normal"].T).max(initial=0.0),
                      friction_zoom(run["scene"]) * np.hypot(*run["friction"].T).max(initial=0.0))
                  for run in runs) / newton_per_metre                       # m of arrow at factor 1
    needed = longest / (ARROW_FIT * view.unit)
    if needed > view.arrow_factor:
        view.arrow_factor = nice_number(needed, up=True)
    return view.arrow_factor


def draw_arrows(pygame, surface, view, x, forces, newton_per_metre, color):
    """An arrow from each node whose force is not zero, 1 m (in the world) per newton_per_metre."""
    size = np.hypot(forces[:, 0], forces[:, 1])
    on = size > 0.0
    length = size[on] / newton_per_metre
    direction = forces[on] / size[on, None]
    tail, head = view(x[on]), view(x[on] + length[:, None] * direction)
    for t, h, (c1, c2) in zip(tail.tolist(), head.tolist(), arrow_heads(tail, head, 8).tolist()):
        pygame.draw.line(surface, color, t, h, 2)
        pygame.draw.polygon(surface, color, [h, c1, c2])


def draw_hand(pygame, surface, scene, x, t, view):
    """The hand: each held node's spring to its target at time t as a line, each target a small square."""
    targets = view(scene.hand.targets(t))
    held = view(x[scene.hand.nodes])
    for a, b in zip(held.tolist(), targets.tolist()):
        pygame.draw.line(surface, HAND_COLOR, a, b, 1)
    for q in targets.tolist():
        pygame.draw.rect(surface, HAND_COLOR, (q[0] - 3, q[1] - 3, 7, 7))


def draw_legend(pygame, surface, font, entries, top, left=12):
    """Colour swatches with their text, one per line from `top` down, laid out from the font's
    measured size: a line apart, each swatch as tall as the capitals of its text and level with them
    (from their top to the baseline), twice as wide; returns the next free row."""
    line, baseline, cap = font.get_linesize(), font.get_ascent(), cap_height(font)
    for color, text in entries:
        pygame.draw.rect(surface, color, (left, top + baseline - cap, 2 * cap, cap))
        surface.blit(font.render(text, True, (0, 0, 0)), (left + 2 * cap + cap // 2, top))
        top += line
    return top


def wrap(font, text, width):
    """`text` broken at spaces into rows at most `width` pixels wide (a longer word stays whole)."""
    rows, row = [], ""
    for word in text.split(" "):
        trial = f"{row} {word}" if row else word
        if row.strip() and font.size(trial)[0] > width:
            rows.append(row.rstrip())
            row = word
        else:
            row = trial
    return rows + [row]


def nice_number(value, steps=(1, 2, 5), up=False):
    """A round number for a scale bar, a tick or a zoom: the largest of `steps` times a power of ten that
    is at most `value` (> 0), or with `up` the smallest that is at least it. The steps are 1, 2 and 5
    by default (0.3 -> 0.2, up: 0.5); range(10, 100) gives two significant digits (38.79 -> 38)."""
    power = 10.0 ** (math.floor(math.log10(value)) - math.floor(math.log10(max(steps))))
    if up:
        return min(m * p for p in (power, 10 * power) for m in steps if m * p >= value)
    return max(m * power for m in steps if m * power <= value * (1 + 1e-12))


def cap_height(font):
    """How tall a capital letter is in `font`, px: the top of an H above the baseline."""
    return font.metrics("H")[0][3]


def font_with_caps(pygame, cap):
    """pygame's default font at the smallest size whose capitals are at least `cap` px tall (they are
    at most 0.6 of the size: the search starts below it)."""
    size = max(1, math.floor(cap / 0.6))
    while cap_height(pygame.font.Font(None, size)) < cap:
        size += 1
    return pygame.font.Font(None, size)


def fonts(pygame, height=RESOLUTION):
    """The two fonts of a picture `height` px tall: the text (the slope's marks, the arrows' legend,
    the window's lines) with capitals MIN_CAP_HEIGHT of the height, and the title (and the runs'
    legend) TITLE_SCALE taller."""
    cap = MIN_CAP_HEIGHT * height
    return font_with_caps(pygame, TITLE_SCALE * cap), font_with_caps(pygame, cap)


def draw_frame(pygame, runs, t, view, fonts, newton_per_metre=None, reserve=(0, 0)):
    """One frame: the slope, every run's square in its colour, the forces of each (when given), the
    time, a legend for the runs (when there are several) and for the arrows; the chalk's hand, marks
    and the strip magnifying them (viewer.pictures.marks), off `reserve`: (rows under the legends, rows at the
    bottom) the caller writes in (None: no strip). Returns the frame and the first row below its text.
    `runs`: dicts of scene, x, label, color, and normal, friction ((N, 2) forces), marks (the chalk's)."""
    surface = pygame.Surface((view.size, view.size))
    surface.fill((255, 255, 255))
    font, small = fonts
    below = draw_slope(pygame, surface, runs[0]["scene"], view, BLUE, small)
    chalks = [run for run in runs if run.get("marks") is not None]
    if chalks:
        tip_marks.draw_marks(pygame, surface, chalks, view)
    for run in runs:
        draw_square(pygame, surface, run["scene"], run["x"], view, run["color"])
        if run["scene"].hand is not None:
            draw_hand(pygame, surface, run["scene"], run["x"], t, view)
    if newton_per_metre is not None:
        factor = arrow_factor(runs, newton_per_metre, view)
        newton_per_metre *= factor                  # this frame's scale, as its legend says
        for run in runs:
            draw_arrows(pygame, surface, view, run["x"], run["normal"], newton_per_metre, NORMAL_COLOR)
            draw_arrows(pygame, surface, view, run["x"], friction_zoom(run["scene"]) * run["friction"],
                        newton_per_metre, FRICTION_COLOR)
    title = f"t = {t:.2f} s" + (f"   {runs[0]['label']}" if len(runs) == 1 else "")
    surface.blit(font.render(title, True, (0, 0, 0)), (12, 10))
    top = 10 + font.get_linesize()
    if len(runs) > 1:
        top = draw_legend(pygame, surface, font, [(r["color"], r["label"]) for r in runs], top)
    if newton_per_metre is not None:
        metres = ARROW_PER_WEIGHT * view.unit
        force, words = reference_force(runs[0]["scene"])
        words = words if factor == 1 else f"{factor:g} x {words}"
        scale = f"{metres:g} m of arrow = {newton_per_metre * metres:.5g} N ({words})"
        top = draw_legend(pygame, surface, small, [
            (NORMAL_COLOR, "normal force lambda_k n"),
            (FRICTION_COLOR, f"friction force, drawn {FRICTION_ZOOM:g}x longer" if runs[0]["scene"].hand is None
             else "friction force"),
            ((255, 255, 255), scale)], top + 4)
    if runs[0]["scene"].hand is not None:
        hand = [(HAND_COLOR, "the hand: its targets and springs")]
        top = draw_legend(pygame, surface, small, hand + tip_marks.legend(chalks), top + 4)
    if chalks and reserve is not None:
        tip_marks.place_strip(pygame, surface, chalks, t, view, small, (top + reserve[0], view.height - reserve[1]), below)
    return surface, top


# 3-3-2 bits of colour, index r << 5 | g << 2 | b (each channel's top bits): 8 levels of red and
# green, 4 of blue; every colour drawn here (white, black, BLUE, RUN_COLORS, ...) is one of them
PALETTE = np.array([(round(r * 255 / 7), round(g * 255 / 7), round(b * 255 / 3))
                    for r in range(8) for g in range(8) for b in range(4)], np.uint8)


def encode_png(pygame, surface):
    """The surface as an 8-bit palette PNG: each pixel to its PALETTE index, the top 3, 3 and 2 bits
    of red, green and blue (a third of RGB's data; anti-aliased edges and text keep a few shades),
    the rows each after a 0 byte (no filter) in one zlib stream at level 1, the fastest; the IHDR,
    PLTE, IDAT and IEND chunks as the PNG specification (section 11.2) lays them out."""
    rgb = pygame.surfarray.pixels3d(surface)            # a view, [x, y, channel]
    width, height = rgb.shape[:2]
    rows = np.zeros((height, 1 + width), np.uint8)
    rows[:, 1:] = ((rgb[:, :, 0] & 0xE0) | ((rgb[:, :, 1] & 0xE0) >> 3) | (rgb[:, :, 2] >> 6)).T
    del rgb                                             # unlocks the surface

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    header = struct.pack(">IIBBBBB", width, height, 8, 3, 0, 0, 0)     # 8 bits, palette, no interlace
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"PLTE", PALETTE.tobytes())
            + chunk(b"IDAT", zlib.compress(rows.tobytes(), 1)) + chunk(b"IEND", b""))


def png_data(pygame, surface, exact=False):
    """The surface as PNG bytes: a frame by encode_png, a picture whose colours must stay exact (plots,
    summary) by pygame, in 24-bit colour."""
    if not exact:
        return encode_png(pygame, surface)
    buffer = io.BytesIO()
    pygame.image.save(surface, buffer, "png")
    return buffer.getvalue()
