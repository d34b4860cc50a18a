"""figures/grasp.py on a small case: each cell's simulated outcome is the rigid Coulomb block's,
one just below the line 2 mu N = m (g + a) holds all the same, and the creep sits on u*."""
import pytest

import figures.page
import scenes.grasp
from figures import grasp


def test_the_grasp_table_agrees_with_the_coulomb_block_and_the_creep_with_u_star():
    """mu 0.5: N 1.5 drops (2 mu N = 1.5 < m g = 1.96 N), 2.05 sits just below the line (2 mu N /
    (m (g + a)) = 0.994: it slips 5.5 mm while the lift accelerates, then grips); a cell above the
    line holds (tests/scenes/test_grasp.py).
    Creep at m g / (2 mu N) = 0.75, eps_v 1e-3: u* = 0.5 mm/s; 2 % (measured 0.06 %)."""
    r = grasp.compute(mus=(0.5,), squeezes=(1.5, 2.05), epsvs=(1e-3,), ratios=(0.75,))
    assert [(c.held, c.coulomb, c.line) for c in r.cells] == [
        (False, False, False), (True, True, False)]
    (point,) = r.points
    assert point.exact == pytest.approx(5e-4) and point.u == pytest.approx(point.exact, rel=0.02)
    page = grasp.draw(r)
    plots = figures.page.plots
    assert page.surface.get_height() == (figures.page.TITLE_HEIGHT + 2 * plots.PANEL_HEIGHT
                                         + figures.page.LINE_HEIGHT * (len(grasp.caption(r)) + 1))
    assert "in 2 of 2 cells; = the line 2 mu N >= m (g + a) in 1 of 2" in " ".join(grasp.caption(r))


def test_the_coulomb_boundary_lies_just_below_the_line():
    """At mu 0.5 the line is N = 2.062 N. By hand, 2 mu N / m = g + a - delta: the block slips
    0.08 delta in the 0.4 s the lift accelerates, then (0.4 delta)^2 / (2 (a - delta)) more as it
    slows; that is the pads' 5 cm at delta = 0.28 m/s^2, 2.7 % below the line."""
    line = scenes.grasp.squeeze_for(1.0, 0.5, grasp.A)
    assert line == pytest.approx(0.2 * 10.31 / 1.0)
    assert 0.95 * line < grasp.coulomb_boundary(0.5) < line
