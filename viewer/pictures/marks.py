"""The chalk's mark (analysis.wear: Archard's deposit) in grey, black at a run's darkest bin: under
the board at the picture's scale, and in a strip about the tip magnified MAGNIFICATION times."""
from dataclasses import dataclass

import numpy as np

import square_mesh
from analysis import diagnostics
from analysis.wear import UNIT

MARK_HEIGHT = 0.06          # m (of the lecture's scale, times View.unit): the mark's depth
MAGNIFICATION = 8           # the strip's scale: this many times the picture's
SCALE_BAR = 1e-3            # m: the strip's scale bar, about one slip of the pushed chalk
ROW, ROW_MIN = 0.1, 0.03    # of the picture's height: a run's row of the strip, and its least
MARK_DEPTH = 2 / 7          # of a row: the mark's depth under the strip's board
MIN_WIDTH = 0.25            # of the picture's width: the narrowest strip beside the chalk
PAD = 8                     # px between the strip and what it sits beside, and inside its border
SWATCH = (73, 73, 85)       # the legend's swatch of the mark: a dark grey of the frames' PALETTE
WHITE, INK, BOARD = (255, 255, 255), (0, 0, 0), (0, 0, 255)


def greys(shade):
    """The colours (k, 3) of shades 0 (white: nothing left) to 1 (black: the darkest bin)."""
    level = np.rint(255.0 * (1.0 - np.asarray(shade, float))).astype(np.uint8)
    return np.repeat(level[:, None], 3, axis=1)


def paint_mark(pygame, surface, deposit, column, s_of, top, depth):
    """A run's mark, `depth` rows down from `top`, on the surface's columns over the board it
    covers: column c shows the board from s_of(c) to s_of(c + 1); column(s) inverts s_of."""
    span = deposit.span()
    if span is None:
        return
    a, b = sorted(float(column(s)) for s in span)
    first, last = max(int(np.floor(a)), 0), min(int(np.ceil(b)), surface.get_width())
    if last <= first or depth <= 0:
        return
    s0, s1 = s_of(np.arange(first, last)), s_of(np.arange(first, last) + 1)
    colours = greys(deposit.shade(np.minimum(s0, s1), np.maximum(s0, s1)))
    row = pygame.surfarray.make_surface(np.ascontiguousarray(colours[:, None, :]))
    surface.blit(pygame.transform.scale(row, (len(colours), depth)), (first, top))


def board_point(scene, s):
    """The points (k, 2) of the board at arc lengths s (as the marks measure them, x . t)."""
    s = np.atleast_1d(np.asarray(s, float))
    return s[:, None] * diagnostics.tangent(scene) + float(scene.o @ scene.n) * scene.n


def draw_marks(pygame, surface, runs, view):
    """Each run's mark (run["marks"], a Deposit) at the picture's scale, under the board's line,
    MARK_HEIGHT deep, a band each."""
    origin, row = view(board_point(runs[0]["scene"], 0.0))[0]
    row = round(float(row)) + 2
    depth = round(MARK_HEIGHT * view.unit * view.scale) // len(runs)
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
            (WHITE, f"black: {black}")]


@dataclass(frozen=True)
class Strip:
    """The strip: board arc length s at its column tip_column + scale (s - s_tip), a height d above
    the board at row board - scale d of each run's row; px from the strip's top left."""
    rect: tuple             # (left, top, width, height) in the picture, px
    scale: float            # px per m: MAGNIFICATION times the picture's
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


def layout(runs, t, view, font, top, bottom, below):
    """The runs' Strip (None: no room): from row `below` to `bottom` where each has a ROW_MIN row
    (the frames), else from `top` to the board beside the chalk and its hand at time t (the window),
    magnified about the tip's own column, or where that is off the strip, 3/4 along."""
    size, want = view.size, round(ROW * view.height)
    least = max(round(ROW_MIN * view.height), 12)
    scene, x = runs[0]["scene"], runs[0]["x"]
    board = float(view(board_point(scene, 0.0))[0, 1])

    def fit(room, width):
        """(each run's row, the header) in `room` px down a strip `width` px across."""
        head = header_rows(font, width, view.scale) * font.get_linesize() + 4
        return min(want, int(room - head - PAD) // len(runs)), head
    width, where = size - 24, "below the board"
    row, head = fit(bottom - below - 2 * PAD, width)
    left, strip_top = 12, int(below) + PAD
    if row < least:
        targets = [view(np.vstack([r["x"], r["scene"].hand.targets(t)]))[:, 0] for r in runs]
        body = np.concatenate(targets)
        room_left, room_right = body.min() - 24, size - body.max() - 24
        width, where = int(max(room_left, room_right)), "beside the chalk"
        row, head = fit(board - PAD - top - PAD, width)
        if row < least or width < MIN_WIDTH * size:
            return None
        left = 12 if room_left >= room_right else int(body.max()) + 12
        strip_top = int(board) - PAD - (head + len(runs) * row + PAD)
    rect = (left, strip_top, width, head + len(runs) * row + PAD)
    k, _ = diagnostics.tip(scene, x)
    s_tip = float(x[k] @ diagnostics.tangent(scene))
    column = float(view(x[k])[0]) - left
    if not 0.1 * width <= column <= 0.9 * width:
        covered = runs[0]["marks"].span()
        ahead = covered is not None and covered[0] > s_tip          # the mark right of the tip
        column = (0.25 if ahead else 0.75) * width
    band = max(4, round(MARK_DEPTH * row))
    rows = tuple((head + i * row, row) for i in range(len(runs)))
    return Strip(rect, MAGNIFICATION * view.scale, s_tip, column, rows, row - band - 4, band, where)


def title():
    return f"the chalk's mark, x{MAGNIFICATION:g}"


def bar_label():
    return f"{SCALE_BAR * 1e3:g} mm"


def header_rows(font, width, scale):
    """The strip's header, `width` px across in a picture of `scale` px/m: 1 row where the title
    and the scale bar fit side by side, else 2 (the bar under the title)."""
    bar = SCALE_BAR * MAGNIFICATION * scale
    return 1 if 4 * PAD + font.size(title())[0] + bar + font.size(bar_label())[0] <= width else 2


def draw_strip(pygame, surface, runs, strip, font):
    """The strip on its own surface, at strip.scale: per run a row with the board's line, the mark
    under it, the chalk about its tip (of several runs, each row's colour at its left end); the
    title and a SCALE_BAR scale bar on top; a border."""
    width = surface.get_width()
    surface.fill(WHITE)
    for run, (top, row) in zip(runs, strip.rows):
        scene, sub, board = run["scene"], surface.subsurface((0, top, width, row)), strip.board
        pygame.draw.line(sub, BOARD, (0, board), (width, board), 3)
        paint_mark(pygame, sub, run["marks"], strip.column, strip.board_at, board + 2, strip.band)
        x = run["x"]
        px = np.stack([strip.column(x @ diagnostics.tangent(scene)),
                       board - strip.scale * ((x - scene.o) @ scene.n)], axis=1)
        for line in square_mesh.polylines(*scene.cells):
            pygame.draw.lines(sub, run["color"], False, px[line].tolist(), 2)
        if len(runs) > 1:
            pygame.draw.rect(sub, run["color"], (0, 1, PAD, row - 2))
    surface.blit(font.render(title(), True, INK), (PAD, 4))
    bar, label = SCALE_BAR * strip.scale, font.render(bar_label(), True, INK)
    one_row = header_rows(font, width, strip.scale / MAGNIFICATION) == 1
    left = width - PAD - label.get_width() - 6 - bar if one_row else PAD
    top = 4 if one_row else 4 + font.get_linesize()
    y = top + font.get_ascent() - font.metrics("H")[0][3] // 2      # the capitals' middle
    bar = round(bar)                                                # its end ticks within
    pygame.draw.rect(surface, INK, (left, y - 1, bar, 3))
    for end in (left, left + bar - 2):
        pygame.draw.rect(surface, INK, (end, y - 5, 2, 11))
    surface.blit(label, (left + bar + 6, top))
    pygame.draw.rect(surface, INK, surface.get_rect(), 2)


def place_strip(pygame, surface, runs, t, view, font, rows, below):
    """The strip of the runs laid out (layout) between `rows` (top, bottom) and under row `below`,
    and a box around the board its first row magnifies; none where there is no room."""
    strip = layout(runs, t, view, font, *rows, below)
    if strip is None:
        return
    above = strip.board / strip.scale                               # m
    under = (strip.rows[0][1] - strip.board) / strip.scale
    s_lo, s_hi = strip.board_at(0.0), strip.board_at(strip.rect[2])
    corners = [board_point(runs[0]["scene"], s)[0] + d * runs[0]["scene"].n
               for s, d in ((s_lo, above), (s_hi, above), (s_hi, -under), (s_lo, -under))]
    pygame.draw.polygon(surface, INK, view(np.array(corners)).tolist(), 1)
    draw_strip(pygame, surface.subsurface(strip.rect), runs, strip, font)
