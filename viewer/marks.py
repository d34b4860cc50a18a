"""The marks the chalk's tip leaves on the board (recording.Track.marks, live.LiveRun.marks: (x along the
board, stuck) of the tip each state it is within dhat), as the frames and the live window draw them:
at the picture's scale under the board, and in a strip of the board about the tip magnified
MAGNIFICATION times, where Rabinowicz's dashed line can be seen.

At the chalk's 4000 px/m (900-px frames) a slip of the pushed chalk, about 1.07 mm, is 4 px, and a stuck
stretch (the tip creeps about 6 um in 93 ms) less than one. The strip magnifies the view, the board
with it: the board's line, each run's chalk about its tip (its springs, the tip hovering where the
barrier holds it, within dhat of the board) and the marks under the board, slipping stretches as a
band, stuck ones as ticks twice as deep, one scale for all of it (a bar of SCALE_BAR at the top right).
x8 makes a slip 34 px long in the frames and 25 px in the 652-px window, and the frames' strip (876 px)
27 mm of board, about what a 3 s run marks (28 mm at 10 mm/s).

No import of viewer.draw (which draws the frame and calls these): the views come in as arguments.
"""
from dataclasses import dataclass

import numpy as np

import square_mesh
from viewer import diagnostics, stick_slip

# the two kinds of mark: the stuck one dark, the slipping one mid-grey in luminance (WCAG contrast on
# white 16.4 and 3.3, 4.9 between them: apart in grey-scale too), each at least 39 in CIELAB from
# white, every run's colour, the forces' and the hand's (tests/test_draw.py measures both)
STUCK_COLOR, SLIP_COLOR = (73, 0, 0), (146, 146, 0)
MARK_HEIGHT = 0.06          # m (of the lecture's scale, times View.unit) a mark reaches below the board
MAGNIFICATION = 8           # the strip's scale: this many times the picture's
SCALE_BAR = 1e-3            # m: the strip's scale bar, about one slip of the pushed chalk
ROW, ROW_MIN = 0.1, 0.03    # of the picture's height: a run's row of the strip, and the least it shrinks to
BAND = 1 / 7                # of a row: a slipping stretch's depth under the board; a stuck one twice that
TICK = 0.005                # of the picture's height: a stuck stretch is drawn at least this wide
MIN_WIDTH = 0.25            # of the picture's width: the narrowest strip drawn beside the chalk
PAD = 8                     # px between the strip and what it sits beside, and inside its border


def stretches(marks):
    """(lo, hi, stuck): the board's stretches the marks cover, m along it, one per run of consecutive
    marks of one kind. A stuck stretch spans its marks; a slipping one reaches from the last mark
    before it to the first after it, for the tip moved in between."""
    if not marks:
        return np.zeros(0), np.zeros(0), np.zeros(0, bool)
    a = np.asarray(marks, float)
    s, stuck = a[:, 0], a[:, 1] > 0.5
    parts = stick_slip.runs(stuck)              # the runs of one kind, as the stick-slip count splits them
    starts, ends = np.array([p[0] for p in parts]), np.array([p[-1] for p in parts])
    kind = stuck[starts]
    before, after = s[np.where(kind, starts, np.maximum(starts - 1, 0))], s[np.where(kind, ends, np.minimum(ends + 1, len(s) - 1))]
    lo = np.minimum(np.minimum.reduceat(s, starts), np.minimum(before, after))
    hi = np.maximum(np.maximum.reduceat(s, starts), np.maximum(before, after))
    return lo, hi, kind


def board_point(scene, s):
    """The points (k, 2) of the board at arc lengths s (as the marks measure them, x . t)."""
    s = np.atleast_1d(np.asarray(s, float))
    return s[:, None] * diagnostics.tangent(scene) + float(scene.o @ scene.n) * scene.n


def draw_marks(pygame, surface, scene, marks, view):
    """The marks at the picture's scale, under the board's line (flat, along the picture's rows, as the
    chalk's is): each slipping stretch a band MARK_HEIGHT / 2 deep, each stuck one MARK_HEIGHT deep
    over them, at least 1 px wide."""
    lo, hi, stuck = stretches(marks)
    row = round(float(view(board_point(scene, 0.0))[0, 1])) + 2
    draw_stretches(pygame, surface, view(board_point(scene, lo))[:, 0], view(board_point(scene, hi))[:, 0], stuck,
                   row, round(MARK_HEIGHT * view.unit * view.scale), 1)


def draw_stretches(pygame, surface, a, b, stuck, row, depth, least):
    """Stretches from columns a to b (px) from `row` down: slipping ones depth / 2 deep in SLIP_COLOR, at
    least 1 px wide, then stuck ones `depth` deep in STUCK_COLOR, at least `least` px wide about their
    middle; those wholly off the surface are left out."""
    a, b = np.minimum(a, b), np.maximum(a, b)
    shown = (b >= 0) & (a <= surface.get_width())
    for which, color, deep, wide in ((~stuck, SLIP_COLOR, depth // 2, 1), (stuck, STUCK_COLOR, depth, least)):
        for x0, x1 in zip(a[shown & which].tolist(), b[shown & which].tolist()):
            w = max(wide, round(x1 - x0))
            pygame.draw.rect(surface, color, (round((x0 + x1 - w) / 2), row, w, deep))


@dataclass(frozen=True)
class Strip:
    """Where the strip is and how it maps the board: the board's arc length s to the strip's column
    tip_column + scale (s - s_tip), the height d above the board to row top + board - scale d of each
    run's row. Pixels are the strip's own, from its top-left corner."""
    rect: tuple             # (left, top, width, height) in the picture, px
    magnification: float
    scale: float            # px per m: magnification times the picture's
    s_tip: float            # m along the board: the first run's tip (diagnostics.tip), ...
    tip_column: float       # ... at this column, px
    rows: tuple             # (top, height) of each run's row, px from the strip's top
    board: int              # the board's row within a run's row, px from its top
    band: int               # a slipping mark's depth under the board, px (a stuck one's: twice it)
    tick: int               # a stuck mark's least width, px
    where: str              # "below the board" or "beside the chalk"

    def column(self, s):
        """The strip's columns (px) of board arc lengths s (m)."""
        return self.tip_column + self.scale * (np.asarray(s, float) - self.s_tip)

    def span(self):
        """The board's arc lengths (m) at the strip's left and right edges."""
        return self.s_tip - self.tip_column / self.scale, self.s_tip + (self.rect[2] - self.tip_column) / self.scale


def layout(runs, t, view, font, top, bottom, below):
    """The Strip of the runs (those with marks: their scene, x, marks), or None where it does not fit:
    across the picture under the board's numbers (from row `below`) down to row `bottom`, where a row
    per run of at least ROW_MIN of the picture's height fits there (the frames); else above the board,
    from row `top` (under the text) down to it, beside the chalk (every run's nodes and the hand's
    targets at time t) on the side with more room (the live window, whose key hints leave no room
    under the board). Its tip column: where the tip is in the picture when that is inside the strip
    (magnified about it), else three quarters of the way along, its marks behind it."""
    size, height = view.size, view.height
    want, least = round(ROW * height), max(round(ROW_MIN * height), 12)
    scene = runs[0]["scene"]
    board = float(view(board_point(scene, 0.0))[0, 1])
    fit = (lambda room, width: min(want, int(room - header(font, width, view.scale) - PAD) // len(runs)))
    row = fit(bottom - below - 2 * PAD, size - 24)
    if row >= least:
        rect = (12, int(below) + PAD, size - 24, header(font, size - 24, view.scale) + len(runs) * row + PAD)
        where = "below the board"
    else:
        body = np.concatenate([view(np.vstack([r["x"], r["scene"].hand.targets(t)]))[:, 0] for r in runs])
        room_left, room_right = body.min() - 24, size - body.max() - 24
        width = int(max(room_left, room_right))
        row = fit(board - PAD - top - PAD, width)
        if row < least or width < MIN_WIDTH * size:
            return None
        strip_height = header(font, width, view.scale) + len(runs) * row + PAD
        left = 12 if room_left >= room_right else int(body.max()) + 12
        rect, where = (left, int(board) - PAD - strip_height, width, strip_height), "beside the chalk"
    k, _ = diagnostics.tip(scene, runs[0]["x"])
    s_tip = float(runs[0]["x"][k] @ diagnostics.tangent(scene))
    column = float(view(runs[0]["x"][k])[0]) - rect[0]
    if not 0.1 * rect[2] <= column <= 0.9 * rect[2]:
        ahead = runs[0]["marks"] and runs[0]["marks"][0][0] > s_tip          # the marks right of the tip
        column = (0.25 if ahead else 0.75) * rect[2]
    band = max(2, round(BAND * row))
    first = header(font, rect[2], view.scale)
    return Strip(rect, MAGNIFICATION, MAGNIFICATION * view.scale, s_tip, column,
                 tuple((first + i * row, row) for i in range(len(runs))), row - 2 * band - 4, band,
                 max(2, round(TICK * height)), where)


def title(magnification=MAGNIFICATION):
    """The strip's title: what it shows, and how much it is magnified."""
    return f"the tip's marks, x{magnification:g}"


def header_rows(font, width, scale):
    """The rows of text of the strip's header, `width` px across, for a picture of `scale` px/m: 1 where
    the title and the scale bar fit side by side, else 2 (the bar under the title)."""
    bar = SCALE_BAR * MAGNIFICATION * scale
    return 1 if 4 * PAD + font.size(title())[0] + bar + font.size(bar_label())[0] <= width else 2


def header(font, width, scale):
    """The height (px) of the strip's header (header_rows of text)."""
    return header_rows(font, width, scale) * font.get_linesize() + 4


def bar_label():
    return f"{SCALE_BAR * 1e3:g} mm"


def draw_strip(pygame, surface, runs, strip, font, board_color, ink=(0, 0, 0)):
    """The strip on its own `surface`: per run a row with the board's line (in `board_color`), the marks
    under it (slipping stretches a band `strip.band` deep in SLIP_COLOR, stuck ones over them twice as
    deep in STUCK_COLOR, at least `strip.tick` wide about their middle) and the run's chalk about its tip
    (its springs in its colour; of several runs, each row has its colour at its left end), all at
    strip.scale; the title and a scale bar of SCALE_BAR at the top, a border."""
    width, height = surface.get_size()
    surface.fill((255, 255, 255))
    for run, (top, row) in zip(runs, strip.rows):
        scene, sub, board = run["scene"], surface.subsurface((0, top, width, row)), strip.board
        pygame.draw.line(sub, board_color, (0, board), (width, board), 3)
        lo, hi, stuck = stretches(run["marks"])
        draw_stretches(pygame, sub, strip.column(lo), strip.column(hi), stuck, board + 2, 2 * strip.band, strip.tick)
        x = run["x"] - scene.o
        px = np.stack([strip.column(run["x"] @ diagnostics.tangent(scene)), board - strip.scale * (x @ scene.n)], axis=1)
        for line in square_mesh.polylines(*scene.cells):
            pygame.draw.lines(sub, run["color"], False, px[line].tolist(), 2)
        if len(runs) > 1:                                   # whose row: the run's colour at its left end
            pygame.draw.rect(sub, run["color"], (0, 1, PAD, row - 2))
    surface.blit(font.render(title(strip.magnification), True, ink), (PAD, 4))
    bar, label = SCALE_BAR * strip.scale, font.render(bar_label(), True, ink)
    one_row = header_rows(font, width, strip.scale / strip.magnification) == 1
    left = width - PAD - label.get_width() - 6 - bar if one_row else PAD
    top = 4 if one_row else 4 + font.get_linesize()
    y = top + font.get_ascent() - font.metrics("H")[0][3] // 2                 # level with the capitals' middle
    bar = round(bar)                                                           # px of ink, its end ticks within
    pygame.draw.rect(surface, ink, (left, y - 1, bar, 3))
    for end in (left, left + bar - 2):
        pygame.draw.rect(surface, ink, (end, y - 5, 2, 11))
    surface.blit(label, (left + bar + 6, top))
    pygame.draw.rect(surface, ink, surface.get_rect(), 2)


def draw_span(pygame, surface, scene, strip, view, ink=(0, 0, 0)):
    """In the picture, a box around the board's stretch the strip's first row magnifies: its two
    edges' arc lengths, from the row's top (above the board) to its bottom (under it)."""
    s_lo, s_hi = strip.span()
    top, row = strip.rows[0]
    above, under = strip.board / strip.scale, (row - strip.board) / strip.scale      # m
    corners = [board_point(scene, s)[0] + d * scene.n for s, d in ((s_lo, above), (s_hi, above), (s_hi, -under), (s_lo, -under))]
    pygame.draw.polygon(surface, ink, view(np.array(corners)).tolist(), 1)


def place_strip(pygame, surface, runs, t, view, font, rows, below, board_color=(0, 0, 255)):
    """The strip of the runs with marks laid out (layout) between `rows` (top, bottom) of the picture
    and under row `below`, drawn with the box of what it magnifies; returns its Strip (None: no room)."""
    strip = layout(runs, t, view, font, *rows, below)
    if strip is not None:
        draw_span(pygame, surface, runs[0]["scene"], strip, view)
        draw_strip(pygame, surface.subsurface(strip.rect), runs, strip, font, board_color)
    return strip
