"""The live window's Newton view (key n): one node of the iterate and the slope magnified together,
so that what is drawn where is what Algorithm 4 computed, at the impact (where the CCD bound cuts
the step) and in the halving demo (`--h 0.03`, step 18, README's Live demo)."""
import itertools

import numpy as np
import pytest

import BarrierEnergy
from helpers import legibility
from helpers.fakes import chalk_at, square_at
import simulator
from analysis import diagnostics
from viewer.pictures import draw, wrap
from viewer.demo import live, newton_view, window

pytestmark = pytest.mark.usefixtures("shared_stepping")   # the runs' steps: helpers/runs.py

SIZE = 652      # the window's default side on a 1024x768 projector


def paused_at(overrides, step, iteration, size=SIZE, build=simulator.build_scene, runs=None):
    """A LiveWindow of build(**overrides) paused in `step` (counted from 1, as on screen) after
    `iteration` presses of n, drawn once (the square's first step - 1 steps:
    helpers.fakes.square_at, stepped once a session, from the shared `runs` if given)."""
    if build is simulator.build_scene:
        run = square_at(step - 1, runs=runs, **overrides)
    else:
        run = live.LiveRun(build(**overrides), 1000)
        for _ in range(step - 1):
            run.step()
    pg = window.open_display()
    w = window.LiveWindow(pg, pg.display.set_mode((size, size)), run.scene, run.steps)
    w.run, w.playing = run, False
    for _ in range(iteration):
        assert w.run.newton_iteration() is None
    w.draw()
    return w


def label_corners(monkeypatch):
    """The list newton_view.label_corner's answers go to, each as it places the node's label."""
    corners, real = [], newton_view.label_corner

    def noting(*args, **kw):
        corners.append(real(*args, **kw))
        return corners[-1]
    monkeypatch.setattr(newton_view, "label_corner", noting)
    return corners


def side(a, b, q):
    """Which side of the line through pixels a and b the pixel q is on: sign((b - a) x (q - a))."""
    return np.sign((b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0]))


def drawn_notes(drawn, inset):
    """The rows drawn under the inset's title ("node k, xM") and above its scale bar's label."""
    texts = [text for text, _, _ in drawn]
    first = len(texts) - 1 - texts[::-1].index(f"node {inset.node}, x{inset.magnification:g}")
    return texts[first + 1:-1]


# the impact's steps, where the CCD bound cuts the step (alpha_CCD = 0.71, 0.59, 0.41)
IMPACT = [({}, 30, 1), ({}, 31, 1), ({}, 32, 1)]
# the halving demo, step 18: alpha = alpha_CCD / 4, / 2, / 2, / 4 in iterations 4 to 7
HALVING = [({"h": 0.03}, 18, i) for i in (4, 5, 6, 7)]


@pytest.mark.parametrize("overrides, step, iteration", IMPACT)
def test_each_marker_is_drawn_on_the_side_of_the_slope_its_point_is_on(overrides, step, iteration):
    """In the inset's pixels, x^i, x^i + p, x^i + alpha_CCD p and x^i + alpha p lie on the same side
    of the slope's drawn line as the computed points lie of the slope (d > 0 above, d < 0 below)."""
    w = paused_at(overrides, step, iteration)
    inset, scene = w.inset, w.scene
    assert inset.slope is not None
    a, b = inset.slope
    above = side(a, b, inset.view(scene.o + scene.n))          # a point 1 m above the slope
    d = {name: float(BarrierEnergy.distances(point[None], scene.n, scene.o)[0])
         for name, point in inset.points.items()}
    for name, marker in inset.markers.items():
        assert (side(a, b, marker) == above) == (d[name] > 0.0), name
    assert d["x^i"] > 0.0 and d["x^i + alpha_CCD p"] > 0.0 and d["x^i + alpha p"] > 0.0
    assert d["x^i + p"] < 0.0 and w.run.iterate.alpha_ccd < 1.0     # the full step crosses it


@pytest.mark.parametrize("overrides, step, iteration", IMPACT[:1] + HALVING)
def test_the_inset_magnifies_the_view_not_the_vectors(monkeypatch, overrides, step, iteration):
    """Every marker is its point seen through one view, `magnification` times the window's scale
    (1, 2, 3 or 5 times a power of ten, on screen in the inset's title): the distances between
    them are alpha p at that scale, and p is at least a quarter of the inset long. The node is the
    one whose CCD bound is alpha_CCD, or where the CCD does not cut the step, the one nearest the
    slope. Where the slope is too far to frame with p (the halving demo), the inset leaves it out
    and says how far it is."""
    drawn = legibility.record_text(monkeypatch)
    w = paused_at(overrides, step, iteration)
    inset, it, scene = w.inset, w.run.iterate, w.scene
    scale = inset.view.scale
    assert scale == pytest.approx(inset.magnification * w.view.scale, rel=1e-12)
    mantissa = inset.magnification / 10.0 ** np.floor(np.log10(inset.magnification))
    k = inset.node
    assert round(mantissa, 9) in newton_view.ZOOMS
    assert f"node {k}, x{inset.magnification:g}" in [text for text, _, _ in drawn]   # the title
    for name, alpha in (("x^i + p", 1.0), ("x^i + alpha_CCD p", it.alpha_ccd),
                        ("x^i + alpha p", it.alpha)):
        offset = inset.markers[name] - inset.markers["x^i"]
        assert offset == pytest.approx(alpha * it.p[k] * [scale, -scale], abs=1e-6), name
    width, height = inset.rect[2:]
    for name, marker in inset.markers.items():
        assert 0 <= marker[0] <= width and 0 <= marker[1] <= height, name
    assert np.hypot(*(inset.markers["x^i + p"] - inset.markers["x^i"])) >= min(width, height) / 4
    if it.alpha_ccd < 1.0:
        alone = BarrierEnergy.init_step_size_kernel(it.x[k:k + 1], scene.n, scene.o, it.p[k:k + 1])
        # one node's rate against all N nodes': numpy's BLAS may take another kernel for a 1-row
        # product than for N rows (and another per CPU), so the two agree to a few ulps, not bits
        assert alone == pytest.approx(it.alpha_ccd, rel=1e-12) and inset.why == "sets alpha_CCD"
    else:
        assert k == np.argmin(BarrierEnergy.distances(it.x, scene.n, scene.o))
        assert inset.why == "nearest the slope"
    if inset.slope is None:
        assert inset.distance > newton_view.SLOPE_REACH * np.hypot(*it.p[k])


@pytest.mark.parametrize("overrides, step, iteration", IMPACT[:1] + HALVING[:1])
def test_the_whole_window_carries_no_position_markers(overrides, step, iteration):
    """The green dots (x^i + alpha p) are drawn in the inset only; the window's red arrows remain,
    as the direction of p at each node."""
    import pygame
    w = paused_at(overrides, step, iteration)
    pixels = pygame.surfarray.array3d(w.screen)                     # [x, y, rgb]
    green = np.all(pixels == draw.GREEN, axis=2)
    left, top, width, height = w.inset.rect
    inside = green[left:left + width, top:top + height].sum()
    assert inside > 0 and inside == green.sum()
    red = np.all(pixels == draw.RED, axis=2)
    red[left:left + width, top:top + height] = False
    assert red.sum() > 100


def test_an_iterate_that_does_not_move_is_drawn_too():
    """At rest with no force (no gravity, no slope) Newton's first direction is p = 0: the window
    draws it (no arrows, the markers all on x^i) instead of failing."""
    w = paused_at({"slope": None, "gravity": (0.0, 0.0)}, 1, 1)
    it, inset = w.run.iterate, w.inset
    assert not it.p.any() and inset.magnification == newton_view.MAX_ZOOM
    assert all(np.array_equal(marker, inset.markers["x^i"]) for marker in inset.markers.values())


@pytest.mark.parametrize("size", [window.MIN_SIZE, 900])
def test_the_inset_fits_the_window_at_any_size(size):
    """From the smallest window to a large one: the inset lies inside the window, under the text."""
    w = paused_at({}, 30, 1, size)
    left, top, width, height = w.inset.rect
    assert 0 <= left and left + width <= size and 0 < top and top + height <= size


@pytest.mark.parametrize("overrides, step, iteration", IMPACT[:1] + HALVING[:1])
def test_the_inset_says_which_lines_are_springs_and_where_the_slope_is(monkeypatch, overrides,
                                                                       step, iteration):
    """A spring lying along the slope (in the halving demo, the mesh's bottom row crosses the whole
    inset) must not read as the slope: the inset's notes call its thin lines springs, and where the
    slope is out of frame they say how far below x^i it is; the slope, where it is in frame, is the
    line with the tint below it (3 px; springs are 1 px). The notes, wrapped, fit the inset."""
    import pygame
    drawn = legibility.record_text(monkeypatch)
    w = paused_at(overrides, step, iteration)
    inset, it, scene = w.inset, w.run.iterate, w.scene
    notes = drawn_notes(drawn, inset)
    text = " ".join(notes)
    assert text.startswith("(sets alpha_CCD) " if it.alpha_ccd < 1 else "(nearest the slope) ")
    assert text.endswith("thin lines: springs")
    d = BarrierEnergy.distances(it.x[inset.node][None], scene.n, scene.o)[0]
    out_of_frame = f"the slope: {newton_view.length_text(d)} below x^i, out of frame"
    assert (out_of_frame in text) == (inset.slope is None)
    left, top, width, height = inset.rect
    pixels = pygame.surfarray.array3d(w.screen)[left:left + width, top:top + height]
    # a few pixels of anti-aliased lines have the tint too
    tinted = np.all(pixels == newton_view.GROUND, axis=2).mean()
    assert (tinted > 0.01) == (inset.slope is not None)
    for row in notes:
        assert w.fonts[1].size(row)[0] <= width - 16 or " " not in row, row


def chalk_paused(runs, steps, drag, iteration=1, size=SIZE):
    """A LiveWindow of the chalk paused in step `steps` + 1 after `iteration` presses of n (its
    state from helpers.fakes.chalk_at, from the session's shared run `runs`: chalk_runs)."""
    run = chalk_at(steps, drag, runs=runs)
    pg = window.open_display()
    w = window.LiveWindow(pg, pg.display.set_mode((size, size)), run.scene, run.steps)
    w.run, w.playing = run, False
    for _ in range(iteration):
        assert w.run.newton_iteration() is None
    w.draw()
    return w


@pytest.mark.parametrize("steps, drag", [(235, False), (300, False), (20, True)])
def test_the_chalks_inset_magnifies_its_tip_against_the_board(monkeypatch, steps, drag,
                                                              chalk_runs):
    """For the chalk (pushed, slipping at step 236 and stuck at 301; dragged, pressed onto the
    board at step 21) the inset magnifies the tip, the node nearest the board, as computed: its
    markers are x^i + alpha p through one view (the board, about 0.9 mm below, out of frame where p
    is microns, and said so); the tip's label sits on the board beside the chalk, off its marks
    and numbers, the chalk's nodes and the inset; the direction arrows are no longer than a node
    spacing (5 mm)."""
    import pygame
    drawn = legibility.record_text(monkeypatch)
    w = chalk_paused(chalk_runs, steps, drag)
    inset, it, scene = w.inset, w.run.iterate, w.scene
    k, d = diagnostics.tip(scene, it.x)
    assert inset.node == k and inset.why == "nearest the board"
    assert inset.distance == pytest.approx(d)
    scale = inset.view.scale
    for name, alpha in (("x^i + p", 1.0), ("x^i + alpha p", it.alpha)):
        offset = inset.markers[name] - inset.markers["x^i"]
        assert offset == pytest.approx(alpha * it.p[k] * [scale, -scale], abs=1e-6), name
    assert (inset.slope is None) == (d > newton_view.SLOPE_REACH * np.hypot(*it.p[k]))
    notes = " ".join(drawn_notes(drawn, inset))
    out_of_frame = f"the board: {newton_view.length_text(d)} below x^i, out of frame"
    assert notes.startswith("(nearest the board) ")
    assert inset.slope is not None or out_of_frame in notes
    px = w.view(it.x)
    size = w.fonts[1].size(f"node {k}")
    left, top = newton_view.label_corner(pygame, scene, w.view, px, px[k], size, inset.rect,
                                         (0, w.view.height), ())
    right, low = left + size[0], top + size[1]
    assert low < w.view(scene.o)[1]                                 # above the board's line
    assert not ((px[:, 0] > left) & (px[:, 0] < right) & (px[:, 1] > top) & (px[:, 1] < low)).any()
    a, b, c, e = inset.rect
    assert right <= a or left >= a + c or low <= b or top >= b + e
    assert 0 <= left and right <= w.size
    red = np.all(pygame.surfarray.array3d(w.screen) == draw.RED, axis=2)
    red[a:a + c, b:b + e] = False
    # px from each red pixel to the nearest node: 14.5 px (a node spacing), not HINT's 23
    reach = np.hypot(*(np.argwhere(red)[:, None, :] - px[None, :, :]).T).min(axis=0)
    assert red.sum() > 100 and reach.max() <= draw.spacing(scene) * w.view.scale + 2


def phrase_break(text, first, second):
    """Do the rows `first` and `second` of `text` meet at one of wrap.BREAKS but a word's?"""
    return any(first + joined + second in text for joined in ("   ", " ")) and (
        second.startswith("(") or first.endswith((";", ",", ":")) or f"{first}   {second}" in text)


@pytest.mark.parametrize("size", [510, 600, 652, 680, 900])
@pytest.mark.parametrize("overrides, step, iteration", IMPACT[:1] + HALVING[:1])
def test_the_newton_view_keeps_its_phrases_and_labels_apart(monkeypatch, size, overrides, step,
                                                             iteration):
    """At 800x600 (510 px), 600, 652, 680 and 900 px, at the impact and in the halving demo: every
    status row and key hint fits the window and a line breaks only between phrases (at 510 px the
    caption broke into "p)" and "node"); the node's label lies off every number of the slope (it
    covered "0 m" at 510 px and "-1 m" at 680), off the inset, inside the window between the status
    and the key hints; and the inset's border cuts no number of the slope (it hides one whole or
    ends above it)."""
    corners = label_corners(monkeypatch)
    w = paused_at(overrides, step, iteration, size)
    width = size - 24
    for text in [t for t, _ in w.status_lines()] + w.help_lines():
        rows = wrap.phrase_rows(w.font, text, width)
        assert all(w.font.size(row)[0] <= width for row in rows), rows
        assert all(phrase_break(text, a, b) for a, b in itertools.pairwise(rows)), rows
    small = w.fonts[1]
    numbers = slope_glyphs(w.scene, w.view, small)
    (left, top), (w_label, h_label) = corners[-1], small.size(f"node {w.inset.node}")
    left, top = int(left), int(top)
    assert not numbers[left:left + w_label, top:top + h_label].any()
    a, b, c, d = w.inset.rect
    assert left + w_label <= a or left >= a + c or top + h_label <= b or top >= b + d
    hint_rows = [row for text in w.help_lines()
                 for row in wrap.phrase_rows(w.font, text, width)]
    hints = size - 6 - len(hint_rows) * w.font.get_linesize()        # the key hints' first row
    assert 0 <= left and left + w_label <= size and w.text_bottom <= top and top + h_label <= hints
    assert not numbers_cut(w, numbers)


def slope_glyphs(scene, view, font, clear=0.0):
    """The pixels (x, y) of the slope's numbers: what draw_slope draws with `font` and not
    without, each picture's ink read as its pixels' least channel under 255."""
    import pygame
    ink = []
    for with_font in (font, None):
        scratch = pygame.Surface((view.size, view.height))
        scratch.fill((255, 255, 255))
        draw.draw_slope(pygame, scratch, scene, view, draw.BLUE, with_font, clear)
        ink.append(pygame.surfarray.array3d(scratch).min(axis=2) < 255)
    return ink[0] & ~ink[1]


def number_boxes(numbers, font):
    """The boxes (x, y slices) of the slope's `numbers` (their pixels): glyphs closer across than
    the font's height are one number's, labelled over the whole picture."""
    from scipy import ndimage
    near = np.ones((font.get_height(), 1), bool)
    labels, _ = ndimage.label(ndimage.binary_dilation(numbers, near))
    return ndimage.find_objects(np.where(numbers, labels, 0))


def numbers_cut(w, numbers):
    """The boxes (x, y slices) of the slope's `numbers` (their pixels) the inset's border cuts."""
    a, b, c, d = w.inset.rect
    cut = []
    for x, y in number_boxes(numbers, w.fonts[1]):
        within = a <= x.start and x.stop <= a + c and b <= y.start and y.stop <= b + d
        apart = x.stop <= a or x.start >= a + c or y.stop <= b or y.start >= b + d
        cut += [] if within or apart else [(x, y)]
    return cut


@pytest.mark.parametrize("size", [510, 600, 652, 680, 900])
def test_the_inset_cuts_none_of_the_table_s_numbers(size):
    """The tablecloth paused in step 11 after one n: the inset at the window's side reached over
    half of "40 cm" (652 px; "-40 cm" on the left), too low to end above it; it now covers it
    whole or stops short of it. The numbers: what draw_slope's font adds, under the cloth's band
    (draw_frame's `clear`)."""
    w = paused_at({}, 11, 1, size, simulator.build_tablecloth_scene)
    numbers = slope_glyphs(w.scene, w.shown, w.fonts[1], draw.CLOTH_DEPTH)
    assert w.inset is not None and not numbers_cut(w, numbers)


@pytest.mark.parametrize("build, size", [(simulator.build_scene, 510),
                                         (simulator.build_tablecloth_scene, 652),
                                         (simulator.build_chalk_scene, 900)])
@pytest.mark.parametrize("shift", [-1.1, 0.0, 0.37])
def test_slope_numbers_are_the_boxes_of_the_numbers_glyphs(build, size, shift):
    """slope_numbers labels the glyphs in their rows and columns only (a font height wider): its
    Rects are the boxes of the numbers labelled over the whole picture, in the same order, with
    the view moved `shift` units along so that numbers sit at the window's edges."""
    import pygame
    scene = build()
    view, small = draw.View.of(scene, size), draw.fonts(pygame, size)[1]
    view.center = view.center + [shift * view.unit, 0.0]
    boxes = number_boxes(slope_glyphs(scene, view, small), small)
    numbers = newton_view.slope_numbers(pygame, scene, view, small)
    assert len(boxes) >= 3
    assert numbers == [pygame.Rect(x.start, y.start, x.stop - x.start, y.stop - y.start)
                       for x, y in boxes]


@pytest.mark.parametrize("size", [510, 652])
def test_the_inset_text_sits_on_a_panel_in_whole_phrases(monkeypatch, size, shared_runs):
    """Sliding at step 397 (t = 3.96 s, node 20 with the slope 9 mm below x^i, out of frame), the
    inset's notes broke into "the slope: 9.09 mm below" / "x^i," and the springs of x^i ran across
    them. Now each note breaks only between phrases, and no spring reaches the white panels of the
    title and notes above or of the scale bar below (x^i's springs drawn in a colour of their
    own)."""
    import pygame
    drawn = legibility.record_text(monkeypatch)
    monkeypatch.setattr(draw, "GREY", (1, 2, 3))
    w = paused_at({}, 397, 1, size, runs=shared_runs)     # the lecture's square's shared run
    inset = w.inset
    assert inset.slope is None and inset.why == "nearest the slope"
    notes = drawn_notes(drawn, inset)
    assert notes[0] == "(nearest the slope)" and notes[-1] == "thin lines: springs"
    d = BarrierEnergy.distances(w.run.iterate.x[inset.node][None], w.scene.n, w.scene.o)[0]
    text, rows = f"the slope: {newton_view.length_text(d)} below x^i, out of frame", notes[1:-1]
    assert " ".join(rows) == text
    assert all(phrase_break(text, a, b) for a, b in itertools.pairwise(rows)), rows
    header, footer = newton_view.text_room(w.fonts, notes)
    left, top, width, height = inset.rect
    springs = np.all(pygame.surfarray.array3d(w.screen) == (1, 2, 3), axis=2)
    inside = springs[left + 2:left + width - 2, top + 2:top + height - 2]     # within the border
    assert inside.any()                                         # x^i's springs, in the drawing
    assert not inside[:, :header - 2].any() and not inside[:, height - footer - 2:].any()


def test_lengths_are_said_in_the_unit_their_3_digits_round_to_and_the_table_is_the_table():
    """0.9996 mm rounded to 3 digits is 1 mm: it was '1e+03 um' (a tester's tablecloth inset),
    whose ground the window called 'the slope'."""
    assert [newton_view.length_text(d) for d in (0.9996e-3, 0.9994e-3, 0.99951, 2.5)] == [
        "1 mm", "999 um", "1 m", "2.5 m"]
    assert newton_view.ground(simulator.build_tablecloth_scene()) == "the table"
    assert newton_view.ground(simulator.build_scene()) == "the slope"


@pytest.mark.parametrize("size", [510, 600, 652, 680, 850, 900])
def test_the_node_s_label_leaves_every_node_and_arrow_in_sight(monkeypatch, size):
    """Paused in step 30 after 5 presses of n (the node nearest the slope at the square's corner,
    the inset beside it, "0 m" under it), the label "node 0" lay over the square, hiding a node and
    the direction arrow it labels (850 px, a 1000-px-high display). It now covers no node of x^i
    or x^i + alpha p and no point of any direction arrow (newton_view.hints, as draw_iterate draws
    them), and lies within a few label heights of its node."""
    corners = label_corners(monkeypatch)
    w = paused_at({}, 30, 5, size)
    it, view = w.run.iterate, w.shown
    (left, top), (width, height) = corners[-1], w.fonts[1].size(f"node {w.inset.node}")
    tail, tip, _ = newton_view.hints(w.scene, it, view)
    along = np.linspace(0.0, 1.0, 9)[:, None, None]
    seen = np.vstack([view(it.x), view(it.x_next), *(tail + along * (tip - tail))])
    inside = ((seen >= [left, top]) & (seen <= [left + width, top + height])).all(axis=1)
    assert not inside.any(), seen[inside]
    node = view(it.x_next[w.inset.node])
    assert np.hypot(left + width / 2 - node[0], top + height / 2 - node[1]) < 5 * height
