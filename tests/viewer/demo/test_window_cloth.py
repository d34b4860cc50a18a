"""The live window of the tablecloth (scene.surface): it draws the cloth as the frames do, under the
dish, its stripes moving during the pull and still after it (helpers.window drives it)."""
import numpy as np
import pytest

import simulator
from viewer.pictures import draw, frames
from viewer.demo import live

from helpers.window import live_window, pygame

pytestmark = pytest.mark.usefixtures("shared_stepping")   # the runs' steps: helpers/runs.py


def test_the_window_draws_the_cloth_as_the_frames_do_moving_only_during_the_pull():
    """A 400 px window of a 0.2 m pull at 4 m/s (t = 0 to 0.05 s), paused after n steps: its band
    under the table is the frame's (draw_frame with the window's view and forces), in the cloth's
    colours under the dish (arrowheads aside); it changes from step 4 to 5 (in the pull), not from
    15 to 16."""
    scene = simulator.build_tablecloth_scene(pull_length=0.2, t_pull=0.0)
    w, _ = live_window(scene, steps=20, size=400)
    w.run, w.playing = live.LiveRun(scene, 20), False
    rows = {}
    for n in (4, 5, 15, 16):
        while w.run.index < n:
            w.run.step()
        w.draw()
        row = round(float(w.view(scene.o - 0.5 * draw.CLOTH_DEPTH * w.view.unit * scene.n)[1]))
        rows[n] = pygame().surfarray.array3d(w.screen)[:, row]
        run = frames.frame_run(scene, w.run.x, w.run.report, w.label, draw.BLUE, True)
        frame, _ = draw.draw_frame(pygame(), [run], w.run.t, w.view, w.fonts, w.newton_per_metre)
        assert np.array_equal(rows[n], pygame().surfarray.array3d(frame)[:, row]), n
        ends = w.view(w.run.x)[:, 0]
        under = rows[n][round(ends.min()):round(ends.max()) + 1]
        under = under[~(under == draw.BLUE).all(axis=1)]            # the table's ticks aside
        cloth = [(under == color).all(axis=1) for color in (draw.CLOTH_COLOR, draw.CLOTH_STRIPE)]
        assert np.logical_or(*cloth).mean() > 0.9, n
    assert not np.array_equal(rows[4], rows[5])
    assert np.array_equal(rows[15], rows[16])
