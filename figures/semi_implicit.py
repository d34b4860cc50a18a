"""Slide "Approximation: semi-implicit temporal discretization": friction with mu*lambda^n and T^n lagged
from x^n, against the fully implicit friction of Algorithm 5's fixed point (`friction_updates`), on the
lecture's scene and on one where the two differ visibly."""
from types import SimpleNamespace

import numpy as np

import FrictionEnergy
import simulator
from figures.page import Page
from viewer.draw import run_color

SCENES = {"the default scene": {}, "mu 1, h 0.05 s, v0 (5, -5) m/s": {"mu": 1.0, "h": 0.05, "v0": (5.0, -5.0)}}
DURATION = 2.0              # s
FRICTION_UPDATES = 20       # Algorithm 5's cap per step


def trajectory(params, friction_updates, duration):
    """Times t (s), the centre of mass sum m x / sum m at each (steps + 1, 2), and how many steps ended
    with report.friction_converged False."""
    scene = simulator.build_scene(friction_updates=friction_updates, **params)
    records = list(simulator.simulate(scene, round(duration / scene.h)))
    x = np.stack([scene.x0] + [r.x for r in records])
    com = np.einsum("n,snd->sd", scene.m, x) / scene.m.sum()
    t = np.arange(len(x)) * scene.h
    return t, com, sum(not r.report.friction_converged for r in records), FrictionEnergy.tangent(scene.n)


def compute(scenes=SCENES, duration=DURATION, friction_updates=FRICTION_UPDATES):
    """For each scene: the displacement of the centre of mass along the slope, lagged and Algorithm 5,
    and the distance between the two centres of mass over time (gap[-1]: at the end)."""
    out = []
    for label, params in scenes.items():
        t, lagged, _, tangent = trajectory(params, 0, duration)
        _, implicit, unconverged, _ = trajectory(params, friction_updates, duration)
        out.append(SimpleNamespace(label=label, t=t, along_lagged=(lagged - lagged[0]) @ tangent,
                                   along_implicit=(implicit - implicit[0]) @ tangent, unconverged=unconverged,
                                   gap=np.hypot(*(implicit - lagged).T)))
    return SimpleNamespace(scenes=out, friction_updates=friction_updates)


def draw(r):
    """Per scene: along the slope (lagged, Algorithm 5), then the gap between them (mm)."""
    page = Page("Semi-implicit (lagged mu*lambda^n, T^n) against fully implicit friction (Algorithm 5)",
                2 * len(r.scenes), [f"Algorithm 5: at most {r.friction_updates} friction updates per step. "
                                    "Gap: the distance between the two centres of mass."] + [
        f"{s.label}: {1e3 * s.gap[-1]:.3g} mm apart after {s.t[-1]:g} s (largest {1e3 * s.gap.max():.3g} mm); "
        f"Algorithm 5 did not converge in {s.unconverged} of {len(s.t) - 1} steps" for s in r.scenes])
    for i, s in enumerate(r.scenes):
        lo = min(s.along_lagged.min(), s.along_implicit.min())
        hi = max(s.along_lagged.max(), s.along_implicit.max())
        ax = page.axes(2 * i, s.t[-1], lo, hi, f"{s.label}: centre of mass along the slope (m) against time (s)",
                       "t (s)", "s (m)")
        for k, (name, along) in enumerate((("lagged", s.along_lagged), ("Algorithm 5", s.along_implicit))):
            ax.line(s.t, along, run_color(k))
            ax.legend(run_color(k), name)
        ax = page.axes(2 * i + 1, s.t[-1], 0.0, 1e3 * s.gap.max(), f"{s.label}: gap (mm) against time (s)",
                       "t (s)", "gap (mm)")
        ax.line(s.t, 1e3 * s.gap, run_color(3))
        ax.legend(run_color(3), "|com_5 - com_lagged|")
    return page
