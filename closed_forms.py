"""How a run is measured against a closed form (and the full scene against a smaller step), and
the closed forms that are no one scene's own: the mollifier's creep, which the square on its slope
and the grasp between its fingers share, and the grasp's. A closed form only one scene uses sits in
its unit: scenes/square.py (sliding, sticking, free fall), scenes/tablecloth.py (the dish's
travel). tests/physics/test_accuracy.py and tests/scenes/ assert them, benchmarks/ reports them.
"""
import math
from dataclasses import dataclass

import numpy as np

import BarrierEnergy
import simulator
from scenes import square


def creep_speed(scene):
    """The square's steady creep on the slope under the mollifier f1(v) = 2v/eps_v - v^2/eps_v^2
    where mu N f1(v) balances the drive: v = eps_v (1 - sqrt(1 - tan(theta)/mu)), mu > tan(theta)
    (square.holds); implicit Euler reproduces it exactly. Here, not in scenes/square.py: it stands
    on mollified_creep, which the grasp shares."""
    normal_load, drive, _ = square.loads(scene)
    return mollified_creep(scene.epsv, drive / (scene.mu * normal_load))


def mollified_creep(epsv, load_ratio):
    """The speed v where friction's mollifier carries a load `load_ratio` (<= 1) times mu N:
    f1(v) = 2v/eps_v - v^2/eps_v^2 = load_ratio, v = eps_v (1 - sqrt(1 - load_ratio))."""
    return epsv * (1.0 - math.sqrt(1.0 - load_ratio))


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


# ---- The grasp (scenes/grasp.py): a block of mass m between two fingers pressed with N each ------

def grasp_grip(scene):
    """2 mu N / m: the largest acceleration the two fingers' friction can give the block, m/s^2."""
    return scene.mu * float(scene.fingers.squeeze.sum()) / scene.params["mass"]


def grasp_load_ratio(scene, lift_accel=0.0):
    """m (g + a) / (2 mu N): the load on friction while the fingers lift at acceleration a (inf
    without friction)."""
    grip = grasp_grip(scene)
    return (-scene.g[1] + lift_accel) / grip if grip > 0.0 else math.inf


def grasp_holds(scene):
    """Whether the grasp holds: 2 mu N >= m (g + a) while the lift accelerates, and m g after."""
    return max(grasp_load_ratio(scene, scene.fingers.lift_accel), grasp_load_ratio(scene)) <= 1.0


def grasp_creep_speed(scene, lift_accel=0.0):
    """u* = eps_v (1 - sqrt(1 - m (g + a) / (2 mu N))): held, its creep down the fingers, in
    the steady lift (a = 0) or while it accelerates (mollified_creep); nan where it cannot hold."""
    ratio = grasp_load_ratio(scene, lift_accel)
    return mollified_creep(scene.epsv, ratio) if ratio <= 1.0 else math.nan


def grasp_slip_acceleration(scene, lift_accel=0.0):
    """(g + a) - 2 mu N / m: the block's acceleration down the fingers while it slips."""
    return -scene.g[1] + lift_accel - grasp_grip(scene)


def grasp_coulomb_slip(scene, t):
    """How far a rigid block with Coulomb friction has slid down the fingers by time t (m): through
    the lift's phases (still, accelerating at a, steady), its slip speed u grows at
    (g + a) - 2 mu N / m where that is > 0, and falls at that rate to 0 (sticking) where not."""
    f = scene.fingers
    t_a = f.t_lift + f.lift_speed / f.lift_accel
    s = u = 0.0
    for t0, t1, a in [(0.0, f.t_lift, 0.0), (f.t_lift, t_a, f.lift_accel), (t_a, math.inf, 0.0)]:
        du = grasp_slip_acceleration(scene, a)
        T = max(min(t1, t) - t0, 0.0)
        T = T if du >= 0.0 else min(T, u / -du)                 # until it sticks again
        s, u = s + u * T + du * T * T / 2, u + du * T
    return s


def grasp_block_com(scene, x):
    """The block's centre of mass (the fingers' rows, the last, left out)."""
    block = len(x) - len(scene.fingers.n)
    return np.average(x[:block], axis=0, weights=scene.m[:block])


def grasp_slip(scene, x):
    """How far the block has slid down relative to the fingers since t = 0 (m): the fingers' lift
    minus the rise of the block's centre of mass, along the lift."""
    f = scene.fingers
    lift = float((x[len(x) - len(f.n):] @ f.tangent - f.start).mean())
    return lift - float((grasp_block_com(scene, x) - grasp_block_com(scene, scene.x0)) @ f.tangent)


def grasp_run(scene, duration):
    """The grasp simulated for `duration` seconds: (t, slip) at every step (index 0: the start)."""
    t, slip = [0.0], [0.0]
    for rec in simulator.simulate(scene, int(round(duration / scene.h))):
        t.append(rec.t)
        slip.append(grasp_slip(scene, rec.x))
    return np.array(t), np.array(slip)


def fitted_rate(t, s, start, end, order=1):
    """The slip's speed (order 1: a line's slope) or acceleration (order 2: twice a parabola's
    leading coefficient) fitted to s over start <= t <= end."""
    window = (t >= start - 1e-9) & (t <= end + 1e-9)
    return float(np.polyfit(t[window], s[window], order)[0]) * order


def grasp_drop_slip(scene):
    """The slip at which the block has slid past the pads (its top below their bottom), m."""
    return (scene.fingers.pad_length + scene.params["height"]) / 2
