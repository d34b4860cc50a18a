"""The live window's Newton view (key n): a Newton iterate of the step in progress, as Algorithm 4
computed it. In the window, x^i in grey under x^i + alpha p in blue and the direction of p at each
node; beside the square, an inset with one node and the slope magnified together, so that p, the
CCD bound alpha_CCD and the accepted alpha are seen at their true size against the slope; in the
status, the iterate's figures (iterate_lines). The chalk's the same, against its board (ground).
"""
import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage, spatial

import BarrierEnergy
from viewer.pictures import draw

HINT = 0.035              # the window's arrows (the direction of p) are this fraction of the window long,
HINT_FLOOR = 0.01         # ... drawn where |p_k| is at least this fraction of the largest
INSET = 0.4               # the inset: its width at most this fraction of the window's,
MIN_INSET = 0.25          # ... and at least this, over the square where there is no more room beside it,
INSET_TALL = 0.6          # ... its height at most this fraction of the window's,
INSET_FILL = 0.75         # ... the node's x^i, x^i + p (and its foot on the slope) filling this much of it,
SLOPE_REACH = 1.5         # ... the slope framed where the node is within this many |p_k| of it (the CCD
                          #     bound can only come from a node within |p_k| / 0.9)
MAX_ZOOM = 1e4            # ... magnified at most this much (p_k = 0 would ask for infinitely much)
ZOOMS = (1, 2, 3, 5)      # ... by one of these times a power of ten
GROUND = (219, 219, 255)  # the inset's tint below the slope
BREAKS = ("   ", "; ", " (", ", ", " ")    # where a line of text may break, the strongest first


@dataclass(frozen=True)
class Inset:
    """The Newton view's inset: one node of the iterate and the slope, magnified together, so that
    p, the CCD bound and the accepted step are seen at their true size against the slope. Pixels are
    the inset's own, from its top-left corner."""
    rect: tuple             # (left, top, width, height) in the window, px
    node: int               # the node magnified
    why: str                # why that node: it sets alpha_CCD, or it is the nearest to the slope
    view: draw.View         # world to the inset's pixels, at `magnification` times the window's scale
    magnification: float
    points: dict            # name -> (2,) world position of the node: x^i, x^i + p, ... (Algorithm 4)
    markers: dict           # name -> (2,) the same in the inset's pixels, where they are drawn
    slope: tuple            # the slope's line as drawn: its two ends in the inset's pixels (None: not drawn)
    distance: float         # the node's distance to the slope at x^i, m (inf without a slope)

    @property
    def title(self):
        """The inset's first line: the node and the magnification."""
        return f"node {self.node}, x{self.magnification:g}"


def focus_node(scene, it):
    """The node the inset magnifies, and why: the one whose approach to the slope sets alpha_CCD
    (Algorithm 4, line 1) when the CCD bound cuts the step, else the one nearest the slope (without
    a slope, the lowest)."""
    if "barrier" not in scene.terms:
        return int(np.argmin(it.x[:, 1])), "the lowest"
    if it.alpha_ccd < 1.0:
        return int(np.argmax(BarrierEnergy.approach_rates(it.x, scene.n, scene.o, it.p))), "sets alpha_CCD"
    return int(np.argmin(BarrierEnergy.distances(it.x, scene.n, scene.o))), f"nearest {ground(scene)}"


def ground(scene):
    """What the barrier keeps the body above, in the window's words: the chalk's board, the square's slope."""
    return "the board" if scene.hand is not None else "the slope"


def newton_inset(scene, it, view, rect, header=0, footer=0, whole=False):
    """The Inset of a Newton iterate in `rect` (its height cut to what the framed points need, at
    least half its width, unless `whole`): its focus node's x^i, x^i + p, x^i + alpha_CCD p,
    x^i + alpha p and the slope (where the node is within SLOPE_REACH |p_k| of it), framed to fill
    INSET_FILL of the inset's rows between `header` and `footer` pixels from its top and bottom, at
    a magnification of `view`'s scale of one of ZOOMS times a power of ten, at most MAX_ZOOM."""
    k, why = focus_node(scene, it)
    x, p = it.x[k], it.p[k]
    points = {"x^i": x, "x^i + p": x + p, "x^i + alpha_CCD p": x + it.alpha_ccd * p,
              "x^i + alpha p": x + it.alpha * p}
    framed, d = [x, x + p], slope_distance(scene, x)
    with_slope = frames_slope(d, p)
    if with_slope:
        framed.append(x - d * scene.n)                          # its foot on the slope
    lo, hi = np.min(framed, axis=0), np.max(framed, axis=0)
    width, height = rect[2:]
    room = np.array([width, height - header - footer])          # px, across and down
    extent = (hi - lo) * view.scale                            # px, at the window's scale
    fit = min((INSET_FILL * room[extent > 0] / extent[extent > 0]).tolist(), default=MAX_ZOOM)
    magnification = draw.nice_number(min(fit, MAX_ZOOM), ZOOMS)
    if not whole:
        room[1] = min(room[1], max(0.5 * width, extent[1] * magnification / INSET_FILL))
    height = int(header + room[1] + footer)                   # no taller than the framed points need
    rect = (*rect[:3], height)
    inset_view = draw.View(view.scale * magnification, width, height)
    middle = header + 0.5 * room[1]                             # the row the framed points centre on
    inset_view.center = 0.5 * (lo + hi) + [0.0, (middle - 0.5 * height) / inset_view.scale]
    markers = {name: inset_view(point) for name, point in points.items()}
    return Inset(rect, k, why, inset_view, magnification, points, markers,
                 draw.slope_ends(scene, inset_view) if with_slope else None, d)


def slope_distance(scene, x):
    """The distance d = n^T (x - o) of one point x to the slope, m (inf without a slope)."""
    if "barrier" not in scene.terms:
        return math.inf
    return float(BarrierEnergy.distances(x[None], scene.n, scene.o)[0])


def frames_slope(d, p):
    """Does the inset frame the slope with a node at distance d whose step is p? Where d is within
    SLOPE_REACH |p|."""
    return d <= SLOPE_REACH * float(np.hypot(*p))


def inset_notes(scene, it):
    """(text, colour) under the inset's title: why its node; where the slope is when it is out of
    frame; and what the thin lines are, so that a spring lying along the slope is not read as it."""
    k, why = focus_node(scene, it)
    d = slope_distance(scene, it.x[k])
    notes = [(f"({why})", draw.BLACK)]
    if math.isfinite(d) and not frames_slope(d, it.p[k]):
        notes.append((f"{ground(scene)}: {length_text(d)} below x^i, out of frame", draw.BLUE))
    return notes + [("thin lines: springs", draw.BLACK)]


def draw_inset(pygame, surface, scene, it, inset, fonts, notes):
    """The inset on its own `surface`: the slope (tinted below), the springs of x^i (grey) and
    x^{i+1} (blue) about the node, p as a red arrow from x^i, a black ring at x^i + alpha_CCD p, a
    green dot at x^i + alpha p, all in one magnified frame; the node and the magnification at the
    top with `notes` (rows of (text, colour)) under them, a scale bar at the bottom, a border."""
    view, m = inset.view, inset.markers
    width, height = surface.get_size()
    surface.fill((255, 255, 255))
    if inset.slope is not None:
        a, b = inset.slope
        below = 2 * (width + height) * np.array([-scene.n[0], scene.n[1]])    # -n on screen, far
        pygame.draw.polygon(surface, GROUND, [a.tolist(), b.tolist(), (b + below).tolist(), (a + below).tolist()])
        pygame.draw.line(surface, draw.BLUE, a.tolist(), b.tolist(), 3)
    draw.draw_square(pygame, surface, scene, it.x, view, draw.GREY, nodes=False)
    draw.draw_square(pygame, surface, scene, it.x_next, view, nodes=False)
    tail, tip = m["x^i"], m["x^i + p"]
    r = max(3, round(0.016 * width))                                        # px, the markers' radius
    pygame.draw.line(surface, draw.RED, tail.tolist(), tip.tolist(), 3)
    if np.hypot(*(tip - tail)) > 1.0:
        pygame.draw.polygon(surface, draw.RED, [tip.tolist()] + draw.arrow_heads(tail[None], tip[None], 3 * r)[0].tolist())
    pygame.draw.circle(surface, draw.GREY, tail.tolist(), r)
    pygame.draw.circle(surface, draw.BLACK, m["x^i + alpha_CCD p"].tolist(), r + 2, 2)
    pygame.draw.circle(surface, draw.GREEN, m["x^i + alpha p"].tolist(), r)
    big, small = fonts
    surface.blit(big.render(inset.title, True, draw.BLACK), (8, 6))
    row = 6 + big.get_linesize()
    for text, color in notes:
        surface.blit(small.render(text, True, color), (8, row))
        row += small.get_linesize()
    metres = draw.nice_number(0.3 * width / view.scale)
    bar, y = metres * view.scale, height - 6 - small.get_linesize() // 2
    pygame.draw.line(surface, draw.BLACK, (8, y), (8 + bar, y), 3)
    surface.blit(small.render(length_text(metres), True, draw.BLACK), (14 + bar, y - small.get_linesize() // 2))
    pygame.draw.rect(surface, draw.BLACK, surface.get_rect(), 2)


def length_text(metres):
    """A length in m, mm or micrometres (um), to 3 digits."""
    if metres >= 1.0:
        return f"{metres:.3g} m"
    return f"{metres * 1e3:.3g} mm" if metres >= 1e-3 else f"{metres * 1e6:.3g} um"


def iterate_lines(run, scene):
    """The figures of Algorithm 4 for the iterate on screen, and what the colours show."""
    it = run.iterate
    friction = ("lagged friction" if it.friction_update == 0 else
                f"friction update {it.friction_update}, Algorithm 5")
    verdict = "<=" if it.residual <= scene.tol else ">"
    return [f"step {run.index + 1}, Newton iteration {run.iteration} ({friction})",
            f"||p||_inf / h = {it.residual:.3g} m/s {verdict} tol = {scene.tol:g} m/s at x^i",
            f"CCD bound alpha_CCD = {it.alpha_ccd:.4g} (black ring: x^i + alpha_CCD p)",
            f"accepted alpha = alpha_CCD / 2^{it.halvings} = {it.alpha:.4g} (green dot: x^i + alpha p)",
            "grey: x^i; blue: x^i + alpha p; red: the direction of p at each node",
            f"inset: one node and {ground(scene)} magnified together; p (red) to scale"]


def draw_iterate(pygame, surface, scene, it, view):
    """The main view of a Newton iterate: x^i in grey under x^{i+1} = x^i + alpha p in blue, and
    at each node an arrow of fixed length in the direction of p (where |p_k| is at least
    HINT_FLOOR of the largest): a hint of direction only, p itself is too short to see here. The
    arrows are HINT of the window long, at most a node spacing (the chalk's nodes are closer)."""
    size = view.size
    reach = min(HINT * size, draw.spacing(scene) * view.scale)         # px
    draw.draw_square(pygame, surface, scene, it.x, view, draw.GREY, nodes=False)
    draw.draw_square(pygame, surface, scene, it.x_next, view)
    length = np.hypot(it.p[:, 0], it.p[:, 1])
    shown = (length > 0.0) & (length >= HINT_FLOOR * length.max())
    tail = view(it.x[shown])
    direction = it.p[shown] / length[shown, None] * [1.0, -1.0]        # y grows downwards on screen
    tip = tail + reach * direction
    heads = draw.arrow_heads(tail, tip, min(0.012 * size, 0.5 * reach))
    for a, b, (w1, w2) in zip(tail.tolist(), tip.tolist(), heads.tolist()):
        pygame.draw.line(surface, draw.RED, a, b, 2)
        pygame.draw.polygon(surface, draw.RED, [b, w1, w2])


def place_inset(pygame, surface, scene, it, view, fonts, top, bottom):
    """The inset of a Newton iterate between rows `top` and `bottom`, beside the square on the
    side with more room (over it only where that room is under MIN_INSET of the window), its node
    circled and labelled in the main view (label_corner); its border cuts no number of the slope
    (slope_numbers): the inset covers it whole, else ends above it. Returns its Inset (None where
    the text leaves no room)."""
    size, px = view.size, view(it.x)
    room_left, room_right = px[:, 0].min(), size - px[:, 0].max()
    width = int(min(INSET * size, max(max(room_left, room_right) - 24, MIN_INSET * size)))
    height = int(min(INSET_TALL * size, bottom - top))
    big, small = fonts
    notes = [(row, color) for text, color in inset_notes(scene, it)
             for row in phrase_rows(small, text, width - 16)]
    line = small.get_linesize()
    header, footer = 8 + big.get_linesize() + len(notes) * line, 12 + line
    if height < header + footer + line:                    # no room left under the text
        return None
    rect = (12 if room_left > room_right else size - 12 - width, int(top), width, height)
    inset = newton_inset(scene, it, view, rect, header, footer)
    numbers = slope_numbers(pygame, scene, view, small)
    for _ in numbers:           # a slope's number its border cuts: covered whole, else ended above
        cut = [box for box in numbers if overlap(box, inset.rect) and not inside(box, inset.rect)]
        if not cut:
            break
        box = min(cut, key=lambda box: box[1])
        if box[3] + 2 - rect[1] <= height and rect[0] <= box[0] and box[2] <= rect[0] + width:
            taller = (*rect[:3], box[3] + 2 - rect[1])
            inset = newton_inset(scene, it, view, taller, header, footer, whole=True)
        elif box[1] - 2 - rect[1] >= header + footer + line:
            inset = newton_inset(scene, it, view, (*rect[:3], box[1] - 2 - rect[1]), header, footer)
        else:
            break
    node = px[inset.node]
    label = small.render(f"node {inset.node}", True, draw.BLACK, (255, 255, 255))    # on white
    pygame.draw.circle(surface, draw.BLACK, node.tolist(), 9, 1)
    corner = label_corner(scene, view, px, node, label.get_size(), inset.rect, (top, bottom),
                          numbers)
    surface.blit(label, corner)
    draw_inset(pygame, surface.subsurface(inset.rect), scene, it, inset, fonts, notes)
    return inset


def overlap(box, rect, gap=0):
    """Do the box (left, top, right, bottom) and the rect (left, top, width, height) overlap, or
    come closer than `gap` px?"""
    a, b, c, d = rect
    return box[0] < a + c + gap and a < box[2] + gap and box[1] < b + d + gap and b < box[3] + gap


def inside(box, rect):
    """Is the box (left, top, right, bottom) inside the rect (left, top, width, height)?"""
    a, b, c, d = rect
    return a <= box[0] and box[2] <= a + c and b <= box[1] and box[3] <= b + d


def phrase_rows(font, text, width, breaks=BREAKS):
    """`text` in rows at most `width` px wide, broken where its phrases meet: between the key hints
    (three spaces), else after a semicolon, else before a parenthesis, else after a comma, and only
    then between words (a word wider than `width` stays whole): no row a stray fragment ("p)")."""
    if font.size(text)[0] <= width or not breaks:
        return [text]
    sep, weaker = breaks[0], breaks[1:]
    pieces = text.split(sep)
    if sep == " (":
        pieces = pieces[:1] + ["(" + piece for piece in pieces[1:]]
    else:
        pieces = [piece + sep.strip() for piece in pieces[:-1]] + pieces[-1:]
    joiner, rows = "   " if sep == "   " else " ", []
    for piece in pieces:
        if rows and font.size(rows[-1] + joiner + piece)[0] <= width:
            rows[-1] += joiner + piece
        else:
            rows.append(piece)
    return [part for row in rows for part in phrase_rows(font, row, width, weaker)]


def label_corner(scene, view, px, node, size, inset, rows=None, numbers=()):
    """The top-left corner (px) of the label, `size` (w, h), of the circled node at `node` (`px`: the
    body's nodes): off the node diagonally, away from the body's middle, else on its other sides,
    then a row further off; for the chalk, whose tip has the board's marks and numbers under it, on
    the board beside the body, either side. The first of these that is clear of the `inset` (left,
    top, width, height), inside the window between `rows` (top, bottom; default the whole window),
    a fifth of its height off the slope's `numbers` (boxes: slope_numbers) and off the body (its
    convex hull, at 5 x 3 points of the label); else the first that is all that but off the body;
    else the first clear of the inset."""
    w, h = size
    out = np.where(node >= px.mean(axis=0), 1, -1)
    top_row, bottom_row = (0, view.height) if rows is None else rows
    corners = []
    turns = ((out[0], out[1]), (out[0], -out[1]), (-out[0], out[1]), (-out[0], -out[1]))
    for further, (side, up) in [(f, turn) for f in (0, h + 4) for turn in turns]:
        if scene.hand is None:
            corners.append((node[0] + side * (6 + w / 2) - w / 2,
                            node[1] + up * (14 + further + h / 2) - h / 2))
        elif up == out[1] and not further:
            top = min(float(view(scene.o)[1]), node[1] + h / 2) - 2 - h      # resting on the (flat) board
            level = px[(px[:, 1] >= top) & (px[:, 1] <= top + h), 0]         # the body's nodes beside it
            left = (max(level.max(initial=node[0]), node[0] + 4) + 8 if side > 0 else
                    min(level.min(initial=node[0]), node[0] - 4) - 8 - w)
            corners.append((min(max(left, 0), view.size - w), top))
    boxes = {corner: (corner[0], corner[1], corner[0] + w, corner[1] + h) for corner in corners}
    clear = [corner for corner in corners if not overlap(boxes[corner], inset)]
    free = [corner for corner in clear
            if inside(boxes[corner], (0, top_row, view.size, bottom_row - top_row))
            and not any(overlap(number, (*corner, w, h), h // 5) for number in numbers)]
    hull = spatial.ConvexHull(px, qhull_options="QJ").equations      # n . q + c <= 0 inside
    grid = np.stack(np.meshgrid(np.linspace(0, w, 5), np.linspace(0, h, 3)), -1).reshape(-1, 2)

    def over_body(corner):
        return ((corner + grid) @ hull[:, :2].T + hull[:, 2] <= 0).all(axis=1).any()
    return next((corner for corner in free if not over_body(corner)), (free or clear or corners)[0])


def slope_numbers(pygame, scene, view, font):
    """The boxes (left, top, right, bottom; px) of the slope's numbers in the window: the pixels
    draw.draw_slope draws with `font` and not without, each number's glyphs together (none without
    a slope)."""
    if scene.n is None:
        return []
    ink = []
    for with_font in (font, None):
        surface = pygame.Surface((view.size, view.height))
        surface.fill((255, 255, 255))
        draw.draw_slope(pygame, surface, scene, view, draw.BLUE, with_font)
        ink.append(pygame.surfarray.array3d(surface).min(axis=2) < 255)
    glyphs, word = ink[0] & ~ink[1], font.get_height()     # px: one number's glyphs are closer
    numbers, _ = ndimage.label(ndimage.binary_dilation(glyphs, np.ones((word, 1), bool)))
    boxes = ndimage.find_objects(np.where(glyphs, numbers, 0))
    return [(x.start, y.start, x.stop, y.stop) for x, y in boxes]
