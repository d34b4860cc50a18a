"""Slide "Approximation: semi-implicit temporal discretization": friction with mu*lambda^n and T^n lagged
from x^n, against the fully implicit friction of Algorithm 5's fixed point (`friction_updates`), and
which of the two is nearer the truth: a reference run, Algorithm 5 at h/8 with a tight Newton
tolerance, and the same at h/4, whose distance from the reference is how far the reference moved at
its last halving of h: an estimate of the reference's own error. A mode is called nearer by a measured
margin only where that margin exceeds this estimate.

Two scenes: the lecture's, and a square set on the slope while sliding, its bottom row inside dhat,
where the barrier pushes several times its weight: lambda^n of the first step is not the step's own."""
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
REFERENCE_DIVISOR, CHECK_DIVISOR, REFERENCE_TOL = 8, 4, 1e-6    # the reference: h/8, checked at h/4; tol in m/s
CHECK = f"h/{CHECK_DIVISOR}"     # the check run's name
REFERENCE_COLOR, CHECK_COLOR = (0, 0, 0), (150, 150, 150)
WIDTHS = {"lagged": 6, CHECK: 1}    # px (else 2): lagged wide under Algorithm 5, seen either side
COINCIDE = 0.01     # lagged and Algorithm 5 coincide: this fraction of the top panel's span apart


def sliding_start(d0, speed, **params):
    """Scene parameters for the square set on the slope while sliding: aligned with the slope, its bottom
    row d0 (m) from it, every node moving downhill at `speed` (m/s)."""
    p = {**simulator.DEFAULTS, **params}
    n = np.array(p["slope"], dtype=float) / math.hypot(*p["slope"])
    center = np.array(p["slope_point"], dtype=float) + (d0 + p["side_len"] / 2) * n
    return {**params, "angle": -math.atan2(n[0], n[1]), "center": tuple(center.tolist()),
            "v0": tuple((speed * FrictionEnergy.tangent(n)).tolist())}


SCENES = {"the default scene": {},
          "mu 0.3, h 0.05 s, set on the slope 8 mm from it, sliding at 3 m/s":
              sliding_start(0.008, 3.0, mu=0.3, h=0.05)}


def trajectory(params, friction_updates, duration, divisor=1, tol=None):
    """Run the scene at h / divisor (and Newton tolerance tol, if given): times t (s), the centre of mass
    sum m x / sum m at each (steps + 1, 2), how many steps ended with report.friction_converged False,
    and the slope's downhill tangent."""
    h = params.get("h", simulator.DEFAULTS["h"]) / divisor
    scene = simulator.build_scene(**{**params, "friction_updates": friction_updates, "h": h,
                                     **({} if tol is None else {"tol": tol})})
    records = list(simulator.simulate(scene, round(duration / scene.h)))
    x = np.stack([scene.x0] + [r.x for r in records])
    com = np.einsum("n,snd->sd", scene.m, x) / scene.m.sum()
    t = np.arange(len(x)) * scene.h
    return t, com, sum(not r.report.friction_converged for r in records), FrictionEnergy.tangent(scene.n)


def start_load(params):
    """The barrier's push on the square at its start, sum of lambda_k(x^0), over its weight's normal part."""
    scene = simulator.build_scene(**params)
    lam = BarrierEnergy.compute_mu_lambda(scene.x0, scene.n, scene.o, scene.contact_area, 1.0, scene.dhat,
                                          scene.kappa)
    return float(lam.sum() / (scene.m.sum() * -(scene.g @ scene.n)))


def verdict(lagged, implicit, own_error):
    """Which run ends nearer the reference, given the two distances from it at the end and the
    reference's own error there: (name, margin, measured), measured meaning margin > own_error."""
    nearer = "lagged" if lagged < implicit else "Algorithm 5"
    margin = abs(lagged - implicit)
    return nearer, margin, margin > own_error


def compute(scenes=SCENES, duration=DURATION, friction_updates=FRICTION_UPDATES):
    """For each scene: the centre of mass's displacement along the slope, lagged, Algorithm 5, the
    reference (Algorithm 5 at h/8, tol REFERENCE_TOL) and its check (the same at h/4); the distances of
    the centres of mass from the reference's at the steps of h (from_reference[name], [-1]: at the end),
    the check's being the reference's own error; the gap between lagged and Algorithm 5; and the
    verdict at the end."""
    out = []
    for label, params in scenes.items():
        t, lagged, _, tangent = trajectory(params, 0, duration)
        _, implicit, unconverged, _ = trajectory(params, friction_updates, duration)
        t_ref, reference, unconverged_ref, _ = trajectory(params, friction_updates, duration,
                                                          REFERENCE_DIVISOR, REFERENCE_TOL)
        t_check, check, unconverged_check, _ = trajectory(params, friction_updates, duration,
                                                          CHECK_DIVISOR, REFERENCE_TOL)
        on_t = reference[::REFERENCE_DIVISOR]                       # the reference at the times t
        runs = {"lagged": lagged, "Algorithm 5": implicit, CHECK: check[::CHECK_DIVISOR]}
        far = {name: np.hypot(*(com - on_t).T) for name, com in runs.items()}
        along = {name: (com - com[0]) @ tangent for name, com in
                 (("lagged", lagged), ("Algorithm 5", implicit), ("reference", reference), (CHECK, check))}
        out.append(SimpleNamespace(
            label=label, t=t, t_ref=t_ref, t_check=t_check, along=along, from_reference=far,
            gap=np.hypot(*(implicit - lagged).T), unconverged=unconverged,
            unconverged_reference=unconverged_ref + unconverged_check, start_load=start_load(params),
            verdict=verdict(far["lagged"][-1], far["Algorithm 5"][-1], far[CHECK][-1])))
    return SimpleNamespace(scenes=out, friction_updates=friction_updates)


def span(s):
    """The range of a scene's top panel, m: from the lowest to the highest s of its four runs."""
    return max(a.max() for a in s.along.values()) - min(a.min() for a in s.along.values())


def apart(s):
    """A caption line: how far apart lagged and Algorithm 5 come over the run, and whether they
    coincide in the top panel (at most COINCIDE of its span apart)."""
    most, share = s.gap.max(), s.gap.max() / span(s)
    if share <= COINCIDE:
        return (f"    lagged and Algorithm 5 coincide to within {1e3 * most:.3g} mm over the run "
                f"({100 * share:.2g} % of the top panel's span; lagged drawn wide, under).")
    return f"    lagged and Algorithm 5 come up to {1e3 * most:.3g} mm apart over the run."


def caption(r):
    """The caption's lines: what the reference is, then per scene the distances at the end and the verdict."""
    lines = [f"Black: the reference, Algorithm 5 at h/{REFERENCE_DIVISOR} with Newton tol {REFERENCE_TOL:g} m/s; grey: "
             f"the same at {CHECK}, how far the reference",
             "moved at its last halving of h (an estimate of its own error). Algorithm 5: at most "
             f"{r.friction_updates} friction updates per step."]
    for s in r.scenes:
        mm = {name: 1e3 * far[-1] for name, far in s.from_reference.items()}
        nearer, margin, measured = s.verdict
        start = (f"at the start the barrier pushes {s.start_load:.2g} times its weight" if s.start_load > 0
                 else "starting in the air")
        lines += [f"{s.label} ({start}): after {s.t[-1]:g} s,",
                  f"    from the reference: lagged {mm['lagged']:.3g} mm, Algorithm 5 {mm['Algorithm 5']:.3g} mm, "
                  f"the {CHECK} run {mm[CHECK]:.3g} mm (lagged and Algorithm 5: {1e3 * s.gap[-1]:.3g} mm apart);",
                  f"    {nearer} is nearer by {1e3 * margin:.3g} mm, " + (
                      "more than the reference's own error." if measured else
                      "less than the reference's own error: not a measured difference."), apart(s)]
        if min(mm["lagged"], mm["Algorithm 5"]) > 1e3 * s.gap[-1]:
            lines.append("    Both are farther from the reference than from each other: the time step's error outweighs"
                         " the lagging's.")
        lines += [f"    Algorithm 5 did not converge in {s.unconverged} of {len(s.t) - 1} steps (the reference"
                  f" and its check: in {s.unconverged_reference})."]
    return lines


def draw(r):
    """Per scene: along the slope (lagged, Algorithm 5, the reference and its check), then each one's
    distance from the reference (mm)."""
    page = Page("Semi-implicit (lagged mu*lambda^n, T^n) against fully implicit friction (Algorithm 5)",
                2 * len(r.scenes), caption(r))
    looks = {"lagged": run_color(0), "Algorithm 5": run_color(1), "reference": REFERENCE_COLOR, CHECK: CHECK_COLOR}
    for i, s in enumerate(r.scenes):
        times = {"lagged": s.t, "Algorithm 5": s.t, "reference": s.t_ref, CHECK: s.t_check}
        lo = min(along.min() for along in s.along.values())
        hi = max(along.max() for along in s.along.values())
        ax = page.axes(2 * i, s.t[-1], lo, hi, f"{s.label}: centre of mass along the slope (m) against time (s)",
                       "t (s)", "s (m)")
        for name in (CHECK, "reference", "lagged", "Algorithm 5"):      # the runs at h drawn on top
            ax.line(times[name], s.along[name], looks[name], WIDTHS.get(name, 2))
        for name in ("lagged", "Algorithm 5", "reference", CHECK):
            ax.legend(looks[name], {"reference": f"reference (h/{REFERENCE_DIVISOR})"}.get(name, name))
        ax = page.axes(2 * i + 1, s.t[-1], 0.0, 1e3 * max(far.max() for far in s.from_reference.values()),
                       f"{s.label}: distance from the reference (mm) against time (s)", "t (s)", "mm")
        for name in (CHECK, "lagged", "Algorithm 5"):
            ax.line(s.t, 1e3 * s.from_reference[name], looks[name], WIDTHS.get(name, 2))
        for name in ("lagged", "Algorithm 5", CHECK):
            ax.legend(looks[name], f"{CHECK}: own error" if name == CHECK else name)
    return page
