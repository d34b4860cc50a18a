"""The live window's layout over a run: the view after r, the run's result when it ends (the
closing's words), and the status text clear of the drawing (helpers.window drives it)."""
import numpy as np
import pytest

import simulator
from analysis import closing
from helpers.command import recorded
from helpers.fakes import chalk_at
from scenes import grasp
from viewer.pictures import draw, wrap

from helpers.window import frames_until, live_window, press, pygame

pytestmark = pytest.mark.usefixtures("shared_stepping")   # the runs' steps: helpers/runs.py


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


def played_to_the_end(scene, steps, size, restart_at=None):
    """A window of `scene` played to the end of its `steps` (r pressed once at step `restart_at`),
    then paused there a few frames; the window."""
    def script():
        if restart_at is not None:
            yield from frames_until(lambda: w.run.index >= restart_at)
            press("K_r")
        yield from frames_until(lambda: w.run.finished)
        for _ in range(3):
            yield

    w, clock = live_window(scene, steps=steps, size=size)
    clock.script = script()
    assert w.loop() == 0
    return w


def status_rows(w):
    """The status's rows as the window breaks them (wrap.phrase_rows)."""
    return [row for text, _ in w.status_lines()
            for row in wrap.phrase_rows(w.font, text, w.size - 24)]


CASES = {
    "tablecloth": (simulator.build_tablecloth_scene, 120, 652, None),
    "grasp held": (grasp.build_grasp_scene, 300, 510, 40),
    "grasp dropped": (lambda: grasp.build_grasp_scene(squeeze=0.5), 120, 652, None),
    "square in the air": (simulator.build_scene, 20, 400, None),
    "chalk": (simulator.build_chalk_scene, 300, 510, None),
}


@pytest.fixture(scope="module")
def held_grasp():
    """The grasp's window at 510 px played to the end of its 300 steps, r pressed at step 40 (the
    case "grasp held"): after r the run starts afresh (LiveRun.restart, a new view), so it ends as
    a run played through does, and serves the tests of both. Its screen is kept as a copy: a later
    window opens the display again."""
    build, steps, size, restart_at = CASES["grasp held"]
    w = played_to_the_end(build(), steps, size, restart_at)
    w.screen = w.screen.copy()
    return w


@pytest.mark.parametrize("case", CASES)
def test_the_ended_window_says_the_closing_s_result_on_rows_of_its_own(tmp_path, case, request,
                                                                        shared_runs):
    """Once the run has ended, under "end of the run (N steps)", the window says what the
    command line's closing says the run showed: closing.closing_words of the same scene recorded
    into files (the tablecloth's travel beside its closed form, the grasp's held or dropped), also
    after r; on rows of their own within the window, none of the drawing's blue (the body, the
    ground) or pads among them. The recording's steps are the session's shared runs'
    (helpers/runs.py: simulate's, bit for bit)."""
    build, steps, size, restart_at = CASES[case]
    w = request.getfixturevalue("held_grasp") if case == "grasp held" else \
        played_to_the_end(build(), steps, size, restart_at)
    said = closing.closing_words(recorded(tmp_path, [build()], steps,
                                          shared_runs.simulate))
    assert ("dish travelled" in said if case == "tablecloth" else
            case.split()[1] in said if case.startswith("grasp") else
            "slip" in said if case == "chalk" else "in the air" in said)
    lines = [text for text, _ in w.status_lines()]
    assert lines[:2] == [f"end of the run ({steps} steps)", said]
    rows = status_rows(w)
    assert " ".join(rows).count(said.split("; ")[0]) == 1
    assert all(w.font.size(row)[0] <= w.size - 24 for row in rows)
    assert drawing_under_text(w, [draw.BLUE, draw.PUSHED_COLOR, draw.HAND_COLOR]) == 0


def drawing_under_text(w, colors):
    """The pixels of `colors` (the drawing's own: the mesh, the hand, the pads) in the rows of the
    status text, between its first row and its last."""
    top = w.text_bottom - len(status_rows(w)) * w.font.get_linesize()
    rows = pygame().surfarray.array3d(w.screen)[:, top:w.text_bottom]
    return sum(int((rows == color).all(axis=2).sum()) for color in colors)


def test_the_chalk_s_newton_view_at_510_px_keeps_the_chalk_and_hand_under_the_text(shared_runs):
    """At --size 510 the Newton view's lines wrap onto 10 rows, down to where the chalk and its
    hand are drawn: the window draws them lower and smaller (clear_of_text), the board where it
    was; none of the mesh's blue or the hand's colour among the status rows."""
    run = chalk_at(300, runs=shared_runs)
    w, _ = live_window(run.scene, steps=run.steps, size=510)
    w.run, w.playing = run, False
    w.one_newton_iteration()
    w.draw()
    assert len(status_rows(w)) >= 9 and w.inset is not None
    assert drawing_under_text(w, [draw.BLUE, draw.HAND_COLOR]) == 0
    board = w.view(w.scene.o)[1]
    assert w.shown(w.scene.o)[1] == pytest.approx(board, abs=2.0)
    assert w.shown(w.drawn_points())[:, 1].min() > w.text_bottom


def test_the_ended_grasp_at_510_px_keeps_its_pads_under_the_text(held_grasp):
    """The grasp's block is kept centred (View.margin 0); at 510 px its result's rows would reach
    its pads and the arrows on them: the window pans it down, under the text (the window
    `held_grasp`, played to the end after an r: measured, a run played through without it ends
    in the same pixels)."""
    assert drawing_under_text(held_grasp, [draw.BLUE, draw.PUSHED_COLOR]) == 0
