"""The tablecloth (scene.surface) as a frame draws it: a band in the cloth's own colours under the
table and under the dish, whose stripes move with the cloth (surface.offset(t)) during the pull and
stand still after it; plots.png's energy budget with the surface's work and the heat."""
import numpy as np

import simulator
from helpers.command import recorded
from viewer.pictures import draw, frames, plots

U, L = 4.0, 0.2         # m/s, m: a short pull, from t = 0 to L / U = 0.05 s (10 steps of 5 ms)
CLOTH = np.array([draw.CLOTH_COLOR, draw.CLOTH_STRIPE])


def cloth_scene():
    return simulator.build_tablecloth_scene(pull_speed=U, pull_length=L, t_pull=0.0)


def band(pygame, surface, view, scene):
    """The frame's pixels along the middle of the cloth's band, [column, rgb]."""
    row = round(float(view(scene.o - 0.5 * draw.CLOTH_DEPTH * view.unit * scene.n)[1]))
    return pygame.surfarray.array3d(surface)[:, row]


def is_cloth(pixels):
    """Which pixels (k, 3) have one of the cloth's two colours."""
    return (pixels[:, None, :] == CLOTH[None]).all(axis=2).any(axis=1)


def is_tick(pixels):
    """Which pixels (k, 3) are the table's (its ticks, drawn over the cloth)."""
    return (pixels == draw.BLUE).all(axis=1)


def drawn(pygame, scene, x, t, view):
    run = frames.frame_run(scene, x, None, f"U = {U:g} m/s", draw.BLUE, False)
    return draw.draw_frame(pygame, [run], t, view, draw.fonts(pygame))[0]


def test_the_cloth_lies_under_the_dish_and_its_stripes_move_with_it_during_the_pull_only():
    """With the view fixed: under the dish (the table's ticks aside) the cloth's colours at
    t = 0, in the pull and after it; from t to t + h in the pull the band's pattern moves U h along
    the table (U h scale = 20 px), trailing edge and stripes, and after the pull it does not move
    (the table's fixed ticks aside)."""
    pygame = draw.load_pygame()
    scene = cloth_scene()
    view = draw.View.of(scene)
    states = {0: scene.x0} | {r.index + 1: r.x for r in simulator.simulate(scene, 16)}
    rows = {}
    for n in (0, 4, 5, 15, 16):
        rows[n] = band(pygame, drawn(pygame, scene, states[n], n * scene.h, view), view, scene)
        ends = view(states[n])[:, 0]
        under = rows[n][round(ends.min()):round(ends.max()) + 1]
        unticked = ~is_tick(under)
        assert is_cloth(under[unticked]).all() and unticked.mean() > 0.9, n
    shift = round(U * scene.h * view.scale)
    assert shift == 20
    for (a, b), moved in (((4, 5), shift), ((15, 16), 0)):
        before, after = rows[a][:len(rows[a]) - shift], rows[b][moved:len(rows[b]) - shift + moved]
        kept = ~is_tick(before) & ~is_tick(after)
        assert kept.mean() > 0.9 and is_cloth(before[kept]).mean() > 0.5
        assert (before[kept] == after[kept]).all(axis=1).all(), (a, b)
        assert (before == draw.CLOTH_STRIPE).all(axis=1).any()
    assert not (rows[4] == rows[5]).all()


def with_budget(track):
    """Each Sample's cumulative surface_work and heat (heat = W_surface - W_friction) summed from
    its StepReports, where recording.Sample does not carry them yet (the command's helper)."""
    samples = track.samples.all()
    works = np.cumsum([0.0] + [s.report.surface_work for s in samples[1:]])
    for sample, work in zip(samples, works):
        if not hasattr(sample, "surface_work"):
            sample.surface_work, sample.heat = work, work - sample.friction_work
    return track


def test_the_energy_budget_of_a_moving_surface_shows_its_work_and_the_heat(tmp_path, monkeypatch):
    """plots.png of a tablecloth run: the energy panel's title reads E = E(0) + W_surface - heat
    - D and draws W_surface and -heat in their colours; the square's draws neither."""
    pygame = draw.load_pygame()
    titles = {}

    class Noted(plots.Axes):
        def __init__(self, *args, **kw):
            super().__init__(*args, **kw)
            titles[args[7]] = self
    monkeypatch.setattr(plots, "Axes", Noted)
    for scene, shown in ((cloth_scene(), True), (simulator.build_scene(), False)):
        titles.clear()
        (track,) = recorded(tmp_path / str(shown), [scene], 20)
        surface, _ = plots.draw_plots(pygame, [with_budget(track)] if shown else [track])
        title = next(title for title in titles if title.startswith("energy budget"))
        ax = titles[title]
        assert ("E = E(0) + W_surface - heat - D" in title) == shown
        box = pygame.surfarray.array3d(surface)[plots.LEFT + 1:plots.RIGHT, ax.top + 1:ax.bottom]
        for key in ("W_surface", "-heat"):
            assert np.all(box == plots.ENERGY_COLORS[key], axis=2).any() == shown, key
