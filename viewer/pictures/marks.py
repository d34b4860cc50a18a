"""How the frames, the live window and the stick-slip figure draw the chalk's mark (analysis.wear:
Archard's deposit): grey on white, black where the most was left.

Drawn at the picture's scale under the board (a column of pixels holds several bins: their mean),
and in a strip of the board about the tip magnified MAGNIFICATION times (x8: a bin is 3.2 px in the
900-px frames), each run's mark scaled to its own darkest bin (black). No pygame import (it comes in
as an argument) and no import of viewer.pictures.draw (which draws the frame and calls these)."""
from dataclasses import dataclass

import numpy as np

import square_mesh
from analysis import diagnostics
from analysis.wear import UNIT

MARK_HEIGHT = 0.06          # m (of the lecture's scale, times View.unit): the mark's depth
MAGNIFICATION = 8           # the strip's scale: this many times the picture's
SCALE_BAR = 1e-3            # m: the strip's scale bar, about one slip of the pushed chalk
ROW, ROW_MIN = 0.1, 0.03    # of the picture's height: a run's row of the strip, and the least it shrinks to
MARK_DEPTH = 2 / 7          # of a row: the mark's depth under the strip's board
MIN_WIDTH = 0.25            # of the picture's width: the narrowest strip drawn beside the chalk
PAD = 8                     # px between the strip and what it sits beside, and inside its border
SWATCH = (73, 73, 85)       # the legend's swatch of the mark: a dark grey of the frames' PALETTE


# ------------------------------------------------------------------------------------------------
# Drawing it (pygame comes in as an argument)
# ------------------------------------------------------------------------------------------------

def greys(shade):
    """The colours (k, 3) of shades 0 (white: nothing left) to 1 (black: the darkest bin)."""
    level = np.rint(255.0 * (1.0 - np.asarray(shade, float))).astype(np.uint8)
    return np.repeat(level[:, None], 3, axis=1)


def paint(pygame, surface, colours, left, top, depth):
    """Pixel columns in `colours` (k, 3) from column `left`, `depth` rows down from row `top`."""
    if len(colours) and depth > 0:
        row = pygame.surfarray.make_surface(np.ascontiguousarray(colours[:, None, :]))
        surface.blit(pygame.transform.scale(row, (len(colours), depth)), (left, top))


def paint_mark(pygame, surface, deposit, column, s_of, top, depth):
    """A run's mark on `surface`'s columns over the board it covers (within the surface): column c
    shows the board from s_of(c) to s_of(c + 1); `column(s)` is the column of board position s."""
    span = deposit.span()
    if span is None:
        return
    a, b = sorted(float(column(s)) for s in span)
    first, last = max(int(np.floor(a)), 0), min(int(np.ceil(b)), surface.get_width())
    if last <= first:
        return
    c = np.arange(first, last)
    s0, s1 = s_of(c), s_of(c + 1)
    shade = deposit.shade(np.minimum(s0, s1), np.maximum(s0, s1))
    paint(pygame, surface, greys(shade), first, top, depth)


def board_point(scene, s):
    """The points (k, 2) of the board at arc lengths s (as the marks measure them, x . t)."""
    s = np.atleast_1d(np.asarray(s, float))
    return s[:, None] * diagnostics.tangent(scene) + float(scene.o @ scene.n) * scene.n


def draw_marks(pygame, surface, runs, view):
    """Every run's mark (run["marks"], a Deposit) at the picture's scale, under the board's line
    (flat, along the picture's rows, as the chalk's is), MARK_HEIGHT deep, shared by the runs a band
    each."""
    scene = runs[0]["scene"]
    row = round(float(view(board_point(scene, 0.0))[0, 1])) + 2
    depth = round(MARK_HEIGHT * view.unit * view.scale) // len(runs)
    origin = float(view(board_point(scene, 0.0))[0, 0])
    for i, run in enumerate(runs):
        paint_mark(pygame, surface, run["marks"], lambda s: origin + view.scale * s,
                   lambda c: (c - origin) / view.scale, row + i * depth, max(depth, 1))


def legend(runs):
    """The frame's legend rows of the runs' marks: (colour, text)."""
    if not runs:
        return []
    darkest = runs[0]["marks"].darkest()
    if len(runs) > 1:
        black = "each run's darkest 0.1 mm"
    else:
        black = f"{darkest:.3g} {UNIT}, the darkest" if darkest > 0 else "none yet"
    return [(SWATCH, "the chalk's mark: lambda x slid length (Archard)"),
            ((255, 255, 255), f"black: {black}")]


@dataclass(frozen=True)
class Strip:
    """Where the strip is and how it maps the board: the board's arc length s to the strip's column
    tip_column + scale (s - s_tip), the height d above the board to row top + board - scale d of
    each run's row. Pixels are the strip's own, from its top-left corner."""
    rect: tuple             # (left, top, width, height) in the picture, px
    magnification: float
    scale: float            # px per m: magnification times the picture's
    s_tip: float            # m along the board: the first run's tip (diagnostics.tip), ...
    tip_column: float       # ... at this column, px
    rows: tuple             # (top, height) of each run's row, px from the strip's top
    board: int              # the board's row within a run's row, px from its top
    band: int               # the mark's depth under the board, px
    where: str              # "below the board" or "beside the chalk"

    def column(self, s):
        """The strip's columns (px) of board arc lengths s (m)."""
        return self.tip_column + self.scale * (np.asarray(s, float) - self.s_tip)

    def board_at(self, c):
        """The board's arc lengths (m) at strip columns c (px): column's inverse."""
        return self.s_tip + (np.asarray(c, float) - self.tip_column) / self.scale

    def span(self):
        """The board's arc lengths (m) at the strip's left and right edges."""
        return self.s_tip - self.tip_column / self.scale, self.s_tip + (self.rect[2] - self.tip_column) / self.scale


def layout(runs, t, view, font, top, bottom, below):
    """The Strip of the runs (those with marks: their scene, x, marks), or None where it does not
    fit: across the picture under the board's numbers (from row `below`) down to row `bottom`, where
    a row per run of at least ROW_MIN of the picture's height fits there (the frames); else above
    the board, from row `top` (under the text) down to it, beside the chalk (every run's nodes and
    the hand's targets at time t) on the side with more room (the live window, whose key hints leave
    no room under the board). Its tip column: where the tip is in the picture when that is inside
    the strip (magnified about it), else three quarters of the way along, its mark behind it."""
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
        covered = runs[0]["marks"].span()
        ahead = covered is not None and covered[0] > s_tip          # the mark right of the tip
        column = (0.25 if ahead else 0.75) * rect[2]
    band = max(4, round(MARK_DEPTH * row))
    first = header(font, rect[2], view.scale)
    return Strip(rect, MAGNIFICATION, MAGNIFICATION * view.scale, s_tip, column,
                 tuple((first + i * row, row) for i in range(len(runs))), row - band - 4, band,
                 where)


def title(magnification=MAGNIFICATION):
    """The strip's title: what it shows, and how much it is magnified."""
    return f"the chalk's mark, x{magnification:g}"


def header_rows(font, width, scale):
    """The rows of text of the strip's header, `width` px across, for a picture of `scale` px/m: 1
    where the title and the scale bar fit side by side, else 2 (the bar under the title)."""
    bar = SCALE_BAR * MAGNIFICATION * scale
    return 1 if 4 * PAD + font.size(title())[0] + bar + font.size(bar_label())[0] <= width else 2


def header(font, width, scale):
    """The height (px) of the strip's header (header_rows of text)."""
    return header_rows(font, width, scale) * font.get_linesize() + 4


def bar_label():
    return f"{SCALE_BAR * 1e3:g} mm"


def draw_strip(pygame, surface, runs, strip, font, board_color, ink=(0, 0, 0)):
    """The strip on its own `surface`: per run a row with the board's line (in `board_color`), the
    mark under it (`strip.band` deep, grey: black at the run's darkest bin) and the run's chalk
    about its tip (its springs in its colour; of several runs, each row has its colour at its left
    end), all at strip.scale; the title and a scale bar of SCALE_BAR at the top, a border."""
    width = surface.get_width()
    surface.fill((255, 255, 255))
    for run, (top, row) in zip(runs, strip.rows):
        scene, sub, board = run["scene"], surface.subsurface((0, top, width, row)), strip.board
        pygame.draw.line(sub, board_color, (0, board), (width, board), 3)
        paint_mark(pygame, sub, run["marks"], strip.column, strip.board_at, board + 2, strip.band)
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
    row = strip.rows[0][1]
    above, under = strip.board / strip.scale, (row - strip.board) / strip.scale      # m
    corners = [board_point(scene, s)[0] + d * scene.n for s, d in ((s_lo, above), (s_hi, above), (s_hi, -under), (s_lo, -under))]
    pygame.draw.polygon(surface, ink, view(np.array(corners)).tolist(), 1)


def place_strip(pygame, surface, runs, t, view, font, rows, below, board_color=(0, 0, 255)):
    """The strip of the runs with marks laid out (layout) between `rows` (top, bottom) of the
    picture and under row `below`, drawn with the box of what it magnifies; returns its Strip (None:
    no room)."""
    strip = layout(runs, t, view, font, *rows, below)
    if strip is not None:
        draw_span(pygame, surface, runs[0]["scene"], strip, view)
        draw_strip(pygame, surface.subsurface(strip.rect), runs, strip, font, board_color)
    return strip
