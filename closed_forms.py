"""The closed-form cases (sliding, sticking, free fall; the full scene against a smaller step; the
tablecloth), their exact answers and how a run is measured against them:
tests/physics/test_accuracy.py and tests/scenes/ assert, benchmarks/error_vs_runtime.py reports.
"""
import math
from dataclasses import dataclass

import numpy as np

import BarrierEnergy
import FrictionEnergy
import simulator

# Rigid for the formulas: deforms by 5e-6 m under its weight (the lecture's k = 2e4 sags by 2 cm).
STIFF_K = 1e8

LECTURE_TAN = 0.1                           # the lecture's slope, normal (0.1, 1)
STEEP_TAN = math.tan(math.radians(20.0))    # the steeper slope of the tests: 20 degrees


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
    """Normal load N, downhill drive G_t and friction force F = min(G_t, mu N) on the square, N."""
    total = float(np.sum(scene.m))
    normal_load = -total * float(scene.g @ scene.n)
    drive = total * float(scene.g @ downhill(scene))
    return normal_load, drive, min(drive, scene.mu * normal_load)


def sliding_acceleration(scene):
    """Rigid block, Coulomb friction: a = g (sin theta - mu cos theta) downhill."""
    normal_load, drive, _ = _loads(scene)
    return (drive - scene.mu * normal_load) / float(np.sum(scene.m))


def holds(scene):
    """Whether Coulomb friction holds a rigid square on the slope, 0 <= G_t < mu N: where
    creep_speed applies."""
    normal_load, drive, _ = _loads(scene)
    return 0.0 <= drive < scene.mu * normal_load


def creep_speed(scene):
    """Steady creep under the mollifier f1(v) = 2v/eps_v - v^2/eps_v^2 where mu N f1(v) balances
    the drive: v = eps_v (1 - sqrt(1 - tan(theta)/mu)), mu > tan(theta); implicit Euler reproduces
    it exactly."""
    normal_load, drive, _ = _loads(scene)
    return FrictionEnergy.f1_inverse(drive / (scene.mu * normal_load), scene.epsv)


def barrier_force(scene, d):
    """Normal force of the barrier on a bottom node at distance d: -w dhat b'(d) for d < dhat."""
    d = np.asarray(d, dtype=np.float64)
    w = scene.contact_area[0]
    force = -BarrierEnergy.dP_dd(np.minimum(d, scene.dhat), w, scene.dhat, scene.kappa)
    return np.where(d < scene.dhat, force, 0.0)


def _bracketed_root(f, lo, hi):
    import scipy.optimize           # here, not at the top: 0.1-0.3 s that only its callers pay
    return scipy.optimize.brentq(f, lo, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=500)


def resting_pose(scene):
    """Distance d0 of the bottom edge's midpoint from the slope and tilt s = sin(-beta) of the edge
    at which the barrier carries a rigid square without rocking (docs/limits.md): brentq for d0
    at a given s, then for s."""
    normal_load, _, friction = _loads(scene)
    side, n_seg = scene.params["side_len"], scene.params["n_seg"]
    r = -side / 2 + np.arange(n_seg + 1) * side / n_seg
    reach = float(np.abs(r).max())

    def d0_for(s):
        # from the deepest node touching the slope (infinite force) to every node beyond dhat
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
    """A square at rest on a slope of tan(theta) through the default o, at `resting_pose`."""
    overrides = {"slope": slope_normal(tan_theta), "mu": mu, "k": k, **overrides}
    probe = simulator.build_scene(**{**overrides, "center": (0.0, 10.0)})   # masses, loads
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


# ---- Measuring a run -----------------------------------------------------------------------------

@dataclass
class Run:
    """A run's centre of mass at every step (index 0: the start) and its cost."""
    t: np.ndarray                   # (steps+1,) times
    com: np.ndarray                 # (steps+1, 2) centre of mass
    v_com: np.ndarray               # (steps+1, 2) velocity of the centre of mass
    slip: np.ndarray                # (steps+1,) fastest downhill speed within dhat (nan: none)
    newton_iterations: np.ndarray   # (steps,)
    friction_updates: np.ndarray    # (steps,) Algorithm 5's updates that re-solved the step
    friction_converged: np.ndarray  # (steps,) bool, the fixed point reached (True when lagged)
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
    """Simulate `duration` seconds (whole steps) and measure it; calls `progress(fraction)`."""
    steps = int(round(duration / scene.h))
    states = [(0.0, com(scene, scene.x0), com(scene, scene.v0), _slip(scene, scene.x0, scene.v0))]
    reports, wall, every = [], 0.0, max(1, steps // 20)
    for rec in simulator.simulate(scene, steps):
        states.append((rec.t, com(scene, rec.x), com(scene, rec.v), _slip(scene, rec.x, rec.v)))
        reports.append(rec.report)
        wall += rec.wall
        if progress is not None and (rec.index + 1) % every == 0:
            progress((rec.index + 1) / steps)
    t, coms, vs, slips = (np.array(column) for column in zip(*states))
    costs = [np.array([getattr(r, name) for r in reports])
             for name in ("newton_iterations", "friction_updates", "friction_converged")]
    return Run(t, coms, vs, slips, *costs, wall)


# Excluded from the acceleration fit: friction is static until the speed passes eps_v and the
# springs take up the load (single steps off by 0.3 % before 0.05 s, by < 1e-4 from 0.1 s on).
SETTLING = 0.1


def acceleration_error(scene, run, start=SETTLING):
    """Relative error (signed) against `sliding_acceleration` of a, fitted as s0 + v0 t + a t^2/2
    to the downhill displacement over [start, end] (exact for implicit Euler at constant force)."""
    s, _ = run.downhill(scene)
    window = run.t >= start
    exact = sliding_acceleration(scene)
    return (2.0 * np.polyfit(run.t[window], s[window], 2)[0] - exact) / exact


def max_com_error(run, reference):
    """Largest distance between the centres of mass of `run` and `reference` at the run's times;
    the reference's step divides the run's, and it lasts at least as long."""
    stride = int(round((run.t[1] - run.t[0]) / (reference.t[1] - reference.t[0])))
    return float(np.linalg.norm(run.com - reference.com[::stride][:len(run.com)], axis=1).max())


def tablecloth_travel(pull_speed, pull_length, mu, g=9.81):
    """How far a dish on a cloth pulled a length L at speed U travels, friction driving it at mu g:
    mu g T^2 = mu g L^2 / U^2 where the cloth outruns it (U^2 >= mu g L: speed mu g T at T = L / U,
    then as far again to a stop), else L (it rides along, stops as far past the end as it lags)."""
    U, L = pull_speed, pull_length
    return mu * g * L * L / (U * U) if U * U >= mu * g * L else L


def tablecloth_stop_time(pull_speed, pull_length, mu, t_pull, g=9.81):
    """When the closed form's dish stops: the cloth leaves at t_pull + T, T = L / U, the dish then
    moving at min(U, mu g T), which friction takes away in min(U / (mu g), T) more."""
    T = pull_length / pull_speed
    return t_pull + T + (T if mu * g * T <= pull_speed else pull_speed / (mu * g))



def measured(scene, duration, figure):
    """(t, figure(scene, x)) as arrays at every step of `scene` simulated for `duration` seconds
    (index 0: the start)."""
    records = list(simulator.simulate(scene, int(round(duration / scene.h))))
    return (np.array([0.0] + [r.t for r in records]),
            np.array([figure(scene, x) for x in [scene.x0] + [r.x for r in records]]))
