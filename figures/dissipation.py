"""Slide "Properties of dry friction": kinetic energy turns into heat, never back. Friction's power
in the surface's frame, P = -(surface_work - friction_work) / h (StepReport's), is <= 0 at every
step; on the lecture's still slope (surface_work = 0) it is friction_work / h."""
from types import SimpleNamespace

import numpy as np

import simulator
from figures.page import RED, Page
from viewer.pictures.draw import run_color

MUS = (0.1, 0.11, 0.2)      # the lecture's mu comparison; mu = 0.11 is the default scene
DURATION = 6.0              # s, as long as `python simulator.py --mu 0.1,0.11,0.2` runs


def power(mu, duration):
    """The scene at mu: t (s), P = W / h (W), its round-off bound (W), the steps above it (`beyond`)
    and the work so far W(t) (J). W = sum_k F_k . d_k <= 0 in exact arithmetic, the work in the
    surface's frame; in float64 it is off by at most (2N + 8) eps sum_k |F_k| |d_k| (Higham, 3.1),
    F the step's StepReport.friction_force, d_k = x_k^{n+1} - x_k^n (the still slope's frame)."""
    scene = simulator.build_scene(mu=mu)
    t, P, bound, x_n, eps = [], [], [], scene.x0, np.finfo(float).eps
    for record in simulator.simulate(scene, round(duration / scene.h)):
        F, d = record.report.friction_force, record.x - x_n
        t.append(record.t)
        P.append((record.report.friction_work - record.report.surface_work) / scene.h)
        bound.append((2 * len(d) + 8) * eps * np.hypot(*F.T) @ np.hypot(*d.T) / scene.h)
        x_n = record.x
    P, bound = np.array(P), np.array(bound)
    return SimpleNamespace(mu=mu, t=np.array(t), P=P, bound=bound, W=np.cumsum(P * scene.h),
                           beyond=np.flatnonzero(P > bound))


def compute(mus=MUS, duration=DURATION):
    """power's run at each mu."""
    return SimpleNamespace(runs=[power(mu, duration) for mu in mus])


def draw(r):
    """P against t for every mu, steps beyond round-off ringed in red; W(t) below."""
    t_max = max(run.t[-1] for run in r.runs)
    bound = max(run.bound.max() for run in r.runs)
    default_mu = simulator.DEFAULTS["mu"]
    caption = ["P = -(surface_work - friction_work) / h (StepReport's): friction's power in the "
               "surface's frame, here the still slope's,",
               f"at every step of the lecture's mu comparison (its first 3 s at mu = "
               f"{default_mu:g} are the default run).",
               f"Round-off bound per step (dissipation.power): (2N + 8) eps sum_k |F_k| |d_k| / h, "
               f"at most {bound:.2g} W; P = 0 where no node touches."]
    for run in r.runs:
        name = " (the default scene)" if run.mu == default_mu else ""
        caption.append(f"mu = {run.mu:g}{name}: P from {run.P.min():.4g} to {run.P.max():.3g} W; "
                       f"{len(run.beyond)} of {len(run.P)} steps above round-off; "
                       f"W = {run.W[-1]:.4g} J")
    page = Page("Friction turns kinetic energy into heat, never back: its power P <= 0 in the "
                "surface's frame", 2, caption)
    P_lo, P_hi = min(run.P.min() for run in r.runs), max(0.0, *(run.P.max() for run in r.runs))
    top = page.axes(0, t_max, P_lo, P_hi, "friction's power P (W) in the surface's frame at every "
                    "step, against time (s)", "t (s)", "P (W)")
    top.hline(0.0, (0, 0, 0), "P = 0")
    bottom = page.axes(1, t_max, min(run.W.min() for run in r.runs) / 1e3, 0.0,
                       "friction's work so far W (kJ), against time (s): it only falls", "t (s)",
                       "W (kJ)")
    for k, run in enumerate(r.runs):
        for ax, y, width in ((top, run.P, 1), (bottom, run.W / 1e3, 2)):
            ax.line(run.t, y, run_color(k), width)
            ax.legend(run_color(k), f"mu = {run.mu:g}")
        top.markers(run.t[run.beyond], run.P[run.beyond], RED, 5)
    top.legend(RED, f"P > round-off: {sum(len(run.beyond) for run in r.runs)} steps")
    return page
