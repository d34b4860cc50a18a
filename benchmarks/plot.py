"""Log-log line plots drawn with pygame on an off-screen surface (no display needed), saved as PNG.

    save_loglog_panels(path, title, panels, legend)

`panels`: a list of Panel (title, axis titles, and series); every series is drawn as a polyline with
markers, in its Style (colour, dashed or not, marker shape); `legend`: (label, Style) pairs shown once
below the panels, since every panel uses the same styles. Axes are logarithmic with a tick and a
label at every power of ten in range (and unlabelled ticks at 2..9 times it when a panel spans few
decades).
"""
import io
import math
from dataclasses import dataclass, field

from viewer.output import whole_files
from viewer.pictures.draw import load_pygame

PANEL_W, PANEL_H = 620, 430         # pixels per panel, axes and labels included
MARGIN_L, MARGIN_R, MARGIN_T, MARGIN_B = 88, 20, 40, 62
COLUMNS = 2
PAD = 0.03                          # fraction of an axis's span left free beyond its end decades
BLACK, GREY, LIGHT = (0, 0, 0), (110, 110, 110), (228, 228, 228)


@dataclass(frozen=True)
class Style:
    color: tuple
    dashed: bool = False
    marker: str = "o"               # "o" circle, "s" square, "^" triangle, "d" diamond


@dataclass
class Panel:
    title: str
    xlabel: str
    ylabel: str
    series: list = field(default_factory=list)     # (Style, [(x, y), ...]); points with x or y <= 0 are left out


def _decades(values):
    """Whole powers of ten enclosing the positive values (at least one decade)."""
    lo = math.floor(math.log10(min(values)))
    hi = math.ceil(math.log10(max(values)))
    return lo, max(hi, lo + 1)


def _power_label(k):
    return {0: "1", 1: "10"}.get(k, f"1e{k}")


def _dashed_line(pygame, surface, color, a, b, width, dash=9, gap=6):
    length = math.dist(a, b)
    if length == 0.0:
        return
    ux, uy = (b[0] - a[0]) / length, (b[1] - a[1]) / length
    pos = 0.0
    while pos < length:
        end = min(pos + dash, length)
        pygame.draw.line(surface, color, (a[0] + ux * pos, a[1] + uy * pos),
                         (a[0] + ux * end, a[1] + uy * end), width)
        pos = end + gap


def _marker(pygame, surface, style, p, r=5):
    x, y = p
    if style.marker == "s":
        pygame.draw.rect(surface, style.color, (x - r, y - r, 2 * r, 2 * r))
    elif style.marker == "^":
        pygame.draw.polygon(surface, style.color, [(x, y - r - 1), (x - r - 1, y + r), (x + r + 1, y + r)])
    elif style.marker == "d":
        pygame.draw.polygon(surface, style.color, [(x, y - r - 1), (x + r + 1, y), (x, y + r + 1), (x - r - 1, y)])
    else:
        pygame.draw.circle(surface, style.color, (x, y), r)


def _draw_style_sample(pygame, surface, style, x, y, length=44):
    if style.dashed:
        _dashed_line(pygame, surface, style.color, (x, y), (x + length, y), 2, dash=7, gap=5)
    else:
        pygame.draw.line(surface, style.color, (x, y), (x + length, y), 2)
    _marker(pygame, surface, style, (x + length // 2, y))


def _draw_panel(pygame, surface, panel, left, top, fonts):
    small, normal = fonts
    x0, x1 = left + MARGIN_L, left + PANEL_W - MARGIN_R
    y0, y1 = top + MARGIN_T, top + PANEL_H - MARGIN_B
    points = [(x, y) for _, pts in panel.series for x, y in pts if x > 0 and y > 0]
    title = normal.render(panel.title, True, BLACK)
    surface.blit(title, (left + (PANEL_W - title.get_width()) // 2, top + 10))
    pygame.draw.rect(surface, BLACK, (x0, y0, x1 - x0, y1 - y0), 1)
    if not points:
        return
    (xlo, xhi), (ylo, yhi) = _decades([p[0] for p in points]), _decades([p[1] for p in points])

    def to_px(x, y):
        # PAD of each axis's span is left free at both ends, so no marker sits on the frame
        fx = (math.log10(x) - xlo + PAD * (xhi - xlo)) / ((1 + 2 * PAD) * (xhi - xlo))
        fy = (math.log10(y) - ylo + PAD * (yhi - ylo)) / ((1 + 2 * PAD) * (yhi - ylo))
        return (round(x0 + fx * (x1 - x0)), round(y1 - fy * (y1 - y0)))

    for lo, hi, axis in ((xlo, xhi, "x"), (ylo, yhi, "y")):
        minor = hi - lo <= 4
        for k in range(lo, hi + 1):
            for mult in range(1, 10 if (minor and k < hi) else 2):
                value = mult * 10.0 ** k
                if axis == "x":
                    px = to_px(value, 10.0 ** ylo)[0]
                    if mult == 1:
                        pygame.draw.line(surface, LIGHT, (px, y0 + 1), (px, y1 - 1))
                    pygame.draw.line(surface, BLACK, (px, y1), (px, y1 - (8 if mult == 1 else 4)))
                else:
                    py = to_px(10.0 ** xlo, value)[1]
                    if mult == 1:
                        pygame.draw.line(surface, LIGHT, (x0 + 1, py), (x1 - 1, py))
                    pygame.draw.line(surface, BLACK, (x0, py), (x0 + (8 if mult == 1 else 4), py))
                if mult == 1:
                    label = small.render(_power_label(k), True, BLACK)
                    if axis == "x":
                        surface.blit(label, (px - label.get_width() // 2, y1 + 6))
                    else:
                        surface.blit(label, (x0 - label.get_width() - 6, py - label.get_height() // 2))
    pygame.draw.rect(surface, BLACK, (x0, y0, x1 - x0, y1 - y0), 1)

    xlabel = small.render(panel.xlabel, True, BLACK)
    surface.blit(xlabel, ((x0 + x1 - xlabel.get_width()) // 2, y1 + 30))
    ylabel = pygame.transform.rotate(small.render(panel.ylabel, True, BLACK), 90)
    surface.blit(ylabel, (left + 8, (y0 + y1 - ylabel.get_height()) // 2))

    for style, pts in panel.series:
        px = [to_px(x, y) for x, y in pts if x > 0 and y > 0]
        for a, b in zip(px, px[1:]):
            if style.dashed:
                _dashed_line(pygame, surface, style.color, a, b, 2)
            else:
                pygame.draw.line(surface, style.color, a, b, 2)
        for p in px:
            _marker(pygame, surface, style, p)


def save_loglog_panels(path, title, panels, legend, notes=()):
    """Draw the panels in a grid of COLUMNS, the legend and notes below, and save as PNG (atomically)."""
    pygame = load_pygame()
    small, normal, big = (pygame.font.Font(None, s) for s in (22, 26, 32))
    rows = math.ceil(len(panels) / COLUMNS)
    legend_rows = math.ceil(len(legend) / 3)
    width = COLUMNS * PANEL_W
    height = 50 + rows * PANEL_H + 30 + 28 * legend_rows + 24 * len(notes) + 16
    surface = pygame.Surface((width, height))
    surface.fill((255, 255, 255))
    heading = big.render(title, True, BLACK)
    surface.blit(heading, ((width - heading.get_width()) // 2, 14))
    for i, panel in enumerate(panels):
        _draw_panel(pygame, surface, panel, (i % COLUMNS) * PANEL_W, 50 + (i // COLUMNS) * PANEL_H,
                    (small, normal))
    y = 50 + rows * PANEL_H + 16
    column_w = width // 3
    for i, (label, style) in enumerate(legend):
        x, row_y = 40 + (i % 3) * column_w, y + 28 * (i // 3)
        _draw_style_sample(pygame, surface, style, x, row_y + 9)
        surface.blit(normal.render(label, True, BLACK), (x + 56, row_y))
    y += 28 * legend_rows + 8
    for note in notes:
        surface.blit(small.render(note, True, GREY), (40, y))
        y += 24
    buffer = io.BytesIO()
    pygame.image.save(surface, buffer, "png")
    whole_files.write_atomic(path, buffer.getvalue())
