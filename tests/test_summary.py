"""summary.png's layout (viewer.summary.plan, which draw_summary draws): no snapshot or time label is
cut by the picture's border, none overlaps another but the first and the last, and the scale reads
as a round number of pixels per metre."""
import itertools

import numpy as np
import pytest

import simulator
from helpers.command import recorded as tracks_of
from viewer import draw, summary


def overlap(a, b, gap):
    return not (b[0] > a[2] + gap or a[0] > b[2] + gap or b[1] > a[3] + gap or a[1] > b[3] + gap)


@pytest.mark.parametrize("overrides, steps", [
    ([{"v0": (20.0, 0.0)}], 150),                           # 30 m along the slope: the scale shrinks
    ([{"v0": (0.0, -50.0)}], 300),                          # thrown at the slope: crushed, bouncing back
    ([{"mu": 0.1}, {"mu": 0.2}], 300)])                     # mu 0.2 stops near where it landed
def test_snapshots_and_labels_are_whole_and_clear_of_each_other_but_the_first_and_last(tmp_path, overrides, steps):
    pygame = draw.load_pygame()
    tracks = tracks_of(tmp_path, [simulator.build_scene(**o) for o in overrides], steps)
    plan = summary.plan(pygame, tracks, ["a header line"])
    assert plan.width <= summary.MAX_WIDTH
    for panel in plan.panels:
        shots = panel.snapshots
        assert shots[0].t == 0.0 and shots[-1].t == pytest.approx(panel.track.t) and len(shots) >= 2
        for s in shots:                                     # label and square inside the panel's picture
            assert s.box[0] >= 0 and s.box[1] >= 0, s.label
            assert s.box[2] <= plan.width and s.box[3] <= panel.height - summary.HEADER, s.label
        for (i, a), (j, b) in itertools.combinations(enumerate(shots), 2):
            if (i, j) != (0, len(shots) - 1):
                assert not overlap(a.box, b.box, summary.GAP), (a.label, b.label)
    surface = summary.draw_summary(pygame, tracks, ["a header line"])
    assert surface.get_size() == (plan.width, plan.height)


def test_the_scale_is_a_round_number_of_pixels_per_metre(tmp_path):
    """SCALE pixels per metre where the motion fits; beyond, two significant digits, so that the bar's
    text ("1 m (37 pixels)") is the scale drawn."""
    pygame = draw.load_pygame()
    assert summary.plan(pygame, tracks_of(tmp_path, [simulator.build_scene()], 20), []).scale == summary.SCALE
    scale = summary.plan(pygame, tracks_of(tmp_path, [simulator.build_scene(v0=(20.0, 0.0))], 150), []).scale
    assert scale < summary.SCALE and f"{scale:.3g}" == f"{scale:g}" and scale == draw.nice_number(scale, summary.TWO_DIGITS)
    assert [draw.nice_number(v, summary.TWO_DIGITS) for v in (38.79, 0.5432, 99.99, 1234.0)] == [38.0, 0.54, 99.0, 1200.0]
