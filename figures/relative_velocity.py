"""Slide "Tangential Relative Velocity": friction acts on v_p - v_s, so it pulls the dish toward the
cloth's velocity. The tablecloth trick: pulled fast, the dish barely moves; slowly, it rides along
(scenes.tablecloth.travel)."""
import math
from types import SimpleNamespace

import numpy as np

import simulator
from analysis import diagnostics
from figures.page import BLACK, GREY, Page
from scenes import tablecloth
from viewer.pictures.draw import run_color

SPEEDS = (0.5, 1.0, 1.25, 1.6, 2.0, 2.5, 4.0, 5.0, 8.0)    # U (m/s), across sqrt(mu g L) = 1.4;
#   L / U a whole number of steps: a pull ending inside a step drives the dish for all of it, and
#   its travel is then (ceil(T / h) h / T)^2 - 1 longer (4 % at 6 m/s)
SLOW, FAST = 1.0, 4.0           # the pulls whose speeds are drawn over time
LONGEST = 10.0                  # s: a run that has not stopped by then ends there
RIDES = 0.05                    # a dish that travels L to within 5 % rode along with the cloth


def pull(U):
    """A pull at speed U, run until the dish stops after the cloth has: at each step t, the dish's
    speed v_p (its centre of mass's, along the pull) and the cloth's v_s; the dish's travel, its
    closed form (scenes.tablecloth.travel) and the relative error."""
    scene = simulator.build_tablecloth_scene(pull_speed=U)
    p, tangent = scene.params, scene.surface.tangent
    cloth_stops = p["t_pull"] + p["pull_length"] / U
    t, v_p, v_s = [0.0], [0.0], [0.0]
    for record in simulator.simulate(scene, round(LONGEST / scene.h)):
        t.append(record.t)
        v_p.append(diagnostics.centre_of_mass(scene, record.v) @ tangent)
        v_s.append(scene.surface_velocity(record.t) @ tangent)
        if record.t > cloth_stops and np.abs(record.v).max() < scene.epsv:
            break
    travel = float(diagnostics.centre_of_mass(scene, record.x - scene.x0) @ tangent)
    closed = tablecloth.travel(U, p["pull_length"], scene.mu, -scene.g[1])
    return SimpleNamespace(U=U, t=np.array(t), v_p=np.array(v_p), v_s=np.array(v_s),
                           travel=travel, closed=closed, error=travel / closed - 1.0)


def compute(speeds=SPEEDS):
    """Each pull's run and closed-form travel; the crossover sqrt(mu g L) and the measured bracket
    around it: the fastest pull the dish rode along with, the slowest that outran it."""
    p = simulator.TABLECLOTH
    mu, g, L = p["mu"], -p["gravity"][1], p["pull_length"]
    runs = [pull(U) for U in speeds]
    rode = [run.U for run in runs if abs(run.travel / L - 1.0) <= RIDES]
    outran = [run.U for run in runs if abs(run.travel / L - 1.0) > RIDES]
    return SimpleNamespace(runs=runs, mu=mu, g=g, L=L, crossover=math.sqrt(mu * g * L),
                           bracket=(max(rode, default=None), min(outran, default=None)))


def caption(r):
    """The lecture's words, the scene's numbers and the measured agreement, one line each."""
    worst = max(r.runs, key=lambda run: abs(run.error))
    return [
        "Friction acts on the relative velocity v_p - v_s: it pulls the dish toward the cloth's "
        "velocity (here it speeds the dish up).",
        f"The dish accelerates at mu g (mu = {r.mu:g}) while the cloth, pulled L = {r.L:g} m at U, "
        "outruns it: it travels mu g L^2 / U^2 in all;",
        f"below U = sqrt(mu g L) = {r.crossover:.2f} m/s it catches the cloth and rides along: L. "
        f"Rode along up to {r.bracket[0]:g} m/s, outran from {r.bracket[1]:g} m/s.",
        f"Simulated travel on the closed form (scenes.tablecloth.travel) to within "
        f"{100 * abs(worst.error):.2g} % at every U (the most at U = {worst.U:g} m/s)."]


def draw(r):
    """The travel against U (log) on the closed form's two branches; v_p and v_s over time."""
    page = Page("Friction pulls the dish toward the cloth's velocity: the tablecloth trick", 2,
                caption(r))
    U_max = 1.05 * max(run.U for run in r.runs)
    ax = page.axes(0, U_max, 1e-2, 2 * r.L, "the dish's travel (m, log) against the pull speed U "
                   "(m/s)", "U (m/s)", "travel (m)", log=True)
    U = np.union1d(np.linspace(0.0, U_max, 400), [r.crossover])
    closed = np.array([tablecloth.travel(u, r.L, r.mu, r.g) for u in U])
    for k, (branch, name) in enumerate(((U <= r.crossover, "L: it rides along"),
                                        (U >= r.crossover, "mu g L^2 / U^2: outrun"))):
        ax.line(U[branch], closed[branch], run_color(k), 3)
        ax.legend(run_color(k), name)
    ax.vline(r.crossover, GREY, f"sqrt(mu g L) = {r.crossover:.2f} m/s")
    ax.markers([run.U for run in r.runs], [run.travel for run in r.runs], BLACK, 4)
    ax.legend(BLACK, "simulated")
    shown = [run for run in r.runs if run.U in (SLOW, FAST)]
    ax = page.axes(1, max(run.t[-1] for run in shown), 0.0, FAST,
                   "speeds along the pull (m/s) against time (s): the cloth's v_s, the dish's v_p",
                   "t (s)", "v (m/s)")
    for k, run in enumerate(shown):
        ax.line(run.t, run.v_s, run_color(k + 2), 1)
        ax.legend(run_color(k + 2), f"U = {run.U:g}: cloth v_s (thin)")
        ax.line(run.t, run.v_p, run_color(k + 2), 3)
        ax.legend(run_color(k + 2), f"U = {run.U:g}: dish v_p (thick)")
    return page
