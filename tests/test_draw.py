"""viewer/draw.py's drawing helpers, one copy each for the frames, plots.png, summary.png and the
window: round numbers (nice_number), arrowheads (arrow_heads), text wrapping (wrap); and the chalk's
marks (viewer/marks.py) as the frames draw them: their stretches, colours, the strip magnifying them."""
import numpy as np
import pytest

import simulator
from helpers import legibility
from helpers.fakes import chalk_at
from viewer import diagnostics, draw, frames, marks


@pytest.mark.parametrize("value, down, up", [(0.3, 0.2, 0.5), (7.0, 5.0, 10.0), (1.0, 1.0, 1.0), (2e-5, 2e-5, 2e-5),
                                             (1234.0, 1000.0, 2000.0), (0.0049, 0.002, 0.005)])
def test_nice_number_is_1_2_or_5_times_a_power_of_ten(value, down, up):
    assert draw.nice_number(value) == pytest.approx(down, rel=1e-12)
    assert draw.nice_number(value, up=True) == pytest.approx(up, rel=1e-12)


def test_nice_number_takes_other_steps():
    """The Newton view's zooms (1, 2, 3 or 5 times a power of ten) and summary.png's two digits."""
    assert [draw.nice_number(v, (1, 2, 3, 5)) for v in (4.0, 31.0, 7000.0)] == [3.0, 30.0, 5000.0]
    assert [draw.nice_number(v, range(10, 100)) for v in (38.79, 0.5432, 99.99, 1234.0)] == [38.0, 0.54, 99.0, 1200.0]


def test_arrow_heads_sit_behind_the_tip_on_either_side():
    tail, head = np.array([[0.0, 0.0], [5.0, 5.0]]), np.array([[10.0, 0.0], [5.0, 5.0]])
    corners = draw.arrow_heads(tail, head, 4.0)
    assert corners.shape == (2, 2, 2)
    assert sorted(corners[0].tolist()) == [[6.0, -2.0], [6.0, 2.0]]
    assert np.array_equal(corners[1], [[5.0, 5.0], [5.0, 5.0]])          # an arrow of no length: its tip


def test_wrap_breaks_at_spaces_within_the_width():
    class Font:                                                         # 10 px a character
        def size(self, text):
            return 10 * len(text), 12
    assert draw.wrap(Font(), "space: play   r: restart", 120) == ["space: play", "r: restart"]
    assert draw.wrap(Font(), "a_very_long_word fits", 50) == ["a_very_long_word", "fits"]


def test_the_arrows_scale_coarsens_at_the_impact_so_no_arrow_is_longer_than_arrow_fit(monkeypatch):
    """The default run's first 60 steps drawn as frames.FrameWriter draws them (one view): no arrow
    (normal, or friction drawn FRICTION_ZOOM longer) is longer than ARROW_FIT m, 3/4 of the square's
    side (at the impact, steps 31 to 34, they reached 1.39 m at 1 m per weight, through the square);
    the scale is 1 m per weight until an arrow would be longer, then the smallest of 2, 5, 10, ...
    times it that fits, kept from then on; the legend says the scale drawn; and the red ink of the
    normal forces lies within ARROW_FIT m (in pixels) of the contact nodes."""
    pygame = draw.load_pygame()
    drawn = legibility.record_text(monkeypatch)
    scene = simulator.build_scene()
    view, fonts = draw.View.of(scene), draw.fonts(pygame)
    per_weight = draw.newton_per_metre(scene)                 # N per m of arrow at factor 1
    weight = float(scene.m.sum() * np.hypot(*scene.g))
    assert per_weight == pytest.approx(weight / draw.ARROW_PER_WEIGHT)
    factors, longest_at_1 = [], []
    for record in simulator.simulate(scene, 60):
        run = frames.frame_run(scene, record.x, record.report, "mu = 0.11", draw.BLUE, True)
        view.follow(diagnostics.centre_of_mass(scene, record.x)[None])
        start = len(drawn)
        surface, top = draw.draw_frame(pygame, [run], record.t, view, fonts, per_weight)
        factor = view.arrow_factor
        friction = draw.FRICTION_ZOOM * np.hypot(*run["friction"].T).max(initial=0.0)
        longest = max(np.hypot(*run["normal"].T).max(initial=0.0), friction) / per_weight   # m, x1
        assert longest / factor <= draw.ARROW_FIT
        assert draw.nice_number(factor) == factor and factor >= max(factors, default=1.0)
        if factor > max(factors, default=1.0):              # raised here: the smallest that fits
            assert longest / draw.nice_number(0.99 * factor) > draw.ARROW_FIT
        words = "the weight M|g|" if factor == 1 else f"{factor:g} x the weight M|g|"
        scale = f"{draw.ARROW_PER_WEIGHT:g} m of arrow = {factor * weight:.5g} N ({words})"
        assert scale in [text for text, _, _ in drawn[start:]]
        factors.append(factor)
        longest_at_1.append(longest)
        pixels = pygame.surfarray.array3d(surface)[:, top:]
        red = np.argwhere(np.all(pixels == draw.NORMAL_COLOR, axis=2)) + [0, top]
        nodes = view(record.x[np.hypot(*run["normal"].T) > 0.0])
        if len(red):
            reach = np.hypot(*(red[:, None, :] - nodes[None, :, :]).T).min(axis=0)   # px to a node
            assert reach.max() <= draw.ARROW_FIT * view.scale + 2
    assert max(longest_at_1) > 1.3 and factors[0] == 1.0 < factors[-1]       # (measured: 1.39, x2)


# ------------------------------------------------------------------------------------------------
# The chalk's marks (viewer/marks.py): at the picture's scale, and in the strip magnified about the tip
# ------------------------------------------------------------------------------------------------

def chalk_frame(steps, drag=False, size=draw.RESOLUTION, reserve=(0, 0)):
    """The chalk's frame after `steps` steps (helpers.fakes.chalk_at) as frames.FrameWriter draws it (at
    `size` px, the view following the centre of mass): its pixels [x, y, rgb], the run drawn, the view,
    the fonts, the first row under the legends and the Strip marks.layout gives for it."""
    pygame = draw.load_pygame()
    live_run = chalk_at(steps, drag)
    scene = live_run.scene
    view, fonts = draw.View.of(scene, size), draw.fonts(pygame, size)
    view.follow(diagnostics.centre_of_mass(scene, live_run.x)[None])
    run = frames.frame_run(scene, live_run.x, live_run.report, "chalk", draw.BLUE, True)
    run["marks"] = live_run.marks
    surface, top = draw.draw_frame(pygame, [run], live_run.t, view, fonts, draw.newton_per_metre(scene), reserve)
    below = draw.draw_slope(pygame, pygame.Surface((size, size)), scene, view, draw.BLUE, fonts[1])
    strip = marks.layout([run], live_run.t, view, fonts[1], top + reserve[0], size - reserve[1], below)
    return pygame.surfarray.array3d(surface), run, view, fonts, top, strip


def runs_of(marks_list):
    """The runs of consecutive marks of one kind, straight from the marks list: (stuck, first, last index)."""
    flags = [stuck for _, stuck in marks_list]
    cuts = [0] + [i for i in range(1, len(flags)) if flags[i] != flags[i - 1]] + [len(flags)]
    return [(flags[a], a, b - 1) for a, b in zip(cuts[:-1], cuts[1:])]


def longest_run(mask):
    """The longest run of True along the first axis of a 2-d mask (columns across, rows down), in any row."""
    best = 0
    for row in mask.T:
        edges = np.flatnonzero(np.diff(np.r_[0, row.astype(int), 0]))
        best = max([best] + (edges[1::2] - edges[::2]).tolist())
    return best


def in_strip(pixels, strip, columns, row):
    """The colours at strip columns (px from its left) on a row (px from the top of its first run's row)."""
    left, top = strip.rect[:2]
    return [tuple(pixels[left + round(c), top + strip.rows[0][0] + row]) for c in columns]


def test_stretches_are_runs_of_one_kind_and_slipping_reaches_the_stuck_marks_around_it():
    """Two stuck marks at 0, slipping at 0.1 and 0.3 mm, stuck at 0.4 mm twice, slipping at 0.5 mm: the
    stuck stretches are where their marks are; the first slipping one runs from the stuck 0 to the stuck
    0.4 mm (the tip moved between those states), the last from 0.4 mm to its own mark."""
    marks_list = [(0.0, True), (0.0, True), (1e-4, False), (3e-4, False), (4e-4, True), (4e-4, True), (5e-4, False)]
    lo, hi, stuck = marks.stretches(marks_list)
    assert stuck.tolist() == [True, False, True, False]
    assert np.allclose(lo, [0.0, 0.0, 4e-4, 4e-4]) and np.allclose(hi, [0.0, 4e-4, 4e-4, 5e-4])
    assert [len(a) for a in marks.stretches([])] == [0, 0, 0]


def test_the_marks_colours_read_on_white_in_grey_and_stay_apart_from_the_others():
    """Stuck and slipping: each at least 3:1 against white (WCAG's contrast for graphics, 1.4.11), 3:1
    from each other in luminance (so a grey-scale print keeps them apart), at least 39 in CIELAB from
    white, every run's colour, the forces' and the hand's, and in the frames' PALETTE (drawn exactly)."""
    stuck, slipping = marks.STUCK_COLOR, marks.SLIP_COLOR
    assert min(legibility.contrast_ratio(stuck), legibility.contrast_ratio(slipping)) >= 3.0
    assert legibility.contrast_ratio(stuck, slipping) >= 3.0
    others = draw.RUN_COLORS + [draw.NORMAL_COLOR, draw.FRICTION_COLOR, draw.HAND_COLOR, legibility.WHITE]
    assert min(legibility.delta_e(c, o) for c in (stuck, slipping) for o in others + [slipping]
               if c != o) >= 39
    palette = {tuple(int(v) for v in c) for c in draw.PALETTE}
    assert {stuck, slipping} <= palette


def test_the_strip_is_magnified_x8_about_the_tip_and_puts_each_mark_where_that_scale_does():
    """The pushed chalk at 1 s (about 8 slips): the frame's strip, under the board, says x8 and is 8
    times the frame's 4000 px/m (draw.SCALE 200 px/m, times draw.zoom 20 for the 9 cm chalk): 32 px a
    mm, its scale bar of 1 mm 32 px of ink. It is magnified about the tip's
    column (the tip straight under the tip), and every stuck run of the marks list (taken from it here)
    lands in STUCK_COLOR at tip column + 32000 px/m (s - s_tip) of its mean position s, below the
    slipping band's depth; halfway between two stuck runs the band is SLIP_COLOR, and white under it."""
    pixels, run, view, fonts, top, strip = chalk_frame(1000)
    assert view.scale == pytest.approx(4000.0) and strip.magnification == 8 and strip.scale == pytest.approx(32000.0)
    assert strip.where == "below the board" and marks.title() == "the tip's marks, x8"
    k, _ = diagnostics.tip(run["scene"], run["x"])
    assert strip.s_tip == run["x"][k, 0] and strip.tip_column == pytest.approx(view(run["x"][k])[0] - strip.rect[0])
    left, y0 = strip.rect[:2]
    header = np.all(pixels[left + 2:left + strip.rect[2] - 2, y0 + 2:y0 + strip.rows[0][0]] == (0, 0, 0), axis=2)
    assert longest_run(header) == 32                # the bar's ink, its end ticks within it
    s = np.array([m[0] for m in run["marks"]])
    stuck_runs = [s[a:b + 1].mean() for stuck, a, b in runs_of(run["marks"]) if stuck]
    assert len(stuck_runs) >= 8
    board = strip.board
    shown = [c for c in strip.column(stuck_runs) if 0 <= c < strip.rect[2]]
    assert len(shown) >= 8
    assert set(in_strip(pixels, strip, shown, board + 2 + strip.band + 1)) == {marks.STUCK_COLOR}
    middles = [(a + b) / 2 for a, b in zip(shown[:-1], shown[1:])]
    assert set(in_strip(pixels, strip, middles, board + 2)) == {marks.SLIP_COLOR}
    assert set(in_strip(pixels, strip, middles, board + 2 + strip.band - 1)) == {marks.SLIP_COLOR}
    assert set(in_strip(pixels, strip, middles, board + 2 + strip.band)) == {legibility.WHITE}


def test_dragged_the_strip_shows_one_continuous_line_pushed_a_dashed_one():
    """At the same x8, the band under the strip's board at 1 s. Dragged, the marks list holds the first
    touch (one mark, landing), one stuck run (the press) and then one slipping run: from the stuck tick
    where the line began (at 0, 7 mm = 224 px behind the tip) to the tip every column is slipping.
    Pushed, from its first mark to the tip, the slipping band is cut by a stuck tick at each stuck run
    of the marks list (all in view), 1.07 mm = 34 px apart (the slip of the marks list: its stuck runs' mean
    positions, differenced)."""
    for drag in (True, False):
        pixels, run, view, fonts, top, strip = chalk_frame(1000, drag)
        s = np.array([m[0] for m in run["marks"]])
        kinds = runs_of(run["marks"])
        stuck_at = [s[a:b + 1].mean() for stuck, a, b in kinds if stuck]
        if drag:
            assert [stuck for stuck, _, _ in kinds] == [False, True, False] and kinds[0][1:] == (0, 0)
            start = float(strip.column(stuck_at[0]))
            assert 2 < start < strip.tip_column - 200
            columns = range(round(start) + strip.tick, round(strip.tip_column))
            assert set(in_strip(pixels, strip, columns, strip.board + 2)) == {marks.SLIP_COLOR}
            assert in_strip(pixels, strip, [start], strip.board + 2 + strip.band + 1) == [marks.STUCK_COLOR]
        else:
            first = float(strip.column(s.min()))
            assert first > 2                                    # every mark in view, 7.5 mm = 240 px behind the tip
            columns = range(round(first), round(strip.tip_column))
            assert set(in_strip(pixels, strip, columns, strip.board + 2)) == {marks.SLIP_COLOR, marks.STUCK_COLOR}
            deep = in_strip(pixels, strip, range(round(first) - strip.tick, round(strip.tip_column) + strip.tick),
                            strip.board + 2 + strip.band + 1)
            ticks = np.flatnonzero(np.diff(np.r_[0, [c == marks.STUCK_COLOR for c in deep], 0]) == 1)
            assert len(ticks) == len(stuck_at) >= 8
            assert np.diff(stuck_at[-4:]) * 1e3 == pytest.approx(1.07, abs=0.02)
            assert np.diff(ticks) == pytest.approx(32000 * np.diff(stuck_at), abs=1.5)


def arcminutes(px, size):
    """What `px` pixels of a picture `size` px tall subtend from 4 screen heights, where the window fills
    0.85 of the screen (docs/live-demo.md, "Readable"), in arcminutes."""
    return px / size * 0.85 / 4 * 180 / np.pi * 60


@pytest.mark.parametrize("size", [600, 652, draw.RESOLUTION])
def test_the_strips_marks_are_thick_enough_to_see_from_the_back_of_the_room(size):
    """From 4 screen heights a stuck tick is at least 3 arcminutes wide (the stroke of a capital of the
    text's 16 arcminutes is about a fifth of it) and the slipping band at least 8 deep (half a capital),
    measured in the strip's pixels: 3 px and 9 px at 652 px, 4 and 13 in the 900-px frames."""
    pixels, run, view, fonts, top, strip = chalk_frame(1000, size=size)
    deep = [c == marks.STUCK_COLOR for c in in_strip(pixels, strip, range(2, strip.rect[2] - 2),
                                                        strip.board + 2 + strip.band + 1)]
    edges = np.flatnonzero(np.diff(np.r_[0, deep, 0]))
    assert len(edges) >= 8 and arcminutes((edges[1::2] - edges[::2]).min(), size) >= 3
    s = np.array([m[0] for m in run["marks"]])
    stuck_at = [s[a:b + 1].mean() for stuck, a, b in runs_of(run["marks"]) if stuck]
    slipping = round(float(strip.column(0.5 * (stuck_at[-2] + stuck_at[-3]))))      # between two stuck runs
    left, top_row = strip.rect[0], strip.rect[1] + strip.rows[0][0]
    down = [tuple(c) for c in pixels[left + slipping, top_row:top_row + strip.rows[0][1]]]      # the column, down its row
    assert arcminutes(down.count(marks.SLIP_COLOR), size) >= 8


def test_the_frames_strip_covers_neither_the_chalk_the_legends_nor_the_boards_numbers(monkeypatch):
    """In the frames, pushed and dragged, early and late: the strip lies across the frame under the board's
    numbers (their lowest ink), inside the frame, clear of the chalk and its hand's targets; every text it
    draws (its title, its scale bar's length) has capitals of at least draw.MIN_CAP_HEIGHT of the frame
    and contrast at least 4.5:1 on white."""
    drawn = legibility.record_text(monkeypatch)
    for steps, drag in ((240, False), (1000, False), (400, True), (1000, True)):
        pixels, run, view, fonts, top, strip = chalk_frame(steps, drag)
        left, y0, width, height = strip.rect
        numbers = np.flatnonzero((pixels[:, int(view(run["scene"].o)[1]) + 2:y0] == draw.BLUE).all(axis=2).any(axis=0))
        assert strip.where == "below the board" and top < y0 and numbers.size and y0 > int(view(run["scene"].o)[1]) + 2 + numbers.max()
        assert 0 <= left and left + width <= draw.RESOLUTION and y0 + height <= draw.RESOLUTION
        body = view(np.vstack([run["x"], run["scene"].hand.targets(chalk_at(steps, drag).t)]))
        assert body[:, 1].max() < y0
        assert np.all(pixels[left, y0:y0 + height] == 0) and np.all(pixels[left + width - 1, y0:y0 + height] == 0)
    texts = {text for text, _, _ in drawn}
    assert {marks.title(), marks.bar_label(), "marks of the tip: slipping"} <= texts
    assert min(cap for _, cap, _ in drawn) >= draw.MIN_CAP_HEIGHT * draw.RESOLUTION
    assert min(legibility.contrast_ratio(color) for _, _, color in drawn) >= 4.5


def test_the_squares_frames_have_no_marks_and_no_strip(monkeypatch):
    """The square has no marks: draw_frame never reaches viewer.marks for it (the calls would fail here),
    so its frames are those it drew before the strip, pixel for pixel whatever room is reserved."""
    pygame = draw.load_pygame()
    scene = simulator.build_scene()
    runs = [frames.frame_run(scene, scene.x0, None, "mu = 0.11", draw.BLUE, True)]
    view, fonts = draw.View.of(scene), draw.fonts(pygame)
    kept = [pygame.surfarray.array3d(draw.draw_frame(pygame, runs, 0.0, view, fonts, draw.newton_per_metre(scene),
                                                       reserve)[0]) for reserve in ((0, 0), None, (100, 100))]

    def never(*args, **kw):
        raise AssertionError("the square drew marks")
    for name in ("draw_marks", "place_strip", "layout", "draw_strip", "draw_span"):
        monkeypatch.setattr(marks, name, never)
    runs[0]["marks"] = None                                  # as frames.FrameWriter gives a run without a hand
    again = pygame.surfarray.array3d(draw.draw_frame(pygame, runs, 0.0, view, fonts, draw.newton_per_metre(scene))[0])
    assert all(np.array_equal(again, k) for k in kept)
    assert not np.all(again == marks.STUCK_COLOR, axis=2).any() and not np.all(again == marks.SLIP_COLOR, axis=2).any()


def test_a_comparison_has_a_row_per_run_on_one_scale():
    """Two runs (the pushed chalk at 1 s, and the same with only its first 500 marks, in the second run's
    colour): the strip has a row each, one scale (the first run's tip at the same column), the run's
    colour at each row's left end, and each row's marks its own: the second's band ends at its last mark."""
    pygame = draw.load_pygame()
    live_run = chalk_at(1000)
    scene = live_run.scene
    view, fonts = draw.View.of(scene), draw.fonts(pygame)
    runs = [dict(frames.frame_run(scene, live_run.x, live_run.report, f"run {k}", draw.run_color(k), True),
                 marks=live_run.marks[:n]) for k, n in ((0, 1000), (1, 500))]
    surface, top = draw.draw_frame(pygame, runs, live_run.t, view, fonts, draw.newton_per_metre(scene))
    pixels = pygame.surfarray.array3d(surface)
    below = draw.draw_slope(pygame, pygame.Surface(surface.get_size()), scene, view, draw.BLUE, fonts[1])
    strip = marks.layout(runs, live_run.t, view, fonts[1], top, draw.RESOLUTION, below)
    assert len(strip.rows) == 2 and strip.rows[1][0] == strip.rows[0][0] + strip.rows[0][1]
    left, y0 = strip.rect[:2]
    for run, (row_top, row) in zip(runs, strip.rows):
        assert tuple(pixels[left + 3, y0 + row_top + row // 2]) == run["color"]
        end = float(strip.column(run["marks"][-1][0]))
        band = y0 + row_top + strip.board + 2
        assert tuple(pixels[left + round(end) - strip.tick, band]) in (marks.SLIP_COLOR, marks.STUCK_COLOR)
        assert tuple(pixels[left + round(end) + strip.tick, band]) == legibility.WHITE
