"""The live window on the grasp: it steps, draws the fingers' pads, and shows a Newton iteration."""
import numpy as np
import pytest

from helpers.window import frames_until, live_window, press, pygame
from scenes import grasp
from viewer.pictures import draw

pytestmark = pytest.mark.usefixtures("shared_stepping")   # the runs' steps: helpers/runs.py


def test_the_window_draws_the_grasp_s_pads_and_its_newton_iterations():
    scene = grasp.build_grasp_scene()
    seen = {}

    def script():
        yield from frames_until(lambda: w.run.index >= 20)
        pixels = pygame().surfarray.array3d(w.screen)
        seen["pads"] = int(np.all(pixels == draw.PUSHED_COLOR, axis=2).sum())
        press("K_SPACE")
        yield
        press("K_n")
        for _ in range(5):
            yield

    w, clock = live_window(scene, steps=60)
    clock.script = script()
    assert w.loop() == 0
    assert seen["pads"] > 200
