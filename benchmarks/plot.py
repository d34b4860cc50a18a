"""Log-log line plots drawn with pygame on an off-screen surface (no display), saved as PNG: a
labelled tick at every power of ten in range, minor ticks where the axis spans few decades."""
import math
from collections import namedtuple

from viewer.output import whole_files
from viewer.pictures.draw import load_pygame, png_data

PANEL_W, PANEL_H = 620, 430         # pixels per panel, axes and labels included
MARGIN_L, MARGIN_R, MARGIN_T, MARGIN_B = 88, 20, 40, 62
COLUMNS = 2
PAD = 0.03                          # fraction of an axis's span left free beyond its end decades
BLACK, GREY, LIGHT = (0, 0, 0), (110, 110, 110), (228, 228, 228)
Style = namedtuple("Style", "color dashed")      # dashed lines have square markers, solid round


def decades(values):
    """Whole powers of ten enclosing the positive values (at least one decade)."""
    lo = math.floor(math.log10(min(values)))
    return lo, max(math.ceil(math.log10(max(values))), lo + 1)


def ticks(lo, hi):
    """(power, multiple) of each tick: the powers of ten, and 2..9 times them over few decades."""
    return [(k, mult) for k in range(lo, hi + 1)
            for mult in (range(1, 10) if hi - lo <= 4 and k < hi else (1,))]


def power_label(k):
    return {0: "1", 1: "10"}.get(k, f"1e{k}")


def line(pygame, surface, style, a, b, dash=9, gap=6):
    """A line from a to b, 2 px wide, in the style's colour, dashed if the style is."""
    length = math.dist(a, b)
    if not style.dashed or length == 0.0:
        pygame.draw.line(surface, style.color, a, b, 2)
        return
    u = ((b[0] - a[0]) / length, (b[1] - a[1]) / length)
    for pos in range(0, math.ceil(length), dash + gap):
        end = min(pos + dash, length)
        pygame.draw.line(surface, style.color, (a[0] + u[0] * pos, a[1] + u[1] * pos),
                         (a[0] + u[0] * end, a[1] + u[1] * end), 2)


def marker(pygame, surface, style, p, r=5):
    if style.dashed:
        pygame.draw.rect(surface, style.color, (p[0] - r, p[1] - r, 2 * r, 2 * r))
    else:
        pygame.draw.circle(surface, style.color, p, r)


def draw_panel(pygame, surface, title, series, labels, left, top, small, normal):
    """One panel: `series` ({Style: [(x, y), ...], x and y > 0}) in a box with log axes."""
    box = pygame.Rect(left + MARGIN_L, top + MARGIN_T, PANEL_W - MARGIN_L - MARGIN_R,
                      PANEL_H - MARGIN_T - MARGIN_B)
    title = normal.render(title, True, BLACK)
    surface.blit(title, (left + (PANEL_W - title.get_width()) // 2, top + 10))
    pygame.draw.rect(surface, BLACK, box, 1)
    points = [p for pts in series.values() for p in pts]
    if not points:
        return
    (xlo, xhi), (ylo, yhi) = decades([p[0] for p in points]), decades([p[1] for p in points])

    def fraction(value, lo, hi):        # PAD of the span left free at both ends
        return (math.log10(value) - lo + PAD * (hi - lo)) / ((1 + 2 * PAD) * (hi - lo))

    def to_px(x, y):
        return (round(box.left + fraction(x, xlo, xhi) * box.width),
                round(box.bottom - fraction(y, ylo, yhi) * box.height))

    for k, mult in ticks(xlo, xhi):
        x = to_px(mult * 10.0 ** k, 10.0 ** ylo)[0]
        if mult == 1:
            pygame.draw.line(surface, LIGHT, (x, box.top + 1), (x, box.bottom - 1))
            label = small.render(power_label(k), True, BLACK)
            surface.blit(label, (x - label.get_width() // 2, box.bottom + 6))
        pygame.draw.line(surface, BLACK, (x, box.bottom), (x, box.bottom - (8 if mult == 1 else 4)))
    for k, mult in ticks(ylo, yhi):
        y = to_px(10.0 ** xlo, mult * 10.0 ** k)[1]
        if mult == 1:
            pygame.draw.line(surface, LIGHT, (box.left + 1, y), (box.right - 1, y))
            label = small.render(power_label(k), True, BLACK)
            surface.blit(label, (box.left - label.get_width() - 6, y - label.get_height() // 2))
        pygame.draw.line(surface, BLACK, (box.left, y), (box.left + (8 if mult == 1 else 4), y))
    xlabel = small.render(labels[0], True, BLACK)
    surface.blit(xlabel, (box.centerx - xlabel.get_width() // 2, box.bottom + 30))
    ylabel = pygame.transform.rotate(small.render(labels[1], True, BLACK), 90)
    surface.blit(ylabel, (left + 8, box.centery - ylabel.get_height() // 2))
    for style, pts in series.items():
        px = [to_px(x, y) for x, y in pts]
        for a, b in zip(px, px[1:]):
            line(pygame, surface, style, a, b)
        for p in px:
            marker(pygame, surface, style, p)


def save_loglog_panels(path, title, panels, labels, legend, notes):
    """`panels` ({title: series}, axes' `labels` (x, y) shared) in a grid of COLUMNS, the `legend`
    ({Style: label}) and `notes` below, saved as PNG (written whole)."""
    pygame = load_pygame()
    small, normal, big = (pygame.font.Font(None, s) for s in (22, 26, 32))
    rows, legend_rows = math.ceil(len(panels) / COLUMNS), math.ceil(len(legend) / 3)
    width = COLUMNS * PANEL_W
    surface = pygame.Surface((width, 96 + rows * PANEL_H + 28 * legend_rows + 24 * len(notes)))
    surface.fill((255, 255, 255))
    heading = big.render(title, True, BLACK)
    surface.blit(heading, ((width - heading.get_width()) // 2, 14))
    for i, (panel, series) in enumerate(panels.items()):
        draw_panel(pygame, surface, panel, series, labels, (i % COLUMNS) * PANEL_W,
                   50 + (i // COLUMNS) * PANEL_H, small, normal)
    y = 66 + rows * PANEL_H
    for i, (style, label) in enumerate(legend.items()):
        x, row_y = 40 + (i % 3) * (width // 3), y + 28 * (i // 3)
        line(pygame, surface, style, (x, row_y + 9), (x + 44, row_y + 9), dash=7, gap=5)
        marker(pygame, surface, style, (x + 22, row_y + 9))
        surface.blit(normal.render(label, True, BLACK), (x + 56, row_y))
    for i, note in enumerate(notes):
        surface.blit(small.render(note, True, GREY), (40, y + 28 * legend_rows + 8 + 24 * i))
    whole_files.write_whole(path, png_data(pygame, surface), replace=True)
