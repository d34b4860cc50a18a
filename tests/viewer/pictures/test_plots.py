"""plots.png's axes carry their units: "t (s)" at the end of every time axis, the quantity and its
unit up every value axis (the panels' titles name them too). The chalk's plots.png, one run or a
comparison, shows its tip against the drive, the normal force and each stick-slip cycle, per run,
and no square's words (rest)."""
import re

import numpy as np
import pytest

import simulator
from helpers import legibility
from helpers.command import recorded as tracks_of
from viewer.pictures import draw, plots
from analysis import stick_slip


def axis_labels_drawn(pygame, surface, panels):
    dark = np.all(pygame.surfarray.array3d(surface) < 100, axis=2)             # [x, y]: text
    for panel in range(panels):
        first = plots.TOP + panel * plots.PANEL_HEIGHT
        top, bottom = first + 24, first + plots.PANEL_HEIGHT - 30
        t_label = dark[plots.RIGHT + 12:plots.RIGHT + 50, bottom + 3:bottom + 18]
        assert t_label.any(), f"panel {panel}: t (s)"
        assert dark[:22, top:bottom].any(), f"panel {panel}: the value axis"


def test_every_panel_labels_its_time_axis_and_its_value_axis(tmp_path):
    pygame = draw.load_pygame()
    surface, _ = plots.draw_plots(pygame, tracks_of(tmp_path, [simulator.build_scene()], 30))
    axis_labels_drawn(pygame, surface, 3)


@pytest.fixture(scope="module")
def chalks(tmp_path_factory, chalk_runs):
    """Two chalks side by side for 0.6 s (3 cycles of the default's 107 ms after the 0.2 s start):
    one coefficient (mu_s = mu, it slides with the hand) and the default's mu_s = 0.5 > mu
    (stick-slip); their steps the session's shared runs' (helpers/runs.py)."""
    return tracks_of(tmp_path_factory.mktemp("chalks"), [simulator.build_chalk_scene(mu_s=0.35),
                                                         simulator.build_chalk_scene()], 600,
                     chalk_runs.simulate)


def drawn(monkeypatch, pygame, tracks):
    """plots.png's surface for `tracks`, the texts its fonts rendered, and its panels by title."""
    texts, panels = legibility.record_text(monkeypatch), {}

    class Noted(plots.Axes):
        def __init__(self, *args, **kw):
            super().__init__(*args, **kw)
            panels[args[7]] = self
    monkeypatch.setattr(plots, "Axes", Noted)
    surface, axis = plots.draw_plots(pygame, tracks)
    return surface, [text for text, _, _ in texts], panels


def inside(pygame, surface, ax, color):
    """How many pixels of `color` the panel `ax` has inside its box."""
    pixels = pygame.surfarray.array3d(surface)[plots.LEFT + 1:plots.RIGHT, ax.top + 1:ax.bottom]
    return int(np.all(pixels == color, axis=2).sum())


def test_a_chalk_comparison_plots_each_runs_tip_normal_force_cycles_and_friction_work(
        monkeypatch, chalks):
    pygame = draw.load_pygame()
    surface, texts, panels = drawn(monkeypatch, pygame, chalks)
    assert surface.get_size() == (plots.WIDTH, plots.TOP + 4 * plots.PANEL_HEIGHT)
    axis_labels_drawn(pygame, surface, 4)
    titles = list(panels)
    assert [t.split()[:3] for t in titles] == [
        ["the", "tip's", "speed"], ["the", "board's", "normal"], ["each", "stick-slip", "cycle's"],
        ["the", "work", "friction"]]
    tip, normal, cycles, work = panels.values()
    for tr in chalks:
        for ax in (tip, normal, work):
            assert inside(pygame, surface, ax, tr.color) > 50, (tr.label, ax)
        first = plots.cycles_legend(stick_slip.of_track(tr))[0]
        assert {tr.label, f"{tr.label}: {first}"} <= set(texts)
    assert inside(pygame, surface, tip, plots.BLACK) > 200 and "drive speed" in texts   # the drive
    sliding, pushed = (stick_slip.of_track(tr) for tr in chalks)
    assert sliding.slips == [] and inside(pygame, surface, cycles, chalks[0].color) == 0
    assert len(pushed.slips) == 3 and f"{chalks[1].label}: 3 slips" in texts
    pixels = pygame.surfarray.array3d(surface)
    for t, length, _ in pushed.slips:                    # a dot of the run's colour at each cycle
        col, row = cycles.px(t, 1e3 * length)
        assert tuple(pixels[int(round(float(col))), int(round(float(row)))]) == chalks[1].color
    mean, period = 1e3 * pushed.length, 1e3 * pushed.period
    assert f"{mean:.2f} mm, {period:.0f} ms, {100 * pushed.stuck:.0f} %" in texts
    assert not [text for text in texts if re.search(r"\brest\b", text)]


def test_one_chalk_run_has_its_energy_budget_on_top_and_its_cycles(monkeypatch, chalks):
    pygame = draw.load_pygame()
    surface, texts, panels = drawn(monkeypatch, pygame, chalks[1:])
    assert surface.get_size() == (plots.WIDTH, plots.TOP + 4 * plots.PANEL_HEIGHT)
    axis_labels_drawn(pygame, surface, 4)
    assert [t.split()[:2] for t in panels] == [["energy", "budget"], ["the", "tip's"],
                                               ["the", "board's"], ["each", "stick-slip"]]
    first, second = plots.cycles_legend(stick_slip.of_track(chalks[1]))
    shown = {"hand work W_hand", "tip speed", "drive speed", "sum of lambda_k", first, second}
    assert shown <= set(texts)
    assert not [text for text in texts if re.search(r"\brest\b", text)]


def test_the_normal_forces_go_on_a_log_axis_where_the_runs_differ_tenfold(monkeypatch, chalks):
    """Forces of one run ten times another's would flatten the other's saw-tooth on a linear
    axis."""
    pygame = draw.load_pygame()
    peaks = [max(s.normal_force for s in tr.samples.all()) for tr in chalks]
    assert max(peaks) < 10 * min(peaks)
    assert not list(drawn(monkeypatch, pygame, chalks)[2].values())[1].log
    for s in chalks[0].samples.all():
        monkeypatch.setattr(s, "normal_force", s.normal_force * 20 * max(peaks) / peaks[0])
    panels = drawn(monkeypatch, pygame, chalks)[2]
    assert list(panels.values())[1].log and "differ more than 10-fold" in list(panels)[1]


def test_a_long_label_takes_a_legend_row_of_its_own(monkeypatch, chalks):
    """Every row of the cycles' legend fits between the legend's column and the picture's edge."""
    pygame = draw.load_pygame()
    font = pygame.font.Font(None, 18)
    for tr in chalks:
        monkeypatch.setattr(tr, "label", f"friction-iterations = {tr.scene.params['mu_s']:g}")
    _, texts, _ = drawn(monkeypatch, pygame, chalks)
    for tr in chalks:
        first, second = plots.cycles_legend(stick_slip.of_track(tr))
        assert {tr.label, first, second} <= set(texts) and f"{tr.label}: {first}" not in texts
        for row in (tr.label, first, second):
            assert font.size(row)[0] <= plots.WIDTH - plots.LEGEND_TEXT, row


def test_a_panel_grows_to_hold_a_long_legend_above_its_time_axis(monkeypatch, tmp_path):
    """Seven runs: the speed panel's legend has a row per run, one per run's rest and eps_v's, 15
    rows, more than a 250-pixel panel holds (11): it ran over the time axis's "t (s)" and into the
    panel below (a tester's tablecloth comparison). The panel grows; the picture with it."""
    pygame = draw.load_pygame()
    scenes = [simulator.build_scene(mu=mu) for mu in (0.1, 0.12, 0.14, 0.16, 0.18, 0.2, 0.22)]
    surface, _, panels = drawn(monkeypatch, pygame, tracks_of(tmp_path, scenes, 20))
    moved, speeds, newton = panels.values()
    assert speeds.legend_row - speeds.top == 15 * 18 and speeds.legend_row <= speeds.bottom + 3
    assert newton.panel_top == speeds.panel_top + speeds.height_needed() > moved.panel_top + 500
    assert surface.get_height() == newton.panel_top + plots.PANEL_HEIGHT
    axis_labels_drawn(pygame, surface, 1)               # the first panel as it was
