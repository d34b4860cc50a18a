"""The live window's layout over a run: the view after r, and the status text clear of the
drawing (helpers.window drives it)."""
import numpy as np
import pytest

from helpers.fakes import chalk_at
from viewer.pictures import draw, wrap

from helpers.window import frames_until, live_window, press, pygame


def test_r_starts_the_view_afresh_its_arrow_scale_and_zoom_as_a_new_run_s():
    """The arrows' scale coarsens at the impact (view.arrow_factor 1 -> 2, 5, ...) and never goes
    back within a run; after r the view is a new run's (draw.View.of), so the arrows are drawn at
    the scale a new run starts with."""
    def script():
        yield from frames_until(lambda: w.view.arrow_factor > 1)
        press("K_r")
        yield
        fresh = draw.View.of(w.scene, w.size)
        seen["factor"] = w.view.arrow_factor
        assert w.view.scale == fresh.scale and np.array_equal(w.view.center, fresh.center)

    seen = {}
    w, clock = live_window(steps=100)
    clock.script = script()
    assert w.loop() == 0
    assert seen["factor"] == 1.0


def status_rows(w):
    """The status's rows as the window breaks them (wrap.phrase_rows)."""
    return [row for text, _ in w.status_lines()
            for row in wrap.phrase_rows(w.font, text, w.size - 24)]


def drawing_under_text(w, colors):
    """The pixels of `colors` (the drawing's own: the mesh, the hand, the pads) in the rows of the
    status text, between its first row and its last."""
    top = w.text_bottom - len(status_rows(w)) * w.font.get_linesize()
    rows = pygame().surfarray.array3d(w.screen)[:, top:w.text_bottom]
    return sum(int((rows == color).all(axis=2).sum()) for color in colors)


def test_the_chalk_s_newton_view_at_510_px_keeps_the_chalk_and_hand_under_the_text():
    """At --size 510 the Newton view's lines wrap onto 10 rows, down to where the chalk and its
    hand are drawn: the window draws them lower and smaller (clear_of_text), the board where it
    was; none of the mesh's blue or the hand's colour among the status rows."""
    run = chalk_at(300)
    w, _ = live_window(run.scene, steps=run.steps, size=510)
    w.run, w.playing = run, False
    w.one_newton_iteration()
    w.draw()
    assert len(status_rows(w)) >= 9 and w.inset is not None
    assert drawing_under_text(w, [draw.BLUE, draw.HAND_COLOR]) == 0
    board = w.view(w.scene.o)[1]
    assert w.shown(w.scene.o)[1] == pytest.approx(board, abs=2.0)
    assert w.shown(w.drawn_points())[:, 1].min() > w.text_bottom
