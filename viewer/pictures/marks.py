"""The mark the chalk leaves on the board, by Archard's wear law, and how the frames, the live
window and the stick-slip figure draw it: grey on white, black where the most was left.

Archard's law: the volume worn off a sliding body is k N L / H (N the normal force, L the length
slid, H the hardness, k a wear coefficient), so the material left per unit length of board is
proportional to the normal force times the length slid there. Over each step (`Deposit.step`), every
node k within dhat of the board leaves lambda_k (the barrier's normal force on it at x^{n+1}, N)
times its slide along the board from x^n to x^{n+1}, spread evenly over the BIN-wide stretches of
board it slid across (`archard`). The unknown k / H is left out: a bin holds N m, its sum over the
run the sum over steps of lambda_k |delta s_k|. A run keeps the bins over the stretch of board its
mark covers (grown as the mark grows: its memory is bounded by the board touched, not by the run's
length), and writes them as marks.csv (`csv_text`). docs/chalk.md says what the mark looks like and
why.

Drawn at the picture's scale under the board (a column of pixels holds several bins: their mean),
and in a strip of the board about the tip magnified MAGNIFICATION times (x8: a bin is 3.2 px in the
900-px frames), each run's mark scaled to its own darkest bin (black). No pygame import (it comes in
as an argument) and no import of viewer.pictures.draw (which draws the frame and calls these)."""
from dataclasses import dataclass
from itertools import pairwise

import numpy as np

import square_mesh
from analysis import diagnostics

BIN = 1e-4                  # m of board per bin of the mark: 0.1 mm
UNIT = "N m per 0.1 mm"     # what a bin holds: lambda_k times the length slid in it, summed
MARK_HEIGHT = 0.06          # m (of the lecture's scale, times View.unit): the mark's depth
MAGNIFICATION = 8           # the strip's scale: this many times the picture's
SCALE_BAR = 1e-3            # m: the strip's scale bar, about one slip of the pushed chalk
ROW, ROW_MIN = 0.1, 0.03    # of the picture's height: a run's row of the strip, and the least it shrinks to
MARK_DEPTH = 2 / 7          # of a row: the mark's depth under the strip's board
MIN_WIDTH = 0.25            # of the picture's width: the narrowest strip drawn beside the chalk
PAD = 8                     # px between the strip and what it sits beside, and inside its border
SWATCH = (73, 73, 85)       # the legend's swatch of the mark: a dark grey of the frames' PALETTE
RISE = 2.0                  # a dash begins at a bin holding more than this times the one before


# ------------------------------------------------------------------------------------------------
# The deposit (no pygame)
# ------------------------------------------------------------------------------------------------

def archard(s0, s1, lam, width=BIN):
    """One step's deposit by Archard's law: node k slides along the board from s0_k to s1_k (m)
    under the normal force lam_k (N); bin j, the board from j width to (j + 1) width, receives lam_k
    times the length of that slide within it, summed over k. Returns (j0, deposit): deposit[i] is
    bin j0 + i's (N m), over the bins the slides cross; its sum is sum_k lam_k |s1_k - s0_k|."""
    s0, s1, lam = (np.asarray(a, float) for a in (s0, s1, lam))
    lo, hi = np.minimum(s0, s1), np.maximum(s0, s1)
    on = (lam > 0) & (hi > lo)
    if not on.any():
        return 0, np.zeros(0)
    lo, hi, lam = lo[on], hi[on], lam[on]
    j0, j1 = int(np.floor(lo.min() / width)), int(np.floor(hi.max() / width)) + 1
    edges = np.arange(j0, j1 + 1) * width
    # lam_k times the length of node k's slide below each edge, summed over k; differenced, per bin
    below = (lam[:, None] * np.clip(edges - lo[:, None], 0.0, (hi - lo)[:, None])).sum(axis=0)
    return j0, np.diff(below)


class Deposit:
    """The mark so far: the deposit (N m) of each bin from `first` on (`values`), over the stretch
    of board the mark covers. Its storage grows by doubling as the mark spreads, so its memory stays
    within a few times the bins touched however long the run."""

    def __init__(self, width=BIN):
        self.width = width
        self.store, self.base = np.zeros(0), 0     # bins base, base + 1, ...; some not reached yet
        self.lo = self.hi = 0                      # the bins touched: lo <= j < hi

    def add(self, j0, deposit):
        """Add `deposit` to the bins from j0 on (archard's result)."""
        if not len(deposit):
            return
        j1 = j0 + len(deposit)
        lo, hi = (j0, j1) if self.lo == self.hi else (min(self.lo, j0), max(self.hi, j1))
        end, empty = self.base + len(self.store), not len(self.store)
        if empty or lo < self.base or hi > end:     # room for as much again on each side outgrown
            base = lo - (hi - lo) if empty or lo < self.base else self.base
            store = np.zeros((hi + (hi - lo) if empty or hi > end else end) - base)
            store[self.base - base:end - base] = self.store
            self.store, self.base = store, base
        self.store[j0 - self.base:j1 - self.base] += deposit
        self.lo, self.hi = lo, hi

    def step(self, scene, x0, x1):
        """A step from x0 to x1 (node positions): each node's normal force lambda_k at x1 (zero
        beyond dhat; diagnostics.normal_forces) and its positions along the board, through
        `archard`. Returns the step's deposit, sum_k lambda_k |delta s_k| (N m)."""
        tangent = diagnostics.tangent(scene)
        lam = diagnostics.normal_forces(scene, x1) @ scene.n
        j0, deposit = archard(x0 @ tangent, x1 @ tangent, lam, self.width)
        self.add(j0, deposit)
        return float(deposit.sum())

    @property
    def first(self):
        return self.lo

    @property
    def values(self):
        """The touched bins' deposits (N m), from bin `first` on (a view)."""
        return self.store[self.lo - self.base:self.hi - self.base]

    def centres(self):
        """The touched bins' middles along the board (m)."""
        return (self.lo + np.arange(self.hi - self.lo) + 0.5) * self.width

    def span(self):
        """The board the mark covers, (from, to) in m; None before any deposit."""
        return None if self.hi == self.lo else (self.lo * self.width, self.hi * self.width)

    def darkest(self):
        """The largest bin's deposit (N m; 0 before any)."""
        return float(self.values.max()) if self.hi > self.lo else 0.0

    def copy(self):
        """A Deposit of its own holding the same bins (the tests keep runs at a step so)."""
        other = Deposit(self.width)
        other.store, other.base, other.lo, other.hi = self.store.copy(), self.base, self.lo, self.hi
        return other

    def shade(self, a, b):
        """How dark the mark is over each stretch of board [a_i, b_i] (m; a picture's pixel
        columns): its deposit per metre there over the darkest bin's, 0 (none) to 1. The deposit is
        taken as even within a bin, so a stretch inside one bin gets that bin's, one across several
        their mean."""
        darkest = self.darkest()
        a, b = np.asarray(a, float), np.asarray(b, float)
        if darkest <= 0:
            return np.zeros(np.broadcast(a, b).shape)
        edges = (self.lo + np.arange(self.hi - self.lo + 1)) * self.width
        below = np.concatenate([[0.0], np.cumsum(self.values)])        # the deposit below each edge
        held = np.interp(b, edges, below) - np.interp(a, edges, below)
        return np.clip(held / np.maximum(b - a, 1e-300) * self.width / darkest, 0.0, 1.0)


def dashes(values):
    """The dashes of a mark, from its bins' deposits (`values`, along the board): each begins at a
    bin holding more than RISE times the one before it (and a bin that only continues such a rise
    begins none). For each dash that the next one's start ends: (its first bin's index, its darkest
    bin's deposit, its faintest's: where it has faded to before the next begins)."""
    v = np.asarray(values, float)
    rises = np.r_[False, v[1:] > RISE * v[:-1]]
    starts = np.flatnonzero(rises & ~np.r_[False, rises[:-1]])
    return [(int(a), float(v[a:b].max()), float(v[a:b].min())) for a, b in pairwise(starts)]


def inside(values):
    """A mark's bins but its first and last: those the tip started in and is in, slid only partly
    across; what the percentiles of docs/chalk.md are taken over."""
    return np.asarray(values, float)[1:-1]


def csv_text(deposit):
    """marks.csv: a header, then a row per bin the mark covers: the bin's middle along the board
    (mm) and its deposit (N m: lambda times the length slid in it, summed over the run)."""
    centres, values = deposit.centres().tolist(), deposit.values.tolist()
    rows = [f"{1e3 * s:.2f},{d!r}" for s, d in zip(centres, values)]
    return "\n".join([f"x_mm,deposit_N_m_per_{deposit.width * 1e3:g}_mm"] + rows) + "\n"


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
