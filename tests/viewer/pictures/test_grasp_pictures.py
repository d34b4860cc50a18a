"""The grasp's plots.png and page say what its closing words say: the block dropped at its time,
or held and creeping as fitted from the same window, beside u*; never 'sticks from' a time after
the block slid past the pads (there the infinite half-spaces grip it again, the pads do not)."""
import numpy as np
import pytest

from analysis import closing
from helpers import legibility
from helpers.command import recorded
from scenes import grasp
from viewer.pictures import draw, frames, page, plots


@pytest.fixture(scope="module")
def tracks(tmp_path_factory, shared_runs):
    """2 N drops the block at 0.75 s and the half-spaces grip it again at about 1.16 s (measured);
    4 N holds it. 1.2 s each; the steps the session's shared runs' (helpers/runs.py: simulate's,
    bit for bit), which tests/scenes/test_grasp.py reads too."""
    scenes = [grasp.build_grasp_scene(squeeze=2.0), grasp.build_grasp_scene(squeeze=4.0)]
    return recorded(tmp_path_factory.mktemp("grasps"), scenes, 240,
                    shared_runs.simulate)


def test_plots_legend_says_the_closing_words_not_sticks_from(tracks, monkeypatch):
    dropped, held = (closing.closing_words([track]) for track in tracks)
    assert dropped.startswith("the block dropped at 0.75 s") and tracks[0].rest_since > 0.75
    assert held.startswith("the block held") and "from 0.55 s (u* 0.286)" in held
    (when_dropped, _), (when_held, _) = (track.scene.pushed.mark(track) for track in tracks)
    assert f"{when_dropped:.2f}" == "0.75" and when_held == 0.55     # the drop; the fit's start
    texts = legibility.record_text(monkeypatch)
    plots.draw_plots(draw.load_pygame(), tracks)
    said = " ".join(text for text, _, _ in texts)
    assert "sticks from" not in said and "closed form" not in said
    for track in tracks:            # the legend's rows are the short closing words, whole
        assert track.scene.pushed.words(track, short=True) in said


def test_the_page_table_says_the_closing_words(tracks):
    figures = page.run_figures(tracks)
    assert "rest" not in figures
    assert figures["rows"] == [("what it showed", [closing.closing_words([t]) for t in tracks])]


def test_the_energy_panel_draws_each_curve_in_a_colour_of_its_own(tracks, monkeypatch):
    """The grasp's energy curves (gravity and W_lift were both brown): every two colours at least
    60 apart in RGB (the closest pair of the other scenes' curves drawn together: 63)."""
    drawn = []
    monkeypatch.setattr(plots.Axes, "legend", lambda ax, *row: drawn.append((ax, *row)))
    plots.draw_plots(draw.load_pygame(), tracks[1:])
    energy = [(color, text) for ax, color, text in drawn if ax is drawn[0][0]]
    assert {"gravity", "lift work W_lift", "fingers"} <= {text for _, text in energy}
    colors = np.array([color for color, _ in energy], dtype=float)
    apart = np.linalg.norm(colors[:, None] - colors[None], axis=2)[np.triu_indices(len(colors), 1)]
    assert apart.min() >= 60.0, energy


def test_the_lifted_block_stays_centred_under_the_legends(tracks):
    """The view panned only once the block was 1.2 units (6 cm) off its centre: the lift carried
    the block and its pads up under the legends (a tester's frame at 1.5 s). A grasp's view keeps
    the block centred: at 1.2 s, 0.18 m up, its top is below the legends' last row."""
    pygame, (_, held) = draw.load_pygame(), tracks
    view = draw.View.of(held.scene)
    com = held.samples.last.com
    assert com[1] > 0.15                                        # lifted 3 block heights
    view.follow(com[None])
    run = frames.frame_run(held.scene, held.x, held.samples.last.report, held.label, held.color,
                           True)
    _, top = draw.draw_frame(pygame, [dict(run, marks=None)], held.t, view, draw.fonts(pygame),
                             draw.newton_per_metre(held.scene))
    rows = view(np.vstack([held.x, *held.scene.pushed.pads(held.x, draw.PAD_DEPTH * view.unit)]))
    assert rows[:, 1].min() > top and abs(float(view(com)[1]) - view.height / 2) < 1.0
