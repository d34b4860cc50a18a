"""Slide "Properties of dry friction": kinetic energy is always turned into heat, never back. Friction's
power P = W / h at every step, W the step's friction work (StepReport.friction_work), must be <= 0."""
from types import SimpleNamespace

import numpy as np

import simulator
from figures.page import RED, Page
from viewer.pictures.draw import run_color

MUS = (0.1, 0.11, 0.2)      # the lecture's mu comparison; mu = 0.11 is the default scene
DURATION = 6.0              # s, as long as `python simulator.py --mu 0.1,0.11,0.2` runs


def power(scene, steps):
    """t (s), P = W / h (W) and its round-off bound (W) at every step.

    W = sum_k F_k . d_k, F_k = -grad_k P_f the friction force, d_k = x_k^{n+1} - x_k^n. Each term is
    -mu lambda_k f1(|u_k|) / |u_k| u_k (t . d_k) with u_k = t . d_k / h: <= 0 in exact arithmetic. In
    float64 a dot product of 2N products is off by at most 2N eps sum |F_k,i d_k,i| (Higham, Accuracy and
    Stability of Numerical Algorithms, 3.1), and F_k and u_k carry a few roundings each: a computed
    P above bound = (2N + 8) eps sum_k |F_k| |d_k| / h is physics, not round-off. F is the step's own
    friction force (StepReport.friction_force: mu lambda^n at x^n when friction_updates is 0)."""
    t, P, bound, x_n = [], [], [], scene.x0
    for record in simulator.simulate(scene, steps):
        F, d = record.report.friction_force, record.x - x_n
        t.append(record.t)
        P.append(record.report.friction_work / scene.h)
        bound.append((2 * len(d) + 8) * np.finfo(float).eps * np.hypot(*F.T) @ np.hypot(*d.T) / scene.h)
        x_n = record.x
    return np.array(t), np.array(P), np.array(bound)


def compute(mus=MUS, duration=DURATION):
    """Per mu: t, P, the bound, the steps above it (`beyond`) and the work done so far W(t) (J)."""
    runs = []
    for mu in mus:
        scene = simulator.build_scene(mu=mu)
        t, P, bound = power(scene, round(duration / scene.h))
        runs.append(SimpleNamespace(mu=mu, t=t, P=P, bound=bound, beyond=np.flatnonzero(P > bound),
                                    W=np.cumsum(P * scene.h)))
    return SimpleNamespace(runs=runs, default_mu=simulator.DEFAULTS["mu"])


def draw(r):
    """P against t for every mu, steps beyond round-off ringed in red; W(t) below."""
    t_max = max(run.t[-1] for run in r.runs)
    page = Page("Friction takes kinetic energy out and never gives it back: its power P <= 0", 2, [
        "P = StepReport.friction_work / h at every step of the lecture's mu comparison (its first 3 s at mu = "
        f"{r.default_mu:g} are the default run).", "Round-off bound per step (dissipation.power): (2N + 8) eps sum_k "
        f"|F_k| |d_k| / h, at most {max(run.bound.max() for run in r.runs):.2g} W; P = 0 where no node touches."] + [
        f"mu = {run.mu:g}{' (the default scene)' if run.mu == r.default_mu else ''}: P from {run.P.min():.4g} "
        f"to {run.P.max():.3g} W; {len(run.beyond)} of {len(run.P)} steps above round-off; W = {run.W[-1]:.4g} J"
        for run in r.runs])
    ax = page.axes(0, t_max, min(run.P.min() for run in r.runs), max(0.0, max(run.P.max() for run in r.runs)),
                   "friction's power P (W) at every step, against time (s)", "t (s)", "P (W)")
    ax.hline(0.0, (0, 0, 0), "P = 0")
    for k, run in enumerate(r.runs):
        ax.line(run.t, run.P, run_color(k), 1)
        ax.legend(run_color(k), f"mu = {run.mu:g}")
        page.markers(ax, run.t[run.beyond], run.P[run.beyond], RED, 5)
    ax.legend(RED, f"P > round-off: {sum(len(run.beyond) for run in r.runs)} steps")
    ax = page.axes(1, t_max, min(run.W.min() for run in r.runs) / 1e3, 0.0,
                   "friction's work so far W (kJ), against time (s): it only falls", "t (s)", "W (kJ)")
    for k, run in enumerate(r.runs):
        ax.line(run.t, run.W / 1e3, run_color(k))
        ax.legend(run_color(k), f"mu = {run.mu:g}")
    return page
