"""The live window of the chalk (--scene chalk): its view, its hand, forces and mark, its figures
(helpers.window drives it)."""

import numpy as np
import pytest

from helpers.fakes import chalk_at
from helpers import legibility
from analysis import diagnostics
from viewer.pictures import draw, frames, marks, wrap
from viewer.demo import live

from helpers.window import differing_pixels, live_window, pygame

pytestmark = pytest.mark.usefixtures("shared_stepping")   # the runs' steps: helpers/runs.py


# ------------------------------------------------------------------------------------------------
# The chalk (--scene chalk): its view, its hand, forces and marks, its figures
# ------------------------------------------------------------------------------------------------

PUSHED, DRAGGED = (False, 240), (True, 400)     # (drag, steps): a slip's or a slide's mark by then


def chalk_window(runs, steps, drag=False, size=652):
    """A LiveWindow of the chalk paused after `steps` steps (helpers.fakes.chalk_at, from the
    session's shared run `runs`, the chalk_runs fixture), drawn once."""
    run_ = chalk_at(steps, drag, runs=runs)
    w, _ = live_window(run_.scene, steps=run_.steps, size=size)
    w.run, w.playing = run_, False
    w.draw()
    return w


def key_hints_top(w):
    """The first row of pixels of the key hints at the bottom."""
    rows = [row for text in w.help_lines()
            for row in wrap.phrase_rows(w.font, text, w.size - 24)]
    return w.size - 6 - len(rows) * w.font.get_linesize()


def chalk_top(w):
    """The highest row of pixels of the chalk and its hand's targets (7 px squares) in the
    window."""
    targets = w.shown(w.scene.hand.targets(w.run.t))
    return min(w.shown(w.run.shown_x)[:, 1].min(), targets[:, 1].min() - 3)


def mark_columns(w):
    """The columns of the window where the chalk's mark is grey under the board: along the mark's
    lowest row (marks.draw_marks: MARK_HEIGHT deep from 2 rows under the board's line), a neutral
    grey darker than white."""
    board = round(float(w.view(marks.board_point(w.scene, 0.0))[0, 1])) + 2
    depth = round(marks.MARK_HEIGHT * w.view.unit * w.view.scale)
    row = pygame().surfarray.array3d(w.screen)[:, board + depth - 1].astype(int)
    grey = (row[:, 0] == row[:, 1]) & (row[:, 1] == row[:, 2]) & (row[:, 0] < 255)
    return set(np.flatnonzero(grey).tolist())


@pytest.mark.parametrize("drag, steps", [PUSHED, DRAGGED])
def test_the_chalk_window_draws_the_frame_of_the_chalk_its_hand_forces_and_mark(drag, steps,
                                                                                chalk_runs):
    """The window shows the chalk as its frames do, zoomed as they zoom it (draw.View.of, at the
    window's size): below the status lines, the window is the frame draw.draw_frame draws of the
    state (the board, the chalk, the hand's targets and springs, the contact forces, the chalk's
    mark and its strip, kept off the rows of the status lines and the key hints); the hand's targets
    are there, and the mark in grey under the board over the stretch it covers."""
    w = chalk_window(chalk_runs, steps, drag)
    scene, size, frame_view = w.scene, w.size, draw.View.of(w.scene)
    assert w.view.scale == pytest.approx(frame_view.scale * size / draw.RESOLUTION)
    assert w.view.unit == frame_view.unit
    run_ = frames.frame_run(scene, w.run.x, w.run.report, w.label, draw.BLUE, True)
    run_["marks"] = w.run.marks
    top, bottom = w.text_bottom, key_hints_top(w)
    frame, legends = draw.draw_frame(pygame(), [run_], w.run.t, w.view, w.fonts,
                                     w.newton_per_metre, w.reserve)
    assert w.reserve == (top - legends, size - bottom)
    shown, drawn = pygame().surfarray.array3d(w.screen), pygame().surfarray.array3d(frame)
    assert np.array_equal(shown[:, top:bottom], drawn[:, top:bottom]), \
        differing_pixels(shown[:, top:bottom], drawn[:, top:bottom])
    px = w.view(w.run.x)
    (left, high), (right, low) = px.min(axis=0), px.max(axis=0)
    assert left > 0 and right < size and top < high and low < bottom
    box = shown[int(left):int(right) + 1, int(high):int(low) + 1]
    # the chalk's springs, anti-aliased: 3300 px at 652 px
    bluish = box[:, :, 2].astype(int) - box[:, :, :2].max(axis=2) > 60
    assert bluish.sum() > 2000
    for q in np.rint(w.view(scene.hand.targets(w.run.t))).astype(int):
        assert tuple(shown[q[0], q[1]]) == draw.HAND_COLOR                # the hand's targets
    assert np.all(shown[:, top:bottom] == draw.NORMAL_COLOR, axis=2).sum() > 20  # the board's push
    lo, hi = (float(w.view(marks.board_point(scene, s))[0, 0]) for s in w.run.marks.span())
    columns = mark_columns(w)
    assert min(columns) >= lo - 1 and max(columns) <= hi + 1 and len(columns) >= 0.8 * (hi - lo) > 2


def test_the_chalks_mark_grows_as_the_run_goes_and_starts_afresh_at_r(chalk_runs):
    """Stuck, the tip leaves almost nothing; slipping, it draws on (the first slip, about 1 mm,
    comes between steps 200 and 250): the mark drawn at step 250 holds that of step 200 and reaches
    beyond it; r clears it."""
    before = chalk_window(chalk_runs, 200)
    old = mark_columns(before)                                  # (one screen: read it first)
    after = chalk_window(chalk_runs, 250)
    new = mark_columns(after)
    assert old < new and max(new) > max(old)
    after.restart()
    after.draw()
    assert not mark_columns(after)


def test_the_chalk_windows_status_says_the_chalks_figures_and_no_slope(monkeypatch, chalk_runs):
    """Under the caption, the chalk's figures of the state shown (live.tip_lines: the tip's place
    and speed, stuck or slipping, the hand's drive, the board's normal force), as drawn; the Newton
    view says its iterate's figures instead, of the board (its inset's node the nearest to it): no
    text says 'slope'. The slipping state: the middle of the first slip after the press, as
    diagnostics.tip_stuck has the first 300 states (flags[i] is state i + 1's), not a fixed step
    (step 240, slipping when this test was written, is stuck in today's run); the stuck one: 300."""
    drawn = legibility.record_text(monkeypatch)
    scene, _, xs, vs = chalk_runs.states(0.3)                  # the first 300 states
    flags = [diagnostics.tip_stuck(scene, x, v) for x, v in zip(xs, vs)]
    assert len(flags) == 300 and flags[-1]
    first_slip = next(i for i in range(1, 300) if flags[i - 1] and not flags[i])
    slip_end = next(i for i in range(first_slip, 300) if flags[i])
    slipping, stuck = (chalk_window(chalk_runs, (first_slip + slip_end) // 2 + 1),
                       chalk_window(chalk_runs, 300))
    for w, state in ((slipping, "slipping: "), (stuck, "stuck: ")):
        lines = [text for text, _ in w.status_lines()]
        figures = live.tip_lines(w.scene, w.run.x, w.run.v, w.run.t)
        assert lines == [f"paused before step {w.run.index + 1}"] + figures
        assert lines[1].startswith("tip at ") and state in lines[1]
        assert "the hand's drive 10 mm/s" in lines[2]
    texts = [text for text, _, _ in drawn]
    assert set(live.tip_lines(stuck.scene, stuck.run.x, stuck.run.v, stuck.run.t)) <= set(texts)
    stuck.one_newton_iteration()
    stuck.draw()
    lines = [text for text, _ in stuck.status_lines()]
    assert lines[:2] == ["paused in step 301", "step 301, Newton iteration 1 (lagged friction)"]
    assert "inset: one node and the board magnified together; p (red) to scale" in lines
    assert stuck.inset.why == "nearest the board"
    assert stuck.inset.node == diagnostics.tip(stuck.scene, stuck.run.x)[0]
    texts = " ".join(text for text, _, _ in drawn)
    assert "(nearest the board)" in texts and "the board: " in texts and "slope" not in texts


@pytest.mark.parametrize("size", [600, 652, 900])
def test_no_text_in_the_chalk_window_is_small_faint_or_over_the_chalk(monkeypatch, size,
                                                                      chalk_runs):
    """The chalk's window is as legible as the square's: every text (the legends of the forces, the
    hand and the mark, the board's numbers in cm, the chalk's figures, the mark's strip's title and
    scale bar, the Newton view's lines and inset) with capitals at least draw.MIN_CAP_HEIGHT of the
    window tall, in a colour of contrast at least 4.5:1 on white; the legends' swatches on their
    labels' rows. The board is low enough that the status lines end above the chalk and its hand,
    and its numbers above the key hints (the Newton view's lines too, drawn smaller where they
    wrap onto more rows: window.clear_of_text)."""
    drawn = legibility.record_text(monkeypatch)
    w = chalk_window(chalk_runs, 240, size=size)
    assert w.text_bottom < chalk_top(w)
    pixels = pygame().surfarray.array3d(w.screen)
    for color in (draw.HAND_COLOR, marks.SWATCH):
        top, low, first, last, gap = legibility.swatch_and_label_rows(pixels, color, w.text_bottom)
        assert first <= top and low <= last and gap <= draw.cap_height(w.font)
    numbers = [text for text, _, color in drawn if text.endswith(" cm") and color == draw.BLUE]
    assert "0 cm" in numbers
    under = int(w.view(w.scene.o)[1]) + 2                   # the rows under the board's line
    ink = np.nonzero((pixels[:, under:] == draw.BLUE).all(axis=2).any(axis=0))[0]
    assert under + ink.max() < key_hints_top(w)             # the numbers' blue, above the hints
    w.one_newton_iteration()
    w.draw()
    assert w.inset is not None and w.text_bottom < chalk_top(w)
    texts = {text for text, _, _ in drawn}
    assert {"the hand: its targets and springs", "the chalk's mark: lambda x slid length (Archard)",
            "normal force lambda_k n", "paused before step 241", "(nearest the board)",
            "thin lines: springs", marks.title(), marks.bar_label()} <= texts
    assert min(cap for _, cap, _ in drawn) >= draw.MIN_CAP_HEIGHT * size
    assert min(legibility.contrast_ratio(color) for _, _, color in drawn) >= 4.5


def strip_of(w):
    """The Strip of the mark draw.draw_frame drew in the window `w` (marks.layout on the window's
    rows)."""
    run_ = {"scene": w.scene, "x": w.run.shown_x, "marks": w.run.marks, "color": draw.BLUE}
    scratch = pygame().Surface((w.size, w.size))
    below = draw.draw_slope(pygame(), scratch, w.scene, w.view, draw.BLUE, w.font)
    return marks.layout([run_], w.run.t, w.view, w.font, w.text_bottom, key_hints_top(w), below)


@pytest.mark.parametrize("size", [600, 652, 900])
@pytest.mark.parametrize("drag, steps", [PUSHED, DRAGGED])
def test_the_windows_strip_sits_beside_the_chalk_and_goes_for_the_newton_view(size, drag, steps,
                                                                             chalk_runs):
    """No room under the window's board (its numbers, then the key hints): the mark's strip stands
    above the board beside the chalk, on the side with more room, clear of the chalk and its hand's
    targets, under the status lines and above the board, inside the window, at x8 of the window's
    own scale (the frames' times size / 900), its title and border drawn; under its board each
    column over the window's mark (at 240 and 400 steps) the grey of the deposit of the board it
    spans. In the Newton view (n) the Newton inset takes that room: no strip (no room reserved for
    it, its border gone)."""
    w = chalk_window(chalk_runs, steps, drag, size)
    strip = strip_of(w)
    left, top, width, height = strip.rect
    body = np.vstack([w.view(w.run.x), w.view(w.scene.hand.targets(w.run.t))])
    board = int(w.view(w.scene.o)[1])
    assert strip.where == "beside the chalk"
    assert strip.scale == pytest.approx(8 * 4000.0 * size / draw.RESOLUTION)
    assert left + width < body[:, 0].min() - 3 or left > body[:, 0].max() + 3
    assert w.text_bottom < top and top + height < board and 0 <= left and left + width <= size
    shown = pygame().surfarray.array3d(w.screen)
    # its border
    assert np.all(shown[left:left + width, top] == 0) and np.all(shown[left, top:top + height] == 0)
    lo, hi = (float(strip.column(s)) for s in w.run.marks.span())
    columns = np.arange(max(int(np.floor(lo)), 2), min(int(np.ceil(hi)), width - 2))
    y = top + strip.rows[0][0] + strip.board + 2 + strip.band // 2
    want = marks.greys(w.run.marks.shade(strip.board_at(columns), strip.board_at(columns + 1)))
    assert len(columns) > 20 and np.array_equal(shown[left + columns, y], want)
    w.one_newton_iteration()
    w.draw()
    assert w.reserve is None and w.inset is not None
    assert not np.all(pygame().surfarray.array3d(w.screen)[left:left + width, top] == 0)
