"""The chalk's mark (viewer/pictures/marks.py) as the frames draw it: grey under the board at the
frame's scale and in the strip magnified x8 about the tip, each pixel column the deposit of the
board under it (wear.Deposit.shade, black at the run's darkest bin); where the strip goes; legible
from the back of the room. What the mark is (Archard's law): tests/analysis/test_wear.py."""
import numpy as np
import pytest
from helpers import legibility
from helpers.fakes import chalk_at

import simulator
from analysis import diagnostics, wear
from viewer.pictures import draw, frames, marks


def chalk_frame(runs, steps, drag=False, size=draw.RESOLUTION, reserve=(0, 0)):
    """The chalk's frame after `steps` steps (helpers.fakes.chalk_at, from the session's shared
    run `runs`, the chalk_runs fixture) as frames.FrameWriter draws it
    (at `size` px, the view following the centre of mass): its pixels [x, y, rgb], the run drawn,
    the view, the fonts, the first row under the legends and the Strip marks.layout gives for it
    (reserve None: no strip, and None)."""
    pygame = draw.load_pygame()
    live_run = chalk_at(steps, drag, runs=runs)
    scene = live_run.scene
    view, fonts = draw.View.of(scene, size), draw.fonts(pygame, size)
    view.follow(diagnostics.centre_of_mass(scene, live_run.x)[None])
    run = frames.frame_run(scene, live_run.x, live_run.report, "chalk", draw.BLUE, True)
    run["marks"] = live_run.marks
    forces = draw.newton_per_metre(scene)
    surface, top = draw.draw_frame(pygame, [run], live_run.t, view, fonts, forces, reserve)
    below = draw.draw_slope(pygame, pygame.Surface((size, size)), scene, view, draw.BLUE, fonts[1])
    strip = None if reserve is None else marks.layout([run], live_run.t, view, fonts[1],
                                                      top + reserve[0], size - reserve[1], below)
    return pygame.surfarray.array3d(surface), run, view, fonts, top, strip


def band(pixels, strip, row_index=0):
    """The strip's mark along its middle row: the grey of each of the strip's columns."""
    left, top = strip.rect[:2]
    y = top + strip.rows[row_index][0] + strip.board + 2 + strip.band // 2
    return pixels[left:left + strip.rect[2], y]


def expected(deposit, columns, s_of):
    """The greys marks.paint_mark gives the columns (px) of a picture whose column c shows the board
    from s_of(c) to s_of(c + 1)."""
    return marks.greys(deposit.shade(s_of(columns), s_of(columns + 1)))


def longest_run(mask):
    """The longest run of True along the first axis of a 2-d mask (columns across, rows down), in
    any row."""
    best = 0
    for row in mask.T:
        edges = np.flatnonzero(np.diff(np.r_[0, row.astype(int), 0]))
        best = max([best] + (edges[1::2] - edges[::2]).tolist())
    return best


def test_the_strip_is_magnified_x8_about_the_tip_and_each_column_shows_the_deposit_under_it(
        chalk_runs):
    """The pushed chalk at 1 s: the frame's strip, under the board, says x8 and is 8 times the
    frame's 4000 px/m (draw.SCALE 200 px/m, times draw.zoom 20 for the 9 cm chalk): 32 px a mm, its
    scale bar of 1 mm 32 px of ink, a bin of 0.1 mm 3.2 px. It is magnified about the tip's column
    (the tip straight under the tip); under its board every column over the mark is the grey of the
    deposit of the board it spans (black at the darkest bin), and white beyond the mark."""
    pixels, run, view, _, _, strip = chalk_frame(chalk_runs, 1000)
    assert view.scale == pytest.approx(4000.0) and marks.MAGNIFICATION == 8
    assert strip.scale == pytest.approx(32000.0)
    assert strip.where == "below the board" and marks.title() == "the chalk's mark, x8"
    k, _ = diagnostics.tip(run["scene"], run["x"])
    assert strip.s_tip == run["x"][k, 0]
    assert strip.tip_column == pytest.approx(view(run["x"][k])[0] - strip.rect[0])
    left, y0 = strip.rect[:2]
    header = pixels[left + 2:left + strip.rect[2] - 2, y0 + 2:y0 + strip.rows[0][0]]
    header = np.all(header == (0, 0, 0), axis=2)
    assert longest_run(header) == 32                # the bar's ink, its end ticks within it
    deposit = run["marks"]
    lo, hi = (float(strip.column(s)) for s in deposit.span())
    assert 2 < lo < hi < strip.rect[2] - 2          # the whole mark in view
    inside = np.arange(int(np.floor(lo)), int(np.ceil(hi)))
    shown = band(pixels, strip)
    assert np.array_equal(shown[inside], expected(deposit, inside, strip.board_at))
    assert (shown[2:int(np.floor(lo))] == 255).all()
    assert (shown[int(np.ceil(hi)):strip.rect[2] - 2] == 255).all()
    assert shown[inside].min() == 0                 # the darkest bin: black


def test_dragged_one_even_grey_line_pushed_dashes_a_slip_apart_each_fading_from_its_start(
        chalk_runs):
    """At x8, the strip's mark at 1 s. Dragged: from the first whole bin after the press's spot to
    the bin before the tip one even grey, within 8 levels of 255 (its bins within 3 %). Pushed: a
    dash per wear.dashes in view, 1.06 mm = 34 px apart (a slip); at each the grey jumps from light
    (half of black or less in the bin before it) to nearly black within a bin or two, then lightens
    column by column to its faintest (a fifth of black or less), just before the next."""
    for drag in (True, False):
        pixels, run, _, _, _, strip = chalk_frame(chalk_runs, 1000, drag)
        deposit, shown = run["marks"], band(pixels, strip)[:, 0].astype(int)
        def middle(i, first=deposit.first, strip=strip):
            """The strip's column of the middle of the mark's bin i."""
            return round(float(strip.column((first + i + 0.5) * wear.BIN)))
        if drag:
            line = shown[middle(2):middle(len(deposit.values) - 2)]
            assert len(line) > 200 and np.ptp(line) <= 8 and line.max() < 200
            continue
        v = deposit.values
        dashes = wear.dashes(v)
        columns = np.array([middle(a) for a, _, _ in dashes])
        assert len(dashes) >= 6 and np.diff(columns) == pytest.approx(34, abs=4)
        for (a, _, _), b in zip(dashes, [d[0] for d in dashes[1:]] + [len(v)]):
            dark, faint = middle(a + int(np.argmax(v[a:b]))), middle(a + int(np.argmin(v[a:b])))
            assert shown[middle(a - 1)] >= 255 * (1 - 1 / 2) and shown[dark] <= 40   # faint, dark
            assert shown[faint] >= 255 * (1 - 1 / 5)
            assert (np.diff(shown[dark:faint + 1]) >= 0).all()                        # lightening


def test_the_frame_shows_the_mark_at_its_own_scale_under_the_board(chalk_runs):
    """Under the frame's board, from 2 rows below its line, MARK_HEIGHT (of the lecture's scale)
    deep: each column over the mark the grey of the deposit of the board it spans at the frame's
    4000 px/m (a column: 2.5 bins), the mark about the hand's 18 mm (72 px) wide after 2 s pushed
    (drawn without the strip, whose box around the board it magnifies would cross it); the legend
    names it (Archard) and says what black is (none yet before the tip slides)."""
    pixels, run, view, _, _, _ = chalk_frame(chalk_runs, 2000, reserve=None)
    scene, deposit = run["scene"], run["marks"]
    origin = float(view(marks.board_point(scene, 0.0))[0, 0])
    row = round(float(view(marks.board_point(scene, 0.0))[0, 1])) + 2
    depth = round(marks.MARK_HEIGHT * view.unit * view.scale)
    lo, hi = (origin + view.scale * s for s in deposit.span())
    inside = np.arange(int(np.floor(lo)), int(np.ceil(hi)))
    assert 68 <= len(inside) <= 77 and depth >= 10
    want = expected(deposit, inside, lambda c: (c - origin) / view.scale)
    for y in (row, row + depth - 1):
        assert np.array_equal(pixels[inside, y], want)
    black = f"black: {deposit.darkest():.3g} N m per 0.1 mm, the darkest"
    name = "the chalk's mark: lambda x slid length (Archard)"
    assert marks.legend([run]) == [(marks.SWATCH, name), ((255, 255, 255), black)]
    assert marks.legend([{"marks": wear.Deposit()}])[1] == ((255, 255, 255), "black: none yet")


def arcminutes(px, size):
    """What `px` pixels of a picture `size` px tall subtend from 4 screen heights, where the window
    fills 0.85 of the screen (docs/live-demo.md, "Readable"), in arcminutes."""
    return px / size * 0.85 / 4 * 180 / np.pi * 60


@pytest.mark.parametrize("size", [600, 652, draw.RESOLUTION])
def test_the_strips_mark_is_big_and_dark_enough_to_see_from_the_back_of_the_room(
        size, chalk_runs):
    """From 4 screen heights the strip's mark is at least 8 arcminutes deep (half a capital of the
    text's 16) and a dash (1.06 mm at x8) at least 16 wide; a dash's darkest grey stands 3:1 or more
    (WCAG's contrast for graphics) against white and against its faintest."""
    _, run, _, _, _, strip = chalk_frame(chalk_runs, 1000, size=size)
    assert arcminutes(strip.band, size) >= 8
    assert arcminutes(1.06e-3 * strip.scale, size) >= 16
    dashes = wear.dashes(run["marks"].values)
    darkest, faintest = (tuple(int(c) for c in marks.greys([f / run["marks"].darkest()])[0])
                         for f in (max(d for _, d, _ in dashes), min(f for _, _, f in dashes)))
    assert legibility.contrast_ratio(darkest) >= 3
    assert legibility.contrast_ratio(darkest, faintest) >= 3


def test_the_frames_strip_covers_neither_the_chalk_the_legends_nor_the_boards_numbers(
        monkeypatch, chalk_runs):
    """In the frames, pushed and dragged, early and late: the strip lies across the frame under the
    board's numbers (their lowest ink), inside the frame, clear of the chalk and its hand's targets;
    every text it draws (its title, its scale bar's length) has capitals of at least
    draw.MIN_CAP_HEIGHT of the frame and contrast at least 4.5:1 on white."""
    drawn = legibility.record_text(monkeypatch)
    for steps, drag in ((240, False), (1000, False), (400, True), (1000, True)):
        pixels, run, view, _, top, strip = chalk_frame(chalk_runs, steps, drag)
        left, y0, width, height = strip.rect
        board = int(view(run["scene"].o)[1]) + 2
        numbers = np.flatnonzero((pixels[:, board:y0] == draw.BLUE).all(axis=2).any(axis=0))
        assert strip.where == "below the board" and top < y0 and numbers.size
        assert y0 > board + numbers.max()
        assert 0 <= left and left + width <= draw.RESOLUTION and y0 + height <= draw.RESOLUTION
        body = view(np.vstack([run["x"], run["scene"].hand.targets(chalk_at(steps, drag).t)]))
        assert body[:, 1].max() < y0
        assert np.all(pixels[left, y0:y0 + height] == 0)
        assert np.all(pixels[left + width - 1, y0:y0 + height] == 0)
    texts = {text for text, _, _ in drawn}
    assert {marks.title(), marks.bar_label(), marks.legend([run])[0][1]} <= texts
    assert min(cap for _, cap, _ in drawn) >= draw.MIN_CAP_HEIGHT * draw.RESOLUTION
    assert min(legibility.contrast_ratio(color) for _, _, color in drawn) >= 4.5


def test_the_squares_frames_have_no_marks_and_no_strip(monkeypatch):
    """The square has no mark: draw_frame never reaches viewer.pictures.marks for it (the calls
    would fail here), so its frames are those it drew before the strip, pixel for pixel whatever
    room is reserved."""
    pygame = draw.load_pygame()
    scene = simulator.build_scene()
    runs = [frames.frame_run(scene, scene.x0, None, "mu = 0.11", draw.BLUE, True)]
    view, fonts = draw.View.of(scene), draw.fonts(pygame)
    forces = draw.newton_per_metre(scene)
    kept = [pygame.surfarray.array3d(draw.draw_frame(pygame, runs, 0.0, view, fonts, forces, r)[0])
            for r in ((0, 0), None, (100, 100))]

    def never(*args, **kw):
        raise AssertionError("the square drew a mark")
    for name in ("draw_marks", "place_strip", "layout", "draw_strip", "legend", "paint_mark"):
        monkeypatch.setattr(marks, name, never)
    runs[0]["marks"] = None                     # as frames.FrameWriter gives a run without a hand
    again = pygame.surfarray.array3d(draw.draw_frame(pygame, runs, 0.0, view, fonts, forces)[0])
    assert all(np.array_equal(again, k) for k in kept)


def test_a_comparison_has_a_row_per_run_on_one_scale_each_mark_its_own(chalk_runs):
    """Two runs (the pushed chalk at 1 s, and at 0.5 s in the second run's colour): the strip has a
    row each, one scale (the first run's tip at the same column), the run's colour at each row's
    left end, and each row's mark its own: the second's ends where its tip was at 0.5 s, white
    beyond; under the frame's board the two share the mark's depth, a band each; the legend says
    black is each run's darkest."""
    pygame = draw.load_pygame()
    live_runs = [chalk_at(1000, runs=chalk_runs), chalk_at(500, runs=chalk_runs)]
    scene = live_runs[0].scene
    view, fonts = draw.View.of(scene), draw.fonts(pygame)
    runs = [dict(frames.frame_run(scene, r.x, r.report, f"run {k}", draw.run_color(k), True),
                 marks=r.marks) for k, r in enumerate(live_runs)]
    surface, top = draw.draw_frame(pygame, runs, live_runs[0].t, view, fonts,
                                   draw.newton_per_metre(scene))
    pixels = pygame.surfarray.array3d(surface)
    below = draw.draw_slope(pygame, pygame.Surface(surface.get_size()), scene, view, draw.BLUE,
                            fonts[1])
    strip = marks.layout(runs, live_runs[0].t, view, fonts[1], top, draw.RESOLUTION, below)
    assert len(strip.rows) == 2 and strip.rows[1][0] == strip.rows[0][0] + strip.rows[0][1]
    left, y0 = strip.rect[:2]
    for i, (run, (row_top, row)) in enumerate(zip(runs, strip.rows)):
        assert tuple(pixels[left + 3, y0 + row_top + row // 2]) == run["color"]
        lo, hi = (float(strip.column(s)) for s in run["marks"].span())
        inside = np.arange(int(np.floor(lo)), int(np.ceil(hi)))
        shown = band(pixels, strip, i)
        assert np.array_equal(shown[inside], expected(run["marks"], inside, strip.board_at))
        assert (shown[int(np.ceil(hi)):int(np.ceil(hi)) + 20] == 255).all()
    depth = round(marks.MARK_HEIGHT * view.unit * view.scale) // 2
    board = round(float(view(marks.board_point(scene, 0.0))[0, 1])) + 2
    origin = float(view(marks.board_point(scene, 0.0))[0, 0])
    for i, run in enumerate(runs):
        lo, hi = (origin + view.scale * s for s in run["marks"].span())
        inside = np.arange(int(np.floor(lo)), int(np.ceil(hi)))
        want = expected(run["marks"], inside, lambda c: (c - origin) / view.scale)
        assert np.array_equal(pixels[inside, board + i * depth + depth // 2], want)
    assert marks.legend(runs)[1] == ((255, 255, 255), "black: each run's darkest 0.1 mm")
