"""One frame, drawn by pygame off-screen in the lecture's style: the slope with marks every 0.5 m,
the bodies, the contact forces as arrows, one colour per run; and PNG bytes (png_data)."""
import functools
import math
import os
import struct
import zlib

import numpy as np

import FrictionEnergy
import square_mesh
from analysis import diagnostics
from viewer.pictures import marks as tip_marks

RESOLUTION = 900            # pixels, square frames
SCALE = 200.0               # pixels per metre, the lecture's
WHITE, BLUE = (255, 255, 255), (0, 0, 255)
# text colours stand 4.5:1 against white or more; GREY (2.3:1) draws only the Newton view's x^i
BLACK, GREY, RED, GREEN = (0, 0, 0), (170, 170, 170), (200, 0, 0), (0, 128, 0)
RUN_COLORS = [BLUE, (255, 146, 0), (0, 146, 0), (219, 0, 170), (146, 73, 0), (0, 182, 255),
              (109, 109, 85)]      # PALETTE's colours, so that frames show them exactly
NORMAL_COLOR, FRICTION_COLOR = (219, 0, 0), (0, 0, 0)      # far from every run's colour
MARK_SPACING = 0.5          # m between marks along the slope
MAX_MARKS = 400             # marks along the drawn slope at most; beyond, they spread out
ARROW_PER_WEIGHT = 1.0      # m of arrow for reference_force
FRICTION_ZOOM = 5.0         # the square's friction arrows drawn this much longer (mu ~ 0.1)
ARROW_FIT = 0.75            # m: no arrow longer (3/4 of the square); the scale coarsens instead
HAND_COLOR = (73, 0, 85)    # the chalk's hand: its targets and springs
MIN_CAP_HEIGHT = 0.022      # of the picture's height: the least capital (docs/live-demo.md)
TITLE_SCALE = 1.2           # the title's capitals this much taller
CAP_RATIO = 0.5             # pygame's default font: its capitals about half its size
CLOTH_COLOR, CLOTH_STRIPE = (255, 219, 170), (219, 146, 85)     # the tablecloth and its stripes
CLOTH_DEPTH = 0.08          # m (x view.unit): each run's cloth, a band this deep under the table
CLOTH_STRIPES = 2.0         # m (x view.unit): the stripes' period along the cloth
PUSHED_COLOR = (109, 109, 170)  # pushed surfaces (scene.pushed): their pads
PAD_DEPTH = 0.1             # m (x view.unit): each pad drawn this thick, behind its surface
# m/s^2: a weaker gravity (or none) is no scale for the arrows: a force over M|g| could pass
# float64 (the range checks keep a run's forces under 1e150, scenes/ranges.py)
WEAKEST_GRAVITY = 1e-150


def load_pygame():
    """pygame and its fonts, with the dummy video driver unless one is set (no display needed)."""
    os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    import pygame
    pygame.font.init()
    return pygame


def run_color(i):
    return RUN_COLORS[i % len(RUN_COLORS)]


def zoom(scene):
    """How much closer than SCALE a scene is drawn: 1 for the square; for a smaller body a round
    factor drawing it about 2 m across (20 for the 9 cm chalk)."""
    if "n_seg" in scene.params:
        return 1.0
    return nice_number(2.0 / float(np.hypot(*np.ptp(scene.x0, axis=0))))


class View:
    """World to pixels at `scale` px/m; `unit`, the metres that stand for one of the lecture's
    (1 / zoom), scales margins, slope marks and arrows."""

    def __init__(self, scale=SCALE, size=RESOLUTION, height=None, unit=1.0):
        self.scale, self.size, self.center, self.unit = scale, size, np.zeros(2), unit
        self.height = size if height is None else height
        self.arrow_factor = 1.0         # see draw_forces
        self.margin = 1.2               # units the followed points may stray before it pans

    @classmethod
    def of(cls, scene, size=RESOLUTION):
        """A scene's view in a picture `size` px across: SCALE x zoom, as a frame shows it."""
        z = zoom(scene)
        view = cls(SCALE * z * size / RESOLUTION, size, unit=1.0 / z)
        if scene.hand is not None:          # the board low, the chalk under the legends
            view.center = np.array([float(scene.x0[:, 0].mean()), 0.25 * view.size / view.scale])
        if scene.pushed is not None:        # lifted all the way: kept centred, under the legends
            view.margin = 0.0
        return view

    def follow(self, points):
        """Keep `points` (k, 2) 1.5 units from the border: pan once their middle is `margin` units
        off the centre, zoom out (never in) when they spread too far."""
        margin, room = self.margin * self.unit, 1.5 * self.unit
        lo, hi = points.min(axis=0), points.max(axis=0)
        self.scale = min(self.scale, self.size / (float((hi - lo).max()) + 2 * room))
        offset = 0.5 * (lo + hi) - self.center
        half = self.size / (2 * self.scale) - room / 2
        moved = self.center + offset - np.clip(offset, -margin, margin)
        self.center = np.clip(moved, hi - half, lo + half)

    def __call__(self, p):
        q = (np.asarray(p) - self.center) * self.scale         # new: set in place to pixels
        q[..., 0] += self.size / 2
        q[..., 1] = self.height / 2 - q[..., 1]
        return q


def slope_span(scene, view):
    """(t, s_lo, s_hi): the slope's tangent and the arc lengths from o it is drawn between."""
    tangent = FrictionEnergy.tangent(scene.n)
    reach = view.size / view.scale
    s_center = float(np.dot(view.center - scene.o, tangent))
    return tangent, s_center - reach, s_center + reach


def slope_ends(scene, view):
    """The pixels of the two ends of the slope's line (None without a slope)."""
    if scene.n is None:
        return None
    tangent, s_lo, s_hi = slope_span(scene, view)
    return view(scene.o + s_lo * tangent), view(scene.o + s_hi * tangent)


def draw_slope(pygame, surface, scene, view, color=BLUE, font=None, clear=0.0):
    """The slope's line, a tick every MARK_SPACING x view.unit, with `font` a number every whole
    unit, `clear` x view.unit m under the line at least; returns the lowest row drawn. A slope
    drawn over more than MAX_MARKS marks (a body far off it) gets a mark every `nice_number` units
    instead, and a number every other mark."""
    if scene.n is None:
        return None
    a, b = slope_ends(scene, view)
    pygame.draw.aaline(surface, color, a.tolist(), b.tolist())
    lowest = max(a[1], b[1])
    tangent, s_lo, s_hi = slope_span(scene, view)
    span = (s_hi - s_lo) / view.unit
    mark = MARK_SPACING if span <= MAX_MARKS * MARK_SPACING else nice_number(span / MAX_MARKS,
                                                                            up=True)
    first = np.ceil(s_lo / (mark * view.unit))
    units = mark * np.arange(first, first + span / mark + 1)        # k x 0.5, or k x mark
    s = units * view.unit
    feet = scene.o + s[:, None] * tangent
    whole = np.remainder(units, 1.0 if mark < 1.0 else 2.0 * mark) == 0.0   # exact multiples
    ends = feet - view.unit * np.where(whole, 0.08, 0.04)[:, None] * scene.n
    under = view(feet - view.unit * max(0.08, clear) * scene.n).tolist()      # the numbers' tops
    for foot, end, metres, w, at in zip(view(feet).tolist(), view(ends).tolist(), s.tolist(),
                                        whole, under):
        pygame.draw.line(surface, color, foot, end, 2)
        lowest = max(lowest, end[1])
        if font is None or not w:
            continue
        label = font.render(length_text(metres, view.unit), True, color)
        left = at[0] - label.get_width() / 2
        if 0 <= left <= surface.get_width() - label.get_width():
            surface.blit(label, (left, at[1] + 2))
            lowest = max(lowest, at[1] + 2 + label.get_height())
    return lowest


def draw_cloths(pygame, surface, cloths, t, view):
    """Each run's cloth as a band under the table, one under the other, from its trailing edge
    (L behind the dish's rear at t = 0) on, its stripes moved by surface.offset(t)."""
    for i, run in enumerate(cloths):
        scene, cloth = run["scene"], run["scene"].surface
        tangent, s_lo, s_hi = slope_span(scene, view)
        rear = float(((scene.x0 - scene.o) @ tangent).min())
        tail = rear - cloth.pull_length + cloth.offset(t)
        half = 0.5 * CLOTH_STRIPES * view.unit
        depth = CLOTH_DEPTH * view.unit * np.array([i, i, i + 1, i + 1])[:, None]
        stripe = CLOTH_STRIPE if len(cloths) == 1 else run["color"]
        first = max(0, math.floor((s_lo - tail) / half))
        for k in range(first, first + math.ceil((s_hi - s_lo) / half) + 1):
            a, b = max(tail + k * half, s_lo), min(tail + (k + 1) * half, s_hi)
            corners = scene.o + np.array([a, b, b, a])[:, None] * tangent - depth * scene.n
            if a < b:
                color = stripe if k % 2 else CLOTH_COLOR
                pygame.draw.polygon(surface, color, view(corners).tolist())


def length_text(metres, unit=1.0):
    """A length in words: in m for the square (unit 1), in cm for a smaller body."""
    return f"{metres:g} m" if unit == 1.0 else f"{round(metres * 100, 6):g} cm"


def draw_square(pygame, surface, scene, x, view, color=BLUE, nodes=True):
    """The springs as the mesh's polylines, the nodes as dots a tenth of the spacing across."""
    px = view(diagnostics.body(scene, x))
    for line in square_mesh.polylines(*scene.cells):
        polyline(pygame, surface, color, px[line].tolist())
    radius = int(0.1 * spacing(scene) * view.scale)
    if nodes and radius >= 1:
        for q in px.tolist():
            pygame.draw.circle(surface, color, q, radius)


def polyline(pygame, surface, color, points):
    """An anti-aliased open polyline through `points` (px, 2 or more). Two go through aaline:
    pygame-ce 2.5.8's aalines of one segment changes its end pixels from one process to the next
    (docs/output.md, summary.png)."""
    if len(points) == 2:
        pygame.draw.aaline(surface, color, *points)
    else:
        pygame.draw.aalines(surface, color, False, points)


def spacing(scene):
    """The mesh's node spacing, m: side_len / n_seg, else the shortest spring's rest length."""
    p = scene.params
    return p["side_len"] / p["n_seg"] if "n_seg" in p else float(np.sqrt(scene.l2.min()))


def reference_force(scene):
    """(N, words): the force ARROW_PER_WEIGHT m of arrow stands for: the weight M|g|, M x 9.81
    m/s^2 where |g| < WEAKEST_GRAVITY, or with a hand one held node's press, k_hand x press depth
    (where it presses: press 0 has no force to scale by)."""
    if scene.hand is not None and scene.hand.k_hand * scene.params["press"] > 0.0:
        return scene.hand.k_hand * scene.params["press"], "one held node's press"
    mass, g = float(diagnostics.body(scene, scene.m).sum()), float(np.hypot(*scene.g))
    if g < WEAKEST_GRAVITY:
        return mass * 9.81, "M x 9.81 m/s^2"
    return mass * g, "the weight M|g|"


def friction_zoom(scene):
    """How much longer friction arrows are drawn: FRICTION_ZOOM for the square, 1 for the chalk
    and pushed surfaces (friction there is of the normal force's size)."""
    return FRICTION_ZOOM if scene.hand is None and scene.pushed is None else 1.0


def newton_per_metre(scene):
    """The arrows' scale: reference_force per ARROW_PER_WEIGHT m (divided by zoom for the chalk)."""
    return reference_force(scene)[0] / (ARROW_PER_WEIGHT / zoom(scene))


def arrow_heads(tail, head, length):
    """(K, 2, 2): the back corners of arrowheads tail to head (K, 2) px, `length` long and wide."""
    back = (tail - head) / np.maximum(np.hypot(*(tail - head).T), 1e-9)[:, None]
    side = np.stack([-back[:, 1], back[:, 0]], axis=1)
    corner = head + length * back
    return np.stack([corner + 0.5 * length * side, corner - 0.5 * length * side], axis=1)


def draw_forces(pygame, surface, runs, view, newton_per_metre):
    """The runs' contact forces as arrows, 1 m per factor x newton_per_metre: the least factor of
    1, 2, 5, 10, ... keeping every arrow within ARROW_FIT x view.unit m, kept in view.arrow_factor
    (it never refines: docs/output.md); returns the arrows' legend rows."""
    arrows = []
    for run in runs:
        friction = friction_zoom(run["scene"]) * run["friction"]
        arrows += [(run["x"], run["normal"], NORMAL_COLOR), (run["x"], friction, FRICTION_COLOR)]
    longest = max(np.hypot(*forces.T).max(initial=0.0) for _, forces, _ in arrows)
    needed = longest / newton_per_metre / (ARROW_FIT * view.unit)
    if needed > view.arrow_factor:
        view.arrow_factor = nice_number(needed, up=True)
    newton_per_metre *= view.arrow_factor
    for x, forces, color in arrows:
        on = np.hypot(*forces.T) > 0.0
        tail, head = view(x[on]), view(x[on] + forces[on] / newton_per_metre)
        heads = arrow_heads(tail, head, 8).tolist()
        for t, h, (c1, c2) in zip(tail.tolist(), head.tolist(), heads):
            pygame.draw.line(surface, color, t, h, 2)
            pygame.draw.polygon(surface, color, [h, c1, c2])
    scene, metres = runs[0]["scene"], ARROW_PER_WEIGHT * view.unit
    words = reference_force(scene)[1]
    words = words if view.arrow_factor == 1 else f"{view.arrow_factor:g} x {words}"
    z = friction_zoom(scene)
    friction = f"friction force, drawn {z:g}x longer" if z != 1 else "friction force"
    return [(NORMAL_COLOR, "normal force lambda_k n"), (FRICTION_COLOR, friction),
            (WHITE, f"{metres:g} m of arrow = {newton_per_metre * metres:.5g} N ({words})")]


def draw_pushed(pygame, surface, scene, x, view):
    """Pushed surfaces as their pads (scene.pushed.pads), PAD_DEPTH x view.unit deep."""
    for corners in scene.pushed.pads(x, PAD_DEPTH * view.unit):
        pygame.draw.polygon(surface, PUSHED_COLOR, view(corners).tolist())


def draw_hand(pygame, surface, scene, x, t, view):
    """The hand: each held node's spring to its target at time t, each target a small square."""
    targets = view(scene.hand.targets(t))
    for a, b in zip(view(x[scene.hand.nodes]).tolist(), targets.tolist()):
        pygame.draw.line(surface, HAND_COLOR, a, b, 1)
    for q in targets.tolist():
        pygame.draw.rect(surface, HAND_COLOR, (q[0] - 3, q[1] - 3, 7, 7))


def draw_legend(pygame, surface, font, entries, top):
    """(colour, text) rows from `top` down, swatches level with capitals; returns the next row."""
    line, baseline, cap = font.get_linesize(), font.get_ascent(), cap_height(font)
    for color, text in entries:
        pygame.draw.rect(surface, color, (12, top + baseline - cap, 2 * cap, cap))
        surface.blit(font.render(text, True, BLACK), (12 + 2 * cap + cap // 2, top))
        top += line
    return top


def nice_number(value, steps=(1, 2, 5), up=False):
    """The largest of `steps` x a power of ten at most `value` (> 0); with `up`, the smallest at
    least it: 0.3 -> 0.2 (up: 0.5); steps range(10, 100) keep two digits (38.79 -> 38)."""
    power = 10.0 ** (math.floor(math.log10(value)) - math.floor(math.log10(max(steps))))
    if up:
        return min(m * p for p in (power, 10 * power) for m in steps if m * p >= value)
    return max(m * power for m in steps if m * power <= value * (1 + 1e-12))


def cap_height(font):
    """How tall a capital letter is in `font`, px: the top of an H above the baseline."""
    return font.metrics("H")[0][3]


def fonts(pygame, height=RESOLUTION):
    """(title, text) fonts of a picture `height` px tall: pygame's default font at the least size
    whose capitals are MIN_CAP_HEIGHT of the height, the title's TITLE_SCALE taller: searched from
    CAP_RATIO's guess down, then up (capitals grow with the size), each size's font made once."""
    font, chosen = functools.cache(lambda size: pygame.font.Font(None, size)), []
    for cap in (TITLE_SCALE * (MIN_CAP_HEIGHT * height), MIN_CAP_HEIGHT * height):     # px
        size = max(1, round(cap / CAP_RATIO))
        while size > 1 and cap_height(font(size - 1)) >= cap:
            size -= 1
        while cap_height(font(size)) < cap:
            size += 1
        chosen.append(font(size))
    return tuple(chosen)


def draw_frame(pygame, runs, t, view, fonts, newton_per_metre=None, reserve=(0, 0), surface=None):
    """One frame of `runs` (frame_run's dicts, with marks), the chalk's strip clear of `reserve`
    (rows under the legends, at the bottom; None: no strip), drawn over `surface` where given (a
    writer's, kept from frame to frame); returns it, the row under its text."""
    surface = pygame.Surface((view.size, view.size)) if surface is None else surface
    surface.fill(WHITE)
    font, small = fonts
    scene = runs[0]["scene"]
    cloths = [run for run in runs if run["scene"].surface is not None]      # tablecloths
    draw_cloths(pygame, surface, cloths, t, view)
    below = draw_slope(pygame, surface, scene, view, BLUE, small, len(cloths) * CLOTH_DEPTH)
    chalks = [run for run in runs if run.get("marks") is not None]
    if chalks:
        tip_marks.draw_marks(pygame, surface, chalks, view)
    for run in runs:
        draw_square(pygame, surface, run["scene"], run["x"], view, run["color"])
        if run["scene"].hand is not None:
            draw_hand(pygame, surface, run["scene"], run["x"], t, view)
        if run["scene"].pushed is not None:
            draw_pushed(pygame, surface, run["scene"], run["x"], view)
    if newton_per_metre is not None:
        arrows = draw_forces(pygame, surface, runs, view, newton_per_metre)
    title = f"t = {t:.2f} s" + (f"   {runs[0]['label']}" if len(runs) == 1 else "")
    surface.blit(font.render(title, True, BLACK), (12, 10))
    top = 10 + font.get_linesize()
    if len(runs) > 1:
        top = draw_legend(pygame, surface, font, [(r["color"], r["label"]) for r in runs], top)
    if newton_per_metre is not None:
        top = draw_legend(pygame, surface, small, arrows, top + 4)
    if cloths:
        words = "the cloth" if len(cloths) == 1 else "the cloths, top to bottom as the runs"
        top = draw_legend(pygame, surface, small, [(CLOTH_STRIPE, words)], top + 4)
    if scene.pushed is not None:
        pads = [(PUSHED_COLOR, scene.pushed.pads_words)]
        top = draw_legend(pygame, surface, small, pads, top + 4)
    if scene.hand is not None:
        hand = [(HAND_COLOR, "the hand: its targets and springs")] + tip_marks.legend(chalks)
        top = draw_legend(pygame, surface, small, hand, top + 4)
    if chalks and reserve is not None:
        rows = (top + reserve[0], view.height - reserve[1])
        tip_marks.place_strip(pygame, surface, chalks, t, view, small, rows, below)
    return surface, top


PNG_LEVEL = 3   # zlib's, png_data's: the last fast one (4 takes 2-3x the time for 10-20 % less)
# 3-3-2 bits of colour, index r << 5 | g << 2 | b: every colour named here is one of them
PALETTE = np.array([(round(r * 255 / 7), round(g * 255 / 7), round(b * 255 / 3))
                    for r in range(8) for g in range(8) for b in range(4)], np.uint8)


def png_data(pygame, surface):
    """PNG bytes of `surface` in 24-bit colour (plots, summary, figures): its rows of r, g, b, each
    after filter byte 0, deflated at zlib level PNG_LEVEL (a run's frames: frames.BandedPng's)."""
    width, height = surface.get_size()
    rgb = np.frombuffer(pygame.image.tobytes(surface, "RGB"), np.uint8).reshape(height, -1)
    return png(width, height, zlib.compress(np.pad(rgb, ((0, 0), (1, 0))), PNG_LEVEL))


def png(width, height, idat, palette=None):
    """PNG bytes of a picture width x height, `idat` the zlib stream of its rows: of 8-bit r, g, b,
    or with `palette` (n x 3 uint8, PALETTE) of 8-bit indices into it."""
    def chunk(kind, body):
        crc = struct.pack(">I", zlib.crc32(kind + body))
        return struct.pack(">I", len(body)) + kind + body + crc
    header = struct.pack(">IIBBBBB", width, height, 8, 2 if palette is None else 3, 0, 0, 0)
    colours = b"" if palette is None else chunk(b"PLTE", palette.tobytes())
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + colours + chunk(b"IDAT", idat)
            + chunk(b"IEND", b""))


def palette_indices(pixel, shifts, index, scratch):
    """`index` = the PALETTE indices r & 0xE0 | (g & 0xE0) >> 3 | b >> 6 of 32-bit pixels (r, g
    and b at `shifts`), through `scratch` (2 x pixel's shape): a pixel per element, not a channel
    (faster: benchmarks/README.md, frames)."""
    r, g, b = shifts[:3]
    whole, part = scratch
    np.bitwise_and(np.right_shift(pixel, r, out=whole), 0xE0, out=whole)
    whole |= np.bitwise_and(np.right_shift(pixel, g + 3, out=part), 0x1C, out=part)
    whole |= np.bitwise_and(np.right_shift(pixel, b + 6, out=part), 0x03, out=part)
    index[...] = whole
