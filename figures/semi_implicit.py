"""Slide "Approximation: semi-implicit temporal discretization": friction with mu*lambda^n and T^n
lagged from x^n, against Algorithm 5's fully implicit friction, each measured from a reference run
(Algorithm 5 at h/8, tight tol). The same at h/4 estimates the reference's own error: a mode is
called nearer by a measured margin only where the margin exceeds it. Two scenes: the lecture's,
and a square set sliding on the slope inside dhat: the first step's lambda^n is not its own."""
import math
from types import SimpleNamespace

import numpy as np

import BarrierEnergy
import FrictionEnergy
import simulator
from figures.page import Page
from viewer.pictures.draw import run_color

DURATION = 2.0              # s
FRICTION_UPDATES = 20       # Algorithm 5's cap per step
REFERENCE_DIVISOR, CHECK_DIVISOR, REFERENCE_TOL = 8, 4, 1e-6    # h/8, checked at h/4; tol m/s
CHECK = f"h/{CHECK_DIVISOR}"     # the check run's name
RUNS = {"lagged": (1, None), "Algorithm 5": (1, None),        # name: (divisor of h, Newton tol)
        "reference": (REFERENCE_DIVISOR, REFERENCE_TOL), CHECK: (CHECK_DIVISOR, REFERENCE_TOL)}
LOOKS = {"lagged": (run_color(0), 6), "Algorithm 5": (run_color(1), 2),    # (colour, width px):
         "reference": ((0, 0, 0), 2), CHECK: ((150, 150, 150), 1)}  # lagged wide, under Algorithm 5
COINCIDE = 0.01     # lagged and Algorithm 5 coincide: this fraction of the top panel's span apart


def sliding_start(d0, speed, **params):
    """Scene parameters for the square aligned with the slope, its bottom row d0 (m) from it, every
    node moving downhill at `speed` (m/s)."""
    p = {**simulator.DEFAULTS, **params}
    n = np.array(p["slope"], dtype=float) / math.hypot(*p["slope"])
    center = np.array(p["slope_point"], dtype=float) + (d0 + p["side_len"] / 2) * n
    return {**params, "angle": -math.atan2(n[0], n[1]), "center": tuple(center.tolist()),
            "v0": tuple((speed * FrictionEnergy.tangent(n)).tolist())}


SCENES = {"the default scene": {},
          "mu 0.3, h 0.05 s, set on the slope 8 mm from it, sliding at 3 m/s":
              sliding_start(0.008, 3.0, mu=0.3, h=0.05)}


def trajectory(params, friction_updates, duration, divisor=1, tol=None):
    """The scene at h / divisor (and Newton tol, if given): times t (s), the centre of mass at each
    (steps + 1, 2), and how many steps ended with report.friction_converged False."""
    h = params.get("h", simulator.DEFAULTS["h"]) / divisor
    scene = simulator.build_scene(**{**params, "friction_updates": friction_updates, "h": h,
                                     **({} if tol is None else {"tol": tol})})
    records = list(simulator.simulate(scene, round(duration / scene.h)))
    x = np.stack([scene.x0] + [r.x for r in records])
    return SimpleNamespace(t=np.arange(len(x)) * scene.h,
                           com=np.einsum("n,snd->sd", scene.m, x) / scene.m.sum(),
                           unconverged=sum(not r.report.friction_converged for r in records))


def compute(scenes=SCENES, duration=DURATION, friction_updates=FRICTION_UPDATES):
    """Per scene, the RUNS and their centres of mass along the slope; the distances from the
    reference at the steps of h (from_reference[name], the check's: the reference's own error);
    the gap between lagged and Algorithm 5; the verdict at the end: (nearer, margin, measured);
    start_load, the barrier's push sum_k lambda_k(x^0) over the weight's normal part."""
    out = []
    for label, params in scenes.items():
        scene = simulator.build_scene(**params)
        lam = BarrierEnergy.compute_mu_lambda(scene.x0, scene.n, scene.o, scene.contact_area, 1.0,
                                              scene.dhat, scene.kappa)     # lambda_k(x^0)
        runs = {name: trajectory(params, 0 if name == "lagged" else friction_updates, duration,
                                 divisor, tol) for name, (divisor, tol) in RUNS.items()}
        tangent = FrictionEnergy.tangent(scene.n)
        along = {name: (run.com - run.com[0]) @ tangent for name, run in runs.items()}
        reference = runs["reference"].com[::REFERENCE_DIVISOR]      # at the times of h
        far = {name: np.hypot(*(runs[name].com[::divisor] - reference).T)
               for name, (divisor, _) in RUNS.items() if name != "reference"}
        lagged, implicit, own_error = (far[name][-1] for name in ("lagged", "Algorithm 5", CHECK))
        margin = abs(lagged - implicit)
        nearer = "lagged" if lagged < implicit else "Algorithm 5"
        out.append(SimpleNamespace(
            label=label, runs=runs, t=runs["lagged"].t, along=along, from_reference=far,
            gap=np.hypot(*(runs["Algorithm 5"].com - runs["lagged"].com).T),
            start_load=float(lam.sum() / (scene.m.sum() * -(scene.g @ scene.n))),
            verdict=(nearer, margin, margin > own_error)))
    return SimpleNamespace(scenes=out, friction_updates=friction_updates)


def span(s):
    """The range of a scene's top panel (m): its runs' lowest to highest s."""
    return max(a.max() for a in s.along.values()) - min(a.min() for a in s.along.values())


def caption(r):
    """What the reference is, then per scene the distances at the end and the verdict."""
    lines = [f"Black: the reference, Algorithm 5 at h/{REFERENCE_DIVISOR} with Newton tol "
             f"{REFERENCE_TOL:g} m/s; grey: the same at {CHECK}, how far the reference",
             "moved at its last halving of h (an estimate of its own error). Algorithm 5: at most "
             f"{r.friction_updates} friction updates per step."]
    for s in r.scenes:
        mm = {name: 1e3 * far[-1] for name, far in s.from_reference.items()}
        nearer, margin, measured = s.verdict
        start = (f"at the start the barrier pushes {s.start_load:.2g} times its weight"
                 if s.start_load > 0 else "starting in the air")
        most, share = 1e3 * s.gap.max(), s.gap.max() / span(s)
        lines += [f"{s.label} ({start}): after {s.t[-1]:g} s,",
                  f"    from the reference: lagged {mm['lagged']:.3g} mm, Algorithm 5 "
                  f"{mm['Algorithm 5']:.3g} mm, the {CHECK} run {mm[CHECK]:.3g} mm "
                  f"(lagged and Algorithm 5: {1e3 * s.gap[-1]:.3g} mm apart);",
                  f"    {nearer} is nearer by {1e3 * margin:.3g} mm, " + (
                      "more than the reference's own error." if measured else
                      "less than the reference's own error: not a measured difference."),
                  f"    lagged and Algorithm 5 coincide to within {most:.3g} mm over the run "
                  f"({100 * share:.2g} % of the top panel's span; lagged drawn wide, under)."
                  if share <= COINCIDE else
                  f"    lagged and Algorithm 5 come up to {most:.3g} mm apart over the run."]
        if min(mm["lagged"], mm["Algorithm 5"]) > 1e3 * s.gap[-1]:
            lines.append("    Both are farther from the reference than from each other: the time "
                         "step's error outweighs the lagging's.")
        checks = s.runs["reference"].unconverged + s.runs[CHECK].unconverged
        lines.append(f"    Algorithm 5 did not converge in {s.runs['Algorithm 5'].unconverged} of "
                     f"{len(s.t) - 1} steps (the reference and its check: in {checks}).")
    return lines


def draw(r):
    """Per scene: the runs along the slope, then each one's distance from the reference (mm)."""
    page = Page("Semi-implicit (lagged mu*lambda^n, T^n) against fully implicit friction "
                "(Algorithm 5)", 2 * len(r.scenes), caption(r))
    for i, s in enumerate(r.scenes):
        lo = min(a.min() for a in s.along.values())
        ax = page.axes(2 * i, s.t[-1], lo, lo + span(s), f"{s.label}: centre of mass along the "
                       "slope (m) against time (s)", "t (s)", "s (m)")
        for name in (CHECK, "reference", "lagged", "Algorithm 5"):      # the runs at h on top
            ax.line(s.runs[name].t, s.along[name], *LOOKS[name])
        for name in ("lagged", "Algorithm 5", "reference", CHECK):
            ax.legend(LOOKS[name][0], f"reference (h/{REFERENCE_DIVISOR})" if name == "reference"
                      else name)
        top = 1e3 * max(far.max() for far in s.from_reference.values())
        ax = page.axes(2 * i + 1, s.t[-1], 0.0, top, f"{s.label}: distance from the reference (mm) "
                       "against time (s)", "t (s)", "mm")
        for name in (CHECK, "lagged", "Algorithm 5"):
            ax.line(s.t, 1e3 * s.from_reference[name], *LOOKS[name])
        for name in ("lagged", "Algorithm 5", CHECK):
            ax.legend(LOOKS[name][0], f"{CHECK}: own error" if name == CHECK else name)
    return page
