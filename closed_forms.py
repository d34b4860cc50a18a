"""The closed-form cases: their scenes, their exact answers, and how a run is measured against them.

Shared by tests/physics/test_accuracy.py (which asserts) and benchmarks/error_vs_runtime.py (which reports),
so both measure the same thing the same way; a module of its own, so that neither a test imports a
benchmark nor a benchmark a test.

- Sliding and sticking: a nearly rigid square (spring stiffness STIFF_K) starts at rest with its
  bottom edge on the slope, at the pose where the barrier carries its weight (`resting_scene`).
  Sliding (mu < tan theta): the centre of mass accelerates along the slope at
  g (sin theta - mu cos theta). Sticking (mu > tan theta): Coulomb friction holds it still; the
  mollified friction lets it creep at `creep_speed`, below eps_v.
- Free fall without a slope: the centre of mass follows x0 + v0 t + 1/2 g t^2.
- The full scene (the lecture's drop, impact and slide) has no closed form; it is measured
  against a run with a much smaller time step.
"""
import math
from dataclasses import dataclass

import numpy as np
import scipy.optimize

import BarrierEnergy
import FrictionEnergy
import simulator

# Spring stiffness of the closed-form cases. The lecture's k = 2e4 holding 1000 kg is very soft: under
# its own weight the square sags by 2 cm and oscillates, which no rigid-block formula describes.
# At 1e8 it deforms by 5e-6 m under its weight, so it is a rigid block for the formulas, and implicit
# Euler (unconditionally stable) takes it at every h of the sweep.
STIFF_K = 1e8

LECTURE_TAN = 0.1                           # the lecture's slope, normal (0.1, 1)
STEEP_TAN = math.tan(math.radians(20.0))    # the steeper slope of the tests: 20 degrees, tan 0.364


def slope_normal(tan_theta):
    """Unit normal (sin theta, cos theta) of a slope descending to the right at tan(theta)."""
    theta = math.atan(tan_theta)
    return (math.sin(theta), math.cos(theta))


def downhill(scene):
    """Unit tangent of the slope pointing downhill, (n_y, -n_x)."""
    return FrictionEnergy.tangent(scene.n)


def com(scene, x):
    """Centre of mass of positions (or velocities) x."""
    return np.average(x, axis=0, weights=scene.m)


def _loads(scene):
    """Normal load N, downhill drive G_t and the friction force F the slope must supply at rest or
    while sliding (F = G_t if mu N can hold it, else mu N), all for the whole square, in newtons."""
    total = float(np.sum(scene.m))
    normal_load = -total * float(scene.g @ scene.n)
    drive = total * float(scene.g @ downhill(scene))
    return normal_load, drive, min(drive, scene.mu * normal_load)


def sliding_acceleration(scene):
    """Rigid block, Coulomb friction: a = g (sin theta - mu cos theta) along the downhill tangent."""
    normal_load, drive, _ = _loads(scene)
    return (drive - scene.mu * normal_load) / float(np.sum(scene.m))


def creep_speed(scene):
    """Steady creep of a sticking block under the lecture's mollifier f1(y) = 2y/eps_v - y^2/eps_v^2:
    friction mu N f1(v) balances the drive m g sin theta where f1(v) = tan(theta)/mu, so
    v = eps_v (1 - sqrt(1 - tan(theta)/mu)), always below eps_v. Implicit Euler reproduces it exactly
    once the velocity is steady (it is a force balance at constant velocity)."""
    normal_load, drive, _ = _loads(scene)
    ratio = drive / (scene.mu * normal_load)
    if not 0.0 <= ratio < 1.0:
        raise ValueError(f"no creep: tan(theta)/mu = {ratio:.3g} is not in [0, 1) (the block slides)")
    return scene.epsv * (1.0 - math.sqrt(1.0 - ratio))


def barrier_force(scene, d):
    """Normal force of the barrier on a bottom node at distance d: -w dhat b'(d) for d < dhat, else 0."""
    d = np.asarray(d, dtype=np.float64)
    inside = np.minimum(d, scene.dhat)
    return np.where(d < scene.dhat,
                    -BarrierEnergy.dP_dd(inside, scene.contact_area[0], scene.dhat, scene.kappa), 0.0)


def _bracketed_root(f, lo, hi):
    return scipy.optimize.brentq(f, lo, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=500)


def resting_pose(scene):
    """Distance d0 of the bottom edge's midpoint from the slope and the tilt s = sin(-beta) of the edge
    (beta: its rotation away from the slope, counter-clockwise positive) at which the barrier carries a
    rigid square at rest, or sliding steadily, without rocking:

        sum_i f_i = N,   f_i = f(d0 - s r_i)                  (normal forces)
        sum_i r_i f_i = (side/2) N tan(gamma - beta)          (moments about the centre of mass)

    f: barrier force per bottom node (`barrier_force`); r_i: the node's position along the edge,
    downhill positive; N, F: normal load and friction force at the base (`_loads`), tan(gamma) = F/N.
    The moment equation is that of the normal forces f_i and the friction forces (F/N) f_i (sliding:
    mu f_i; sticking: every node creeps at the same speed, so mu f1(v) f_i) at the tilted nodes. F acts
    half a side below the centre of mass and tips the square downhill, so the downhill nodes sit
    deeper (s > 0). With an edge parallel to the slope instead, the square rocks onto this pose in its
    first steps and its centre of mass moves by ~1e-4 m. Solved by bisection (brentq): d0 for a given
    s (the load falls monotonically with d0), then s (the moment excess grows with it)."""
    normal_load, _, friction = _loads(scene)
    side, n_seg = scene.params["side_len"], scene.params["n_seg"]
    r = -side / 2 + np.arange(n_seg + 1) * side / n_seg
    reach = float(np.abs(r).max())

    def d0_for(s):
        # from the deepest node touching the slope (infinite force) to every node beyond dhat (none)
        return _bracketed_root(lambda d0: barrier_force(scene, d0 - s * r).sum() - normal_load,
                               s * reach * (1 + 1e-12) + 1e-15, scene.dhat + s * reach)

    def moment_excess(s):
        lever = side / 2 * math.tan(math.atan2(friction, normal_load) + math.asin(s))
        return r @ barrier_force(scene, d0_for(s) - s * r) - lever * normal_load

    if friction <= 0.0:
        return d0_for(0.0), 0.0
    s_hi = 1e-6
    while moment_excess(s_hi) < 0.0:
        s_hi *= 2.0
        if s_hi > 0.5:
            raise ValueError("no resting pose: the friction force would tip the square over")
    s = _bracketed_root(moment_excess, 0.0, s_hi)
    return d0_for(s), s


def resting_scene(tan_theta, mu, k=STIFF_K, **overrides):
    """A square at rest on a slope of tan(theta) (descending to the right, through the default o), its
    bottom edge on the slope at the pose of `resting_pose`, so no settling is needed."""
    overrides = {"slope": slope_normal(tan_theta), "mu": mu, "k": k, **overrides}
    probe = simulator.build_scene(**{**overrides, "center": (0.0, 10.0)})   # masses, loads, barrier
    d0, tilt = resting_pose(probe)
    theta = math.atan2(probe.n[0], probe.n[1])
    angle = -theta - math.asin(tilt)
    half = probe.params["side_len"] / 2
    base = probe.o + d0 * probe.n                                  # midpoint of the bottom edge
    center = base + half * np.array([-math.sin(angle), math.cos(angle)])
    return simulator.build_scene(**{**overrides, "angle": angle, "center": tuple(center)})


def free_fall_scene(**overrides):
    """No slope; the square thrown upwards and sideways so both axes are tested."""
    return simulator.build_scene(**{"slope": None, "v0": (1.0, 2.0), **overrides})


def free_fall_com(scene, t):
    """x0 + v0 t + 1/2 g t^2 for the centre of mass, at the times t (array)."""
    t = np.asarray(t, dtype=np.float64)[:, None]
    return com(scene, scene.x0) + com(scene, scene.v0) * t + 0.5 * scene.g * t * t


def full_scene(**overrides):
    """The lecture's scene: dropped from rest 0.5 m above the slope, lands at t ~ 0.3 s, slides."""
    return simulator.build_scene(**overrides)


# ------------------------------------------------------------------------------------------------
# Measuring a run
# ------------------------------------------------------------------------------------------------

@dataclass
class Run:
    """What a run is measured by: the centre of mass at every step (index 0: the start) and the cost."""
    t: np.ndarray                   # (steps+1,) times
    com: np.ndarray                 # (steps+1, 2) centre of mass
    v_com: np.ndarray               # (steps+1, 2) velocity of the centre of mass
    slip: np.ndarray                # (steps+1,) fastest downhill speed of a node within dhat (nan: none)
    newton_iterations: np.ndarray   # (steps,)
    friction_updates: np.ndarray    # (steps,) Algorithm 5's updates that re-solved the step (0: lagged)
    friction_converged: np.ndarray  # (steps,) bool, the fixed point reached (always True when lagged)
    wall: float                     # wall-clock seconds spent in the time steps

    def downhill(self, scene):
        """Displacement and velocity of the centre of mass along the downhill tangent."""
        t = downhill(scene)
        return (self.com - self.com[0]) @ t, self.v_com @ t


def _slip(scene, x, v):
    if scene.n is None:
        return math.nan
    touching = BarrierEnergy.distances(x, scene.n, scene.o) < scene.dhat
    return float((v[touching] @ downhill(scene)).max()) if touching.any() else math.nan


def run(scene, duration, progress=None):
    """Simulate `duration` seconds (a whole number of steps) from the scene's start and measure it.
    `progress(fraction)` is called now and then."""
    steps = int(round(duration / scene.h))
    if steps < 1 or abs(steps * scene.h - duration) > 1e-9 * duration:
        raise ValueError(f"duration {duration} s is not a whole number of steps of h = {scene.h} s")
    t, coms, vs, slips = [0.0], [com(scene, scene.x0)], [com(scene, scene.v0)], [_slip(scene, scene.x0, scene.v0)]
    newton, friction, converged, wall = [], [], [], 0.0
    every = max(1, steps // 20)
    for rec in simulator.simulate(scene, steps):
        t.append(rec.t)
        coms.append(com(scene, rec.x))
        vs.append(com(scene, rec.v))
        slips.append(_slip(scene, rec.x, rec.v))
        newton.append(rec.report.newton_iterations)
        friction.append(rec.report.friction_updates)
        converged.append(rec.report.friction_converged)
        wall += rec.wall
        if progress is not None and (rec.index + 1) % every == 0:
            progress((rec.index + 1) / steps)
    return Run(np.array(t), np.array(coms), np.array(vs), np.array(slips), np.array(newton),
               np.array(friction), np.array(converged), wall)


def fit_acceleration(t, s):
    """Least-squares fit of s(t) = s0 + v0 t + a t^2 / 2; returns a. Implicit Euler under a constant
    force gives s_n = s0 + v0 t + a t^2/2 + a h t/2 exactly, so the fit recovers a exactly: any
    error it reports comes from the physics the scene adds (friction, contact) or from Newton."""
    t = np.asarray(t, dtype=np.float64)
    A = np.stack([np.ones_like(t), t, 0.5 * t * t], axis=1)
    return float(np.linalg.lstsq(A, np.asarray(s, dtype=np.float64), rcond=None)[0][2])


# Settling excluded from the acceleration fit. The start is computed (no settling of the pose), but
# the first steps are a transient: the friction is in its static regime until the speed passes eps_v
# (eps_v / a ~ 2 ms, the first step), and the springs take up the load (5e-6 m). Measured at
# h = 0.01, tol 1e-6: the acceleration of single steps is off by up to 0.3 % in the first 0.05 s,
# and by less than 1e-4 from 0.1 s on.
SETTLING = 0.1


def acceleration_error(scene, run, start=SETTLING):
    """Relative error (signed) of the acceleration fitted to the centre of mass's displacement down
    the slope over [start, end of run], against `sliding_acceleration`."""
    s, _ = run.downhill(scene)
    window = run.t >= start
    exact = sliding_acceleration(scene)
    return (fit_acceleration(run.t[window], s[window]) - exact) / exact


def observed_orders(hs, errors):
    """log(e_i / e_{i+1}) / log(h_i / h_{i+1}) for consecutive pairs of time steps."""
    hs, errors = np.asarray(hs, dtype=np.float64), np.asarray(errors, dtype=np.float64)
    return np.log(errors[:-1] / errors[1:]) / np.log(hs[:-1] / hs[1:])


def max_com_error(run, reference):
    """Largest distance between the centres of mass of `run` and `reference` at the run's times; the
    reference's time step must divide the run's, and the reference must last at least as long."""
    stride = int(round((run.t[1] - run.t[0]) / (reference.t[1] - reference.t[0])))
    ref_t = reference.t[::stride][:len(run.t)]
    if len(ref_t) != len(run.t) or not np.allclose(ref_t, run.t, rtol=0, atol=1e-9):
        raise ValueError("the reference's samples do not match the run's times")
    return float(np.linalg.norm(run.com - reference.com[::stride][:len(run.com)], axis=1).max())


def tablecloth_travel(pull_speed, pull_length, mu, g=9.81):
    """How far a dish at rest on a cloth pulled a length L at speed U travels: friction drives it
    at mu g toward the cloth's speed. Where U^2 >= mu g L the cloth outruns it for T = L / U: the
    dish reaches mu g T having gone mu g T^2 / 2, then slides as far again to a stop, mu g T^2 =
    mu g L^2 / U^2 in all. Else it catches the cloth, rides along, and stops as far past the cloth's
    end as it lagged behind: L. g is the magnitude of gravity."""
    U, L = pull_speed, pull_length
    return mu * g * L * L / (U * U) if U * U >= mu * g * L else L


def tablecloth_stop_time(pull_speed, pull_length, mu, t_pull, g=9.81):
    """When the closed form's dish stops: the cloth leaves at t_pull + T, T = L / U, the dish then
    moving at min(U, mu g T), which friction takes away in min(U / (mu g), T) more."""
    T = pull_length / pull_speed
    return t_pull + T + (T if mu * g * T <= pull_speed else pull_speed / (mu * g))
