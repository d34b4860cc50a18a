"""How a run is measured against a closed form (and the full scene against a smaller step), and
the square's creep, which stands on the mollifier's inverse (FrictionEnergy.f1_inverse). A closed
form only one scene uses sits in its unit: scenes/square.py (sliding, sticking, free fall),
scenes/tablecloth.py (the dish's travel), scenes/grasp.py (hold, creep u*, slip). tests/physics/
test_accuracy.py and tests/scenes/ assert them, benchmarks/ reports them.
"""
import math
from dataclasses import dataclass

import numpy as np

import BarrierEnergy
import FrictionEnergy
import simulator
from scenes import square


def creep_speed(scene):
    """The square's steady creep on the slope under the mollifier f1(v) = 2v/eps_v - v^2/eps_v^2
    where mu N f1(v) balances the drive: v = eps_v (1 - sqrt(1 - tan(theta)/mu)), mu > tan(theta)
    (square.holds); implicit Euler reproduces it exactly."""
    normal_load, drive, _ = square.loads(scene)
    return FrictionEnergy.f1_inverse(drive / (scene.mu * normal_load), scene.epsv)


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
        t = square.downhill(scene)
        return (self.com - self.com[0]) @ t, self.v_com @ t


def _slip(scene, x, v):
    if scene.n is None:
        return math.nan
    touching = BarrierEnergy.distances(x, scene.n, scene.o) < scene.dhat
    return float((v[touching] @ square.downhill(scene)).max()) if touching.any() else math.nan


def run(scene, duration, progress=None):
    """Simulate `duration` seconds (whole steps) and measure it; calls `progress(fraction)`."""
    steps = int(round(duration / scene.h))

    def state(t, x, v):             # t, the centres of mass of x and v, the slip
        return t, square.com(scene, x), square.com(scene, v), _slip(scene, x, v)
    states = [state(0.0, scene.x0, scene.v0)]
    reports, wall, every = [], 0.0, max(1, steps // 20)
    for rec in simulator.simulate(scene, steps):
        states.append(state(rec.t, rec.x, rec.v))
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
    """Relative error (signed) against square.sliding_acceleration of a, fitted as s0 + v0 t +
    a t^2/2 to the downhill displacement over [start, end] (exact for implicit Euler at constant
    force)."""
    s, _ = run.downhill(scene)
    window = run.t >= start
    exact = square.sliding_acceleration(scene)
    return (2.0 * np.polyfit(run.t[window], s[window], 2)[0] - exact) / exact


def max_com_error(run, reference):
    """Largest distance between the centres of mass of `run` and `reference` at the run's times;
    the reference's step divides the run's, and it lasts at least as long."""
    stride = int(round((run.t[1] - run.t[0]) / (reference.t[1] - reference.t[0])))
    return float(np.linalg.norm(run.com - reference.com[::stride][:len(run.com)], axis=1).max())


def measured(scene, duration, figure):
    """(t, figure(scene, x)) as arrays at every step of `scene` simulated for `duration` seconds
    (index 0: the start)."""
    records = list(simulator.simulate(scene, int(round(duration / scene.h))))
    return (np.array([0.0] + [r.t for r in records]),
            np.array([figure(scene, x) for x in [scene.x0] + [r.x for r in records]]))
