"""summary.png's layout (viewer.pictures.summary.plan, which draw_summary draws): no snapshot or
time label is cut by the picture's border, none overlaps another but the first and the last, and
the scale reads as a round number of pixels per metre."""
import itertools

import numpy as np
import pytest

import simulator
from helpers.command import recorded as tracks_of
from viewer.pictures import draw, summary
from analysis import closing, stick_slip


@pytest.fixture(scope="module")
def recorded(tmp_path_factory, shared_runs):
    """recorded(build, overrides, steps): the tracks of the square's ("square") or the chalk's
    scenes with these overrides run side by side, each set run once for the module (their steps
    the session's shared runs': helpers/runs.py, simulate's bit for bit)."""
    kept = {}

    def run(build, overrides, steps):
        key = (build, repr(overrides), steps)
        if key not in kept:
            make = simulator.build_chalk_scene if build == "chalk" else simulator.build_scene
            scenes = [make(**o) for o in overrides]
            kept[key] = tracks_of(tmp_path_factory.mktemp(build), scenes, steps,
                                  shared_runs.simulate)
        return kept[key]
    return run


def overlap(a, b, gap):
    return not (b[0] > a[2] + gap or a[0] > b[2] + gap or b[1] > a[3] + gap or a[1] > b[3] + gap)


@pytest.mark.parametrize("overrides, steps", [
    ([{"v0": (20.0, 0.0)}], 150),                   # 30 m along the slope: the scale shrinks
    ([{"v0": (0.0, -50.0)}], 300),                  # thrown at the slope: crushed, bouncing back
    ([{"mu": 0.1}, {"mu": 0.2}], 300)])             # mu 0.2 stops near where it landed
def test_snapshots_and_labels_are_whole_and_clear_of_each_other_but_the_first_and_last(
        recorded, overrides, steps):
    pygame = draw.load_pygame()
    tracks = recorded("square", overrides, steps)
    plan = summary.plan(pygame, tracks, ["a header line"])
    assert plan.width <= summary.MAX_WIDTH
    for panel in plan.panels:
        shots = panel.snapshots
        assert shots[0].t == 0.0 and shots[-1].t == pytest.approx(panel.track.t) and len(shots) >= 2
        for s in shots:                             # label and square inside the panel's picture
            assert s.box[0] >= 0 and s.box[1] >= 0, s.label
            assert s.box[2] <= plan.width and s.box[3] <= panel.height - summary.HEADER, s.label
        for (i, a), (j, b) in itertools.combinations(enumerate(shots), 2):
            if (i, j) != (0, len(shots) - 1):
                assert not overlap(a.box, b.box, summary.GAP), (a.label, b.label)
    surface = summary.draw_summary(pygame, tracks, ["a header line"])
    assert surface.get_size() == (plan.width, plan.height)


def test_the_scale_is_a_round_number_of_pixels_per_metre(recorded):
    """SCALE pixels per metre where the motion fits; beyond, two significant digits (TWO_DIGITS,
    test_draw.py), so that the bar's text ("1 m (37 pixels)") is the scale drawn."""
    pygame = draw.load_pygame()
    assert summary.plan(pygame, recorded("square", [{}], 20), []).scale == summary.SCALE
    scale = summary.plan(pygame, recorded("square", [{"v0": (20.0, 0.0)}], 150), []).scale
    assert scale < summary.SCALE and f"{scale:.3g}" == f"{scale:g}"
    assert summary.TWO_DIGITS == range(10, 100) and scale == draw.nice_number(scale, range(10, 100))


def test_every_line_of_text_fits_and_the_chalk_says_its_stick_slip_not_rest(recorded):
    """The header's lines (the chalk's parameters are long) and each panel's line are whole inside
    the picture: it is as wide as the widest. The square's header ends with what its sticking and
    creep count, its panel with its own; the chalk's with how its stick-slip is counted, each
    run's figures in its panel."""
    pygame = draw.load_pygame()
    font, small = pygame.font.Font(None, 24), pygame.font.Font(None, 20)
    square = recorded("square", [{}], 20)
    assert summary.header_lines(square, ["h"]) == ["h", closing.counted(square[0].scene)]
    assert summary.panel_words(square[0]) == closing.rest_words(square)
    chalks = recorded("chalk", [{}, {"drag": True}], 150)
    plan = summary.plan(pygame, chalks, ["chalk 9 x 1 cm, pushed at tilt = 60 deg   grip k_hand = "
                                         "2000 N/m   drive = 0.01 m/s   mu_s = 0.5   mu = 0.35   "
                                         "v_c = 0.001 m/s"])
    first, second = stick_slip.definition(chalks[0].scene)
    assert plan.lines[1:] == ["stick-slip, " + first, second]
    assert not [h for h in plan.lines if "rest" in h.split()]
    assert plan.width >= max(font.size(text)[0] for text in plan.lines) + 12
    for panel in plan.panels:
        words = summary.panel_words(panel.track)
        assert words == stick_slip.words(stick_slip.of_track(panel.track)) == \
            "not driven yet at t = 0.15 s (the hand drives from t = 0.2 s)"
        assert plan.width >= small.size(words)[0] + 12


@pytest.mark.parametrize("build, overrides, steps", [
    ("square", [{"mu": 0.1}, {"mu": 0.2}], 300),    # the header is wider than the motion
    ("square", [{"slope": (0.5, 1.0)}], 100),       # a steeper slope
    ("chalk", [{}], 300)])                          # the chalk: the header is wider still
def test_the_slope_and_its_numbers_span_the_motion_and_are_whole(recorded, build, overrides, steps):
    """Each panel draws the slope (its ticks and numbers, draw.draw_slope) across the motion alone:
    as wide as the motion with MARGIN either side and the last label, whatever the header's width
    (the chalk's numbers spanned -5 to 38 cm for 3 cm of motion); and tall enough that every number
    is whole (a comparison's were cut at the panel's bottom, where the slope runs down to the
    right)."""
    pygame = draw.load_pygame()
    tracks = recorded(build, overrides, steps)
    plan = summary.plan(pygame, tracks, ["a header line " * 8])
    small = pygame.font.Font(None, 20)                  # the numbers' font (summary.draw_summary)
    label_w = small.size(summary.time_label(max(tr.t for tr in tracks)))[0]
    z = draw.zoom(tracks[0].scene)
    motion = max(np.ptp(np.concatenate([x for _, x in tr.snapshots.all()])[:, 0])
                 for tr in tracks)
    for panel in plan.panels:
        view = panel.view
        across = (motion + 2 * summary.MARGIN / z) * view.scale + label_w + 12   # px
        assert view.size <= across + 1 < plan.width
        ink = []
        for font in (small, None):          # the numbers: what a font adds, on a taller surface
            scratch = pygame.Surface((view.size, 3 * view.height))
            scratch.fill((255, 255, 255))
            draw.draw_slope(pygame, scratch, panel.track.scene, view, (0, 0, 0), font)
            ink.append(pygame.surfarray.array3d(scratch).min(axis=2) < 128)
        rows = np.nonzero((ink[0] & ~ink[1]).any(axis=0))[0]
        assert len(rows) and rows.max() < view.height                           # drawn, and whole


def test_a_square_far_above_its_slope_gets_a_summary_of_bounded_size(recorded):
    """--center 1e8,1e8 --slope-point 1e8,0 --slope-normal 0,1: the slope 1e8 m below asked for a
    picture 1e10 px tall (pygame.error: Out of memory). Both stay in view, at a smaller scale, in
    MAX_HEIGHT px of motion and slope, plus the time labels' rows over and under it at most."""
    pygame = draw.load_pygame()
    far = {"center": (1e8, 1e8), "slope_point": (1e8, 0.0), "slope": (0.0, 1.0)}
    tracks = recorded("square", [far], 5)
    plan = summary.plan(pygame, tracks, ["a header line"])
    (panel,) = plan.panels
    assert plan.width <= summary.MAX_WIDTH and plan.scale < summary.SCALE
    label_h = pygame.font.Font(None, 20).size("t = 0.1 s")[1]          # as summary.plan's
    assert panel.height - summary.HEADER <= summary.MAX_HEIGHT + 2 * (label_h + 4)
    surface = summary.draw_summary(pygame, tracks, ["a header line"])
    assert surface.get_size() == (plan.width, plan.height)


def test_a_label_wider_than_the_room_beside_its_snapshot_is_slid_inside():
    """A 5 cm block at 10 px/m beside the view's left edge (a grasp's dropped block at the scale
    that fits its fall): its label centred above it would start at about -25 px, cut."""
    small = draw.load_pygame().font.Font(None, 20)
    view = draw.View(10.0, 200, 400)
    view.center = np.array([10.0, 0.0])                 # x = 0 m at the left edge
    block = np.array([[0.5, 0.0], [0.55, 0.0], [0.55, 0.05], [0.5, 0.05]])
    shots = summary.labelled(view, small, [(0.0, block), (0.5, block + [0.0, -5.0])])
    centred = view(block)[:, 0].mean() - small.size(shots[0].label)[0] / 2
    assert centred < 0.0 and shots[0].label_at[0] == 0.0 and shots[0].box[0] == 0.0
    assert shots[-1].label_at[0] > view(block)[:, 0].max()      # the last one's to its right
