"""Slide "Fixed-point iteration (cont.)", Algorithm 5 "converges only when starting sufficiently
close": line 3's measure ||p||_inf / h after each friction update, for a step that converges and
one that does not, from the project's own step."""
from types import SimpleNamespace

import numpy as np

import simulator
import time_integrator
from figures.page import RED, Page
from viewer.pictures.draw import run_color

PARAMS = {"mu": 1.0, "h": 0.05, "v0": (5.0, -5.0), "friction_updates": 20}
STEPS = 40


def line3_measures(scene, x, v, step_index):
    """One step by time_integrator.newton_iterates: (x^{n+1}, v^{n+1}, report, measures), measures
    being line 3's ||p||_inf / h after each friction update j >= 1 (re-solve j's first iterate),
    then report.residual."""
    iterates, first = time_integrator.newton_iterates(scene, x, v, step_index=step_index), {}
    try:
        while True:
            it = next(iterates)
            first.setdefault(it.friction_update, it.residual)
    except StopIteration as done:
        x, v, report = done.value
    return x, v, report, [first[j] for j in sorted(first) if j > 0] + [report.residual]


def compute(params=PARAMS, steps=STEPS):
    """Each as (step index, report, measures): `converging`, the converging step with the most
    tests; `failing`, the first that did not converge (or None); `shown`, those two; `farthest`,
    the converging step with the largest first measure."""
    scene = simulator.build_scene(**params)
    x, v, found = scene.x0, scene.v0, []
    for i in range(steps):
        x, v, report, measures = line3_measures(scene, x, v, i)
        found.append((i, report, np.array(measures)))
    converged = [f for f in found if f[1].friction_converged]
    converging = max(converged, key=lambda f: len(f[2]))
    failing = next((f for f in found if not f[1].friction_converged), None)
    return SimpleNamespace(scene=scene, steps=steps, failed=len(found) - len(converged),
                           converging=converging, failing=failing,
                           shown=[f for f in (converging, failing) if f is not None],
                           farthest=max(converged, key=lambda f: f[2][0]))


def caption(r):
    """The scene, line 3's test, each step drawn, and how close is close enough."""
    p = r.scene.params
    lines = [f"Scene: mu {p['mu']:g}, h {p['h']:g} s, v0 {p['v0']} m/s, friction_updates "
             f"{p['friction_updates']} (at most that many re-solves a step);",
             f"{r.failed} of its first {r.steps} steps did not converge.",
             "After each FrictionUpdate (lines 2, 5: mu*lambda at the new x), line 3 measures "
             "||p||_inf / h at it;",
             "below tol the step ends (report.friction_converged True), else Newton re-solves "
             "(line 4) and it repeats."]
    for i, report, m in r.shown:
        lines.append(f"step {i} (t = {i * p['h']:g} s): {len(m)} tests ({len(m) - 1} re-solves), "
                     f"measure {m[0]:.3g} -> {m[-1]:.3g} m/s, "
                     f"report.friction_converged {report.friction_converged}")
    i, _, m = r.farthest
    return lines + [f"How close is close enough is not line 3's first measure: step {i} starts "
                    f"at {m[0]:.3g} m/s and converges."]


def draw(r):
    """The steps' measures on a log axis against the friction update, with tol."""
    measures = np.concatenate([f[2] for f in r.shown])
    page = Page("Algorithm 5: the fixed-point iteration converges only when starting sufficiently "
                "close", 1, caption(r))
    ax = page.axes(0, max(len(f[2]) for f in r.shown) + 1, min(measures.min(), r.scene.tol) / 2,
                   measures.max() * 2, "line 3's measure ||p||_inf / h (m/s, log) at its j-th test "
                   "in the step (after j - 1 re-solves)", "j", "||p||/h (m/s)", log=True)
    for k, (i, report, m) in enumerate(r.shown):
        j = np.arange(1, len(m) + 1)
        ax.line(j, m, run_color(k))
        ax.markers(j, m, run_color(k))
        ends = "converges" if report.friction_converged else "does not"
        ax.legend(run_color(k), f"step {i}: {ends}")
    ax.hline(r.scene.tol, RED, f"tol = {r.scene.tol:g} m/s")
    return page
