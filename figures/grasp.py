"""Slide "Remarks - Applications: Robotics" (IPC-GraspSim's success table) for scenes/grasp.py: held
or dropped over mu x N, beside the line and the Coulomb block; creep on u* (docs/grasp.md)."""
from types import SimpleNamespace

import numpy as np
import scipy.optimize

import FrictionEnergy
import closed_forms
import simulator
from scenes import grasp
from figures.page import BLACK, GREY, Page
from viewer.pictures.draw import run_color

MUS = (0.4, 0.45, 0.5, 0.55, 0.6)           # the grid's friction coefficients, and
SQUEEZES = (1.7, 1.9, 2.05, 2.2, 2.4)       # N, each finger's force (two cells just below the line)
DURATION = 1.0      # s: the lift accelerates from 0.1 s to 0.5 s, then half a second steady
EPSVS = (1e-3, 2e-3)                        # m/s, the creep panel's two eps_v
RATIOS = (0.3, 0.5, 0.7, 0.85, 0.95)        # m g / (2 mu N) of its simulated points
CREEP_TOL = 1e-6    # m/s: the creep read to about 0.5 tol / u* (under 1 % at u* >= 0.1 mm/s)
A = grasp.GRASP["lift_accel"]   # m/s^2, the grid's lift
CREEP_WINDOW = (0.2, 0.4)   # s: the creep fitted here, the fingers still (no lift: t_lift beyond)


def held(scene):
    """Whether the simulated block stays on the pads through DURATION (stops once it has left)."""
    steps = simulator.simulate(scene, round(DURATION / scene.h))
    return all(grasp.slip(scene, record.x) < grasp.drop_slip(scene) for record in steps)


def coulomb_boundary(mu):
    """The squeeze N at which the rigid Coulomb block just reaches the pads' end by DURATION."""
    def excess(N):
        scene = grasp.build_grasp_scene(mu=mu, squeeze=N)
        return grasp.coulomb_slip(scene, DURATION) - grasp.drop_slip(scene)
    line = grasp.squeeze_for(1.0, mu, A)
    return scipy.optimize.brentq(excess, 0.5 * line, line, xtol=1e-9)


def creep(epsv, ratio):
    """A held block's creep speed with the fingers still, fitted over CREEP_WINDOW, beside u*."""
    N = grasp.squeeze_for(ratio, grasp.GRASP["mu"])
    scene = grasp.build_grasp_scene(squeeze=N, epsv=epsv, tol=CREEP_TOL, t_lift=10.0)
    t, slip = closed_forms.measured(scene, CREEP_WINDOW[1], grasp.slip)
    return grasp.fitted_rate(t, slip, *CREEP_WINDOW), grasp.creep_speed(scene)


def compute(mus=MUS, squeezes=SQUEEZES, epsvs=EPSVS, ratios=RATIOS):
    """The grid's cells (mu, N, simulated held, Coulomb held, above the line) and the creep
    points (eps_v, ratio, simulated u, closed-form u*)."""
    cells = [SimpleNamespace(mu=s.mu, N=s.params["squeeze"], held=held(s), line=grasp.holds(s),
                             coulomb=grasp.coulomb_slip(s, DURATION) < grasp.drop_slip(s))
             for s in (grasp.build_grasp_scene(mu=mu, squeeze=N) for mu in mus for N in squeezes)]
    points = [SimpleNamespace(epsv=e, ratio=r, u=u, exact=exact)
              for e in epsvs for r in ratios for u, exact in [creep(e, r)]]
    return SimpleNamespace(cells=cells, points=points, mus=mus, squeezes=squeezes, epsvs=epsvs)


def caption(r):
    """The slide's claim in this model, the agreement counts and the creep's worst error."""
    n, p = len(r.cells), grasp.GRASP
    coulomb, line = (sum(c.held == getattr(c, k) for c in r.cells) for k in ("coulomb", "line"))
    worst = max(r.points, key=lambda p: abs(p.u / p.exact - 1))
    return [
        f"A {p['mass']:g} kg block between two fingers pressed with N each, lifted at a = "
        f"{p['lift_accel']:g} m/s^2 to {p['lift_speed']:g} m/s; held: still on the pads at "
        f"{DURATION:g} s.",
        f"Simulated outcome = rigid Coulomb block's in {coulomb} of {n} cells; = the line "
        f"2 mu N >= m (g + a) in {line} of {n} (just below it,",
        "the block slips while the lift accelerates and may grip again before the pads' end).",
        f"Held, it still creeps: simulated creep on u* = eps_v (1 - sqrt(1 - m g / (2 mu N))) "
        f"within {100 * abs(worst.u / worst.exact - 1):.2g} % (tol {CREEP_TOL:g} m/s)."]


def draw(r):
    """The grid of outcomes over mu x N with the line and the Coulomb boundary; the creep curves."""
    page = Page("A grasp: held or dropped over mu x N, and the creep of a held block", 2,
                caption(r))
    mu_lo, mu_hi = min(r.mus) - 0.04, max(r.mus) + 0.04
    N_lo, N_hi = min(r.squeezes) - 0.2, max(r.squeezes) + 0.2
    ax = page.axes(0, mu_hi, N_lo, N_hi, "each finger's squeeze N (N) against "
                   "mu: filled held, hollow dropped (simulated)", "mu", "N (N)", x_lo=mu_lo)
    mu = np.linspace(mu_lo, mu_hi, 200)
    mu = mu[(grasp.squeeze_for(1.0, mu, A) <= N_hi) & (grasp.squeeze_for(1.0, mu) >= N_lo)]
    curves = [(grasp.squeeze_for(1.0, mu, A), run_color(0), 2, "2 mu N = m (g + a)"),
              (grasp.squeeze_for(1.0, mu), GREY, 1, "2 mu N = m g"),
              ([coulomb_boundary(m) for m in mu], run_color(1), 2, "rigid Coulomb: pads' end")]
    for N, color, width, words in curves:
        ax.line(mu, N, color, width)
        ax.legend(color, words)
    for color, radius, shown in [(BLACK, 6, r.cells),           # filled: held; hollow: dropped
                                 ((255, 255, 255), 4, [c for c in r.cells if not c.held]),
                                 (run_color(3), 2, [c for c in r.cells if c.held != c.coulomb])]:
        ax.markers([c.mu for c in shown], [c.N for c in shown], color, radius)
    ax.legend(BLACK, "simulated cell")
    ax.legend(run_color(3), "differs from Coulomb")
    ax = page.axes(1, 1.0, 0.0, 1e3 * max(r.epsvs), "creep speed of a held block (mm/s) against "
                   "the load m g / (2 mu N)", "m g / (2 mu N)", "u (mm/s)")
    ratio = np.linspace(0.0, 1.0, 200)
    for k, epsv in enumerate(r.epsvs):
        ax.line(ratio, [1e3 * FrictionEnergy.f1_inverse(x, epsv) for x in ratio],
                run_color(2 + 3 * k), 2)
        ax.legend(run_color(2 + 3 * k), f"u*, eps_v = {epsv:g} m/s")
        shown = [p for p in r.points if p.epsv == epsv]
        ax.markers([p.ratio for p in shown], [1e3 * p.u for p in shown], BLACK, 4)
    ax.legend(BLACK, "simulated")
    return page
