"""The Newton view (key n), as docs/live-demo.md shows it: an iterate of Algorithm 4, its inset."""
import math
from collections import namedtuple

import numpy as np
from scipy import ndimage, spatial

import BarrierEnergy
from viewer.pictures import draw, wrap

HINT = 0.035              # the direction arrows: this fraction of the window long,
HINT_FLOOR = 0.01         # ... where |p_k| is at least this fraction of the largest
INSET = 0.4               # the inset: at most this fraction of the window wide,
MIN_INSET = 0.25          # ... at least this (over the square where there is no room beside it),
INSET_TALL = 0.6          # ... at most this fraction of it tall,
INSET_FILL = 0.75         # ... x^i, x^i + p (and the slope's foot) filling this much of it,
SLOPE_REACH = 1.5         # ... the slope framed within this many |p_k| of the node,
MAX_ZOOM = 1e4            # ... magnified at most this much (p_k = 0 asks for infinitely much)
ZOOMS = (1, 2, 3, 5)      # ... by one of these times a power of ten
GROUND = (219, 219, 255)  # the inset's tint below the slope
RULE = (200, 200, 200)    # the line between the inset's drawing and its text panels
# The node magnified with the slope: its rect in the window (px), why it was chosen, the view to the
# inset's pixels, points (x^i, x^i + p, ..., m) and markers (the same in px), the slope's ends (px;
# None: not framed) and the node's distance to the slope (m; inf without a barrier).
Inset = namedtuple("Inset", "rect node why view magnification points markers slope distance")


def ground(scene):
    """What the barrier keeps the body above, in the window's words."""
    return ("the board" if scene.hand is not None else "the table" if scene.surface is not None
            else "the slope")


def focus(scene, it):
    """(k, why, d = n^T (x_k - o), framed): k sets alpha_CCD if it is < 1, else is the nearest."""
    if "barrier" not in scene.terms:
        return int(np.argmin(it.x[:, 1])), "the lowest", math.inf, False
    d = BarrierEnergy.distances(it.x, scene.n, scene.o)
    k, why = int(np.argmin(d)), f"nearest {ground(scene)}"
    if it.alpha_ccd < 1.0:
        k = int(np.argmax(BarrierEnergy.approach_rates(it.x, scene.n, scene.o, it.p)))
        why = "sets alpha_CCD"
    return k, why, float(d[k]), bool(d[k] <= SLOPE_REACH * np.hypot(*it.p[k]))


def newton_inset(scene, it, view, rect, header=0, footer=0, whole=False):
    """The Inset in `rect`: x^i, x^i + p (and the slope's foot) fill INSET_FILL of the rows between
    `header` and `footer`; its height cut to what they need (>= half its width) unless `whole`."""
    k, why, d, with_slope = focus(scene, it)
    x, p = it.x[k], it.p[k]
    points = {"x^i": x, "x^i + p": x + p, "x^i + alpha_CCD p": x + it.alpha_ccd * p,
              "x^i + alpha p": x + it.alpha * p}
    framed = [x, x + p] + ([x - d * scene.n] if with_slope else [])
    lo, hi = np.min(framed, axis=0), np.max(framed, axis=0)
    width, height = rect[2:]
    room = np.array([width, height - header - footer])          # px, across and down
    extent = (hi - lo) * view.scale                             # px, at the window's scale
    fit = min((INSET_FILL * room[extent > 0] / extent[extent > 0]).tolist(), default=MAX_ZOOM)
    magnification = draw.nice_number(min(fit, MAX_ZOOM), ZOOMS)
    if not whole:
        room[1] = min(room[1], max(0.5 * width, extent[1] * magnification / INSET_FILL))
    height = int(header + room[1] + footer)
    inset_view = draw.View(view.scale * magnification, width, height)
    middle = header + 0.5 * room[1]                             # the framed points' centre row
    inset_view.center = 0.5 * (lo + hi) + [0.0, (middle - 0.5 * height) / inset_view.scale]
    markers = {name: inset_view(point) for name, point in points.items()}
    slope = draw.slope_ends(scene, inset_view) if with_slope else None
    return Inset((*rect[:3], height), k, why, inset_view, magnification, points, markers, slope, d)


def length_text(metres):
    """A length in m, mm or micrometres (um), to 3 digits (0.9996 mm is 1 mm, not 1e+03 um)."""
    metres = float(f"{metres:.3g}")
    factor, unit = (1, "m") if metres >= 1 else (1e3, "mm") if metres >= 1e-3 else (1e6, "um")
    return f"{metres * factor:.3g} {unit}"


def iterate_lines(run, scene):
    """The figures of Algorithm 4 for the iterate on screen, and what the colours show."""
    it = run.iterate
    friction = ("lagged friction" if it.friction_update == 0 else
                f"friction update {it.friction_update}, Algorithm 5")
    verdict = "<=" if it.residual <= scene.tol else ">"
    return [f"step {run.index + 1}, Newton iteration {run.iteration} ({friction})",
            f"||p||_inf / h = {it.residual:.3g} m/s {verdict} tol = {scene.tol:g} m/s at x^i",
            f"CCD bound alpha_CCD = {it.alpha_ccd:.4g} (black ring: x^i + alpha_CCD p)",
            f"accepted alpha = alpha_CCD / 2^{it.halvings} = {it.alpha:.4g} "
            f"(green dot: x^i + alpha p)",
            "grey: x^i; blue: x^i + alpha p; red: the direction of p at each node",
            f"inset: one node and {ground(scene)} magnified together; p (red) to scale"]


def hints(scene, it, view):
    """The direction arrows (px): (tail, tip, reach), HINT of the window long, at each node whose
    |p_k| is at least HINT_FLOOR of the largest."""
    reach = min(HINT * view.size, draw.spacing(scene) * view.scale)         # px
    length = np.hypot(it.p[:, 0], it.p[:, 1])
    shown = (length > 0.0) & (length >= HINT_FLOOR * length.max())
    tail = view(it.x[shown])
    tip = tail + reach * it.p[shown] / length[shown, None] * [1.0, -1.0]    # y grows downwards
    return tail, tip, reach


def draw_iterate(pygame, surface, scene, it, view):
    """x^i grey under x^i + alpha p blue; the direction of p (too short to see) at each node."""
    draw.draw_square(pygame, surface, scene, it.x, view, draw.GREY, nodes=False)
    draw.draw_square(pygame, surface, scene, it.x_next, view)
    tail, tip, reach = hints(scene, it, view)
    heads = draw.arrow_heads(tail, tip, min(0.012 * view.size, 0.5 * reach))
    for a, b, (w1, w2) in zip(tail.tolist(), tip.tolist(), heads.tolist()):
        pygame.draw.line(surface, draw.RED, a, b, 2)
        pygame.draw.polygon(surface, draw.RED, [b, w1, w2])


def text_room(fonts, notes):
    """(header, footer): the inset's rows (px) above for its title and `notes`, below for its
    scale bar."""
    big, small = fonts
    return 8 + big.get_linesize() + len(notes) * small.get_linesize(), 12 + small.get_linesize()


def draw_inset(pygame, surface, scene, it, inset, fonts, notes):
    """The inset on its `surface`, as docs/live-demo.md lists it; title and notes on a white panel
    over the springs that reach up there, the scale bar on one below."""
    view, m = inset.view, inset.markers
    width, height = surface.get_size()
    surface.fill((255, 255, 255))
    if inset.slope is not None:
        a, b = inset.slope
        below = 2 * (width + height) * np.array([-scene.n[0], scene.n[1]])    # -n on screen, far
        pygame.draw.polygon(surface, GROUND, [a, b, b + below, a + below])
        pygame.draw.line(surface, draw.BLUE, a, b, 3)
    draw.draw_square(pygame, surface, scene, it.x, view, draw.GREY, nodes=False)
    draw.draw_square(pygame, surface, scene, it.x_next, view, nodes=False)
    tail, tip = m["x^i"], m["x^i + p"]
    r = max(3, round(0.016 * width))                        # px, the markers' radius
    pygame.draw.line(surface, draw.RED, tail, tip, 3)
    if np.hypot(*(tip - tail)) > 1.0:
        head = draw.arrow_heads(tail[None], tip[None], 3 * r)[0]
        pygame.draw.polygon(surface, draw.RED, [tip, *head])
    pygame.draw.circle(surface, draw.GREY, tail, r)
    pygame.draw.circle(surface, draw.BLACK, m["x^i + alpha_CCD p"], r + 2, 2)
    pygame.draw.circle(surface, draw.GREEN, m["x^i + alpha p"], r)
    big, small = fonts
    line, (header, footer) = small.get_linesize(), text_room(fonts, notes)
    pygame.draw.rect(surface, (255, 255, 255), (0, 0, width, header))
    pygame.draw.rect(surface, (255, 255, 255), (0, height - footer, width, footer))
    for row in (header, height - footer):
        pygame.draw.line(surface, RULE, (0, row), (width, row))
    title = f"node {inset.node}, x{inset.magnification:g}"
    surface.blit(big.render(title, True, draw.BLACK), (8, 6))
    for row, (text, color) in enumerate(notes):
        surface.blit(small.render(text, True, color), (8, 6 + big.get_linesize() + row * line))
    metres = draw.nice_number(0.3 * width / view.scale)
    bar, y = metres * view.scale, height - 6 - line // 2
    pygame.draw.line(surface, draw.BLACK, (8, y), (8 + bar, y), 3)
    surface.blit(small.render(length_text(metres), True, draw.BLACK), (14 + bar, y - line // 2))
    pygame.draw.rect(surface, draw.BLACK, surface.get_rect(), 2)


def place_inset(pygame, surface, scene, it, view, fonts, top, bottom):
    """The Inset drawn between rows `top` and `bottom`, its node circled and labelled; or None."""
    size, px = view.size, view(it.x)
    room_left, room_right = px[:, 0].min(), size - px[:, 0].max()
    width = int(min(INSET * size, max(max(room_left, room_right) - 24, MIN_INSET * size)))
    height = int(min(INSET_TALL * size, bottom - top))
    small, line = fonts[1], fonts[1].get_linesize()
    notes = inset_notes(scene, it, small, width)
    header, footer = text_room(fonts, notes)
    if height < header + footer + line:                    # no room left under the text
        return None
    rect = (12 if room_left > room_right else size - 12 - width, int(top), width, height)
    inset = newton_inset(scene, it, view, rect, header, footer)
    numbers = slope_numbers(pygame, scene, view, small)
    for _ in range(2 * len(numbers)):   # a number the border cuts: covered whole, else ended
        border = pygame.Rect(inset.rect)    # above, else passed sideways
        cut = [box for box in numbers if border.colliderect(box) and not border.contains(box)]
        if not cut:
            break
        box = min(cut, key=lambda box: box.top)
        whole = pygame.Rect(rect).contains(box.inflate(0, 4))     # the whole inset covers it
        if whole or box.top - 2 - rect[1] >= header + footer + line:
            cut_height = (box.bottom + 2 if whole else box.top - 2) - rect[1]
            inset = newton_inset(scene, it, view, (*rect[:3], cut_height), header, footer, whole)
            continue
        rect = past(rect, box, size)
        if rect is None:
            break
        notes = inset_notes(scene, it, small, rect[2])
        header, footer = text_room(fonts, notes)
        inset = newton_inset(scene, it, view, rect, header, footer)
    node = px[inset.node]
    label = small.render(f"node {inset.node}", True, draw.BLACK, (255, 255, 255))    # on white
    pygame.draw.circle(surface, draw.BLACK, node, 9, 1)
    tail, tip, _ = hints(scene, it, view)       # what the label must leave in sight
    along = np.linspace(0.0, 1.0, 5)[:, None, None]
    marks = np.vstack([view(it.x_next), px, *(tail + along * (tip - tail))])
    corner = label_corner(pygame, scene, view, px, node, label.get_size(), inset.rect,
                          (top, bottom), numbers, marks)
    surface.blit(label, corner)
    draw_inset(pygame, surface.subsurface(inset.rect), scene, it, inset, fonts, notes)
    return inset


def inset_notes(scene, it, small, width):
    """The inset's notes, (row, colour) in `width` px: why its node, where the slope is, what is
    not a spring."""
    _, why, d, framed = focus(scene, it)
    notes = [(f"({why})", draw.BLACK), ("thin lines: springs", draw.BLACK)]
    if math.isfinite(d) and not framed:
        notes.insert(1, (f"{ground(scene)}: {length_text(d)} below x^i, out of frame", draw.BLUE))
    return [(row, color) for text, color in notes
            for row in wrap.phrase_rows(small, text, width - 16)]


def past(rect, box, size):
    """`rect` (x, y, w, h) with the side whose border cuts `box` moved past it: over it where the
    window of `size` px has room, else short of it; None where neither side cuts it."""
    left, top, width, height = rect
    right = left + width
    if box.left < left < box.right:
        left = box.left - 2 if box.left >= 2 else box.right + 2
    elif box.left < right < box.right:
        right = box.right + 2 if box.right + 2 <= size else box.left - 2
    else:
        return None
    return (left, top, right - left, height)


def label_corner(pygame, scene, view, px, node, size, inset, rows, numbers, marks=()):
    """The corner of the label, `size` (w, h) px, of the node at `node` (`px`: all nodes), off it
    away from the body (the chalk's: on the board): the first clear of the `inset`, within `rows`,
    of the slope's `numbers`, of the `marks` (px: the nodes, points along their arrows) and of the
    body's hull; else the first clear of fewer of them."""
    w, h = size
    out = np.where(node >= px.mean(axis=0), 1, -1)
    if scene.hand is None:
        turns = [(out[0], out[1]), (out[0], -out[1]), (-out[0], out[1]), (-out[0], -out[1])]
        corners = [(node[0] + side * (6 + w / 2) - w / 2, node[1] + up * (14 + far + h / 2) - h / 2)
                   for far in (0, h + 4, 2 * (h + 4)) for side, up in turns]
    else:                                   # resting on the (flat) board, beside the body's nodes
        top = min(float(view(scene.o)[1]), node[1] + h / 2) - 2 - h
        level = px[(px[:, 1] >= top) & (px[:, 1] <= top + h), 0]
        right = max(level.max(initial=node[0]), node[0] + 4) + 8
        left = min(level.min(initial=node[0]), node[0] - 4) - 8 - w
        sides = (right, left) if out[0] > 0 else (left, right)
        corners = [(min(max(side, 0), view.size - w), top) for side in sides]
    labels = [pygame.FRect(corner, size) for corner in corners]
    within = pygame.FRect(0, rows[0], view.size, rows[1] - rows[0])
    clear = [label for label in labels if not label.colliderect(inset)]
    free = [label for label in clear if within.contains(label)
            and label.inflate(2 * (h // 5), 2 * (h // 5)).collidelist(numbers) < 0]
    hull = spatial.ConvexHull(px, qhull_options="QJ").equations      # n . q + c <= 0 inside
    grid = np.stack(np.meshgrid(np.linspace(0, w, 5), np.linspace(0, h, 3)), -1).reshape(-1, 2)
    off_body = [label for label in free if not (
        (label.topleft + grid) @ hull[:, :2].T + hull[:, 2] <= 0).all(axis=1).any()]
    marks = np.reshape(marks, (-1, 2))
    lo, hi = np.array([label.topleft for label in labels]) - 3, np.array(
        [label.bottomright for label in labels]) + 3
    hidden = ((marks[None] >= lo[:, None]) & (marks[None] <= hi[:, None])).all(axis=2).any(axis=1)
    in_sight = [label for label, hides in zip(labels, hidden) if not hides]
    best = [label for label in off_body if label in in_sight]
    return (best or [label for label in free if label in in_sight] or off_body or free or clear
            or labels)[0].topleft


def slope_numbers(pygame, scene, view, font):
    """The Rects of the slope's numbers: what draw.draw_slope draws with `font` and not without.
    One number's glyphs (closer than the font's height apart) give one Rect; the labelling looks
    only at the glyphs' rows and columns, a font height wider each side (what the joining reaches).
    """
    if scene.n is None:
        return []
    ink = []
    for with_font in (font, None):
        surface = pygame.Surface((view.size, view.height), 0, 32)     # a pixel a 32-bit int
        surface.fill((255, 255, 255))
        draw.draw_slope(pygame, surface, scene, view, draw.BLUE, with_font)
        rgb, white = sum(surface.get_masks()[:3]), surface.map_rgb((255, 255, 255))
        ink.append(pygame.surfarray.pixels2d(surface) & rgb != white & rgb)
    glyphs, word = ink[0] & ~ink[1], font.get_height()     # px: one number's glyphs are closer
    columns, rows = np.flatnonzero(glyphs.any(axis=1)), np.flatnonzero(glyphs.any(axis=0))
    if columns.size == 0:
        return []
    left, top = max(int(columns[0]) - word, 0), int(rows[0])
    glyphs = glyphs[left:columns[-1] + word + 1, top:rows[-1] + 1]
    numbers, _ = ndimage.label(ndimage.binary_dilation(glyphs, np.ones((word, 1), bool)))
    boxes = ndimage.find_objects(np.where(glyphs, numbers, 0))
    return [pygame.Rect(left + x.start, top + y.start, x.stop - x.start, y.stop - y.start)
            for x, y in boxes]
