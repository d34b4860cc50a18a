"""A grasp (the slide "Remarks - Applications: Robotics"): a settled block between two fingers
pressed with N each that lift it. Its page, numbers, closed forms and reasons: docs/grasp.md."""
import dataclasses
import math
import types

import numpy as np

import BarrierEnergy
import FingerEnergy
import FrictionEnergy
import GravityEnergy
import InertiaEnergy
import square_mesh
import utils
from scenes import ranges
from scenes.scene import MovingSurface, assemble, fixed, gap_carrying, readonly

GRASP = types.MappingProxyType({
    "width": 0.05, "height": 0.05,  # m: the block
    "nx": 4, "ny": 4,           # cells along and across: (nx + 1)(ny + 1) nodes
    "mass": 0.2,                # the block, kg
    "k": 1e5,                   # spring stiffness, N/m
    "h": 5e-3,                  # time step, s
    "gravity": (0.0, -9.81),    # m/s^2
    "mu": 0.5,                  # friction coefficient of the pads
    "squeeze": 2.616,           # N, each finger's force: m g / (2 mu N) = 0.75, held
    "finger_mass": 0.05,        # kg, each finger
    "lift_accel": 0.5, "lift_speed": 0.2, "t_lift": 0.1,  # lift: a (m/s^2), V (m/s), start (s)
    "pad_length": 0.05,         # m, each pad, centred on the block at t = 0
    "dhat": 1e-3, "kappa": 100.0,   # barrier activation distance (m) and stiffness: gap 0.7 dhat
    "epsv": 1e-3,               # friction's eps_v, m/s
    "tol": 1e-5,                # Newton tolerance on ||p||_inf / h, m/s: u* / 50 (docs/grasp.md)
    "friction_updates": 0, "max_newton_iterations": 1000, "max_halvings": 60,
    "newton_start": "x_n",
})


@dataclasses.dataclass(frozen=True)
class Fingers:
    """The grasp's contact (HalfSpace's methods): finger f, the half-space through row len(x) - F
    + f of x, normal n[f], pressed by squeeze[f] (FingerEnergy), lifted along `tangent`: offset."""
    n: np.ndarray               # (F, 2) unit normals, toward the block
    squeeze: np.ndarray         # (F,) N: each finger's pressing force
    tangent: np.ndarray         # (2,) the direction of the lift (along every finger)
    lift_accel: float           # a, m/s^2
    lift_speed: float           # V, m/s
    t_lift: float               # when the lift starts, s
    pad_length: float           # each finger's pad, centred on its node at t = 0 (drawn), m
    module, stores_energy = FingerEnergy, True      # its term, as time_integrator.TERMS' entries
    velocity = MovingSurface.velocity               # v_s over a step: the offset's difference / h
    counted = "slip: the fingers' lift minus the block's rise; dropped: slid past the pads"
    pads_words = "the fingers' pads"
    moves = True                # along the lift
    normals = property(lambda self: self.n)
    friction_n = property(lambda self: self.n[0])   # they share one tangent
    rows = property(lambda self: slice(0, -len(self.n)))    # the block's: all but the last F

    def args(self, s, lagged, x, v):
        """FingerEnergy's arguments in the lecture's order, as a Term's."""
        return x, self.n, self.squeeze, s.contact_area, s.dhat, s.kappa

    def offset(self, t):
        """The lift by time t (m): a tau^2 / 2 (tau = t - t_lift) up to V / a, then steady at V."""
        tau, t_a = max(t - self.t_lift, 0.0), self.lift_speed / self.lift_accel
        return self.lift_accel * tau * tau / 2 if tau < t_a else self.lift_speed * (tau - t_a / 2)

    def along(self, a):
        """t . a_f (F,) of the fingers' rows of a (N, 2)."""
        return a[len(a) - len(self.n):] @ self.tangent

    def moved(self, a, along):
        """A copy of a (N, 2) whose fingers' rows lie at `along` along `tangent`."""
        a = a.copy()
        a[len(a) - len(self.n):] += np.outer(along - self.along(a), self.tangent)
        return a

    def prescribe(self, lagged, t):
        """`lagged` (x^n checked) with the fingers' rows of x^n and x_tilde lifted to time t."""
        FingerEnergy.each(BarrierEnergy.check_above, lagged.x_n, self.n)
        x_n, x_tilde = (self.moved(a, self.offset(t)) for a in (lagged.x_n, lagged.x_tilde))
        return dataclasses.replace(lagged, x_n=x_n, x_tilde=x_tilde)

    def free(self, g):
        """g (N, 2) without its component along `tangent` on the fingers' rows: no unknowns."""
        return self.moved(g, 0.0)

    def distances(self, x):
        """d_fi = n_f . (x_i - x_f), (F, N_block)."""
        return np.array(FingerEnergy.each(BarrierEnergy.distances, x, self.n))

    def lambdas(self, scene, x, mu=1.0):
        """mu lambda_fi (F, N): BarrierEnergy's with o = x_f, zero on the fingers' own rows."""
        mu_lambda = FingerEnergy.each(BarrierEnergy.compute_mu_lambda_kernel, x, self.n,
                                      scene.contact_area, mu, scene.dhat, scene.kappa)
        return np.hstack([mu_lambda, np.zeros((len(self.n), len(self.n)))])    # fingers' rows: 0

    def init_step_size(self, x, p):
        """Algorithm 4, line 1: BarrierEnergy's against each finger, p relative to its own."""
        (block, fingers), (p_block, p_fingers) = (FingerEnergy.split(a, self.n) for a in (x, p))
        return min(BarrierEnergy.init_step_size_kernel(block, n_f, x_f, p_block - p_f)
                   for n_f, x_f, p_f in zip(self.n, fingers, p_fingers))

    def work(self, scene, x_n, v_n, x):
        """The lift's work over a step (J): sum_f (t . F_f)(t . (x_f - x_f^n)), F = grad E / h^2."""
        force = (InertiaEnergy.grad_kernel(x, x_n + scene.h * v_n, scene.m) / scene.h ** 2
                 + GravityEnergy.grad_kernel(x, scene.m, scene.g)
                 + FingerEnergy.grad_kernel(*self.args(scene, None, x, None)))
        return float(self.along(force) @ self.along(x - x_n))

    def figures(self, scene, x):
        """What log.csv adds for a state x: the slip (m) and each finger's force (N)."""
        return {"slip": slip(scene, x), "finger_forces": self.lambdas(scene, x).sum(axis=1)}

    def closed_creep(self, scene):
        """u* in the steady lift (mm/s), or None where the grasp does not hold."""
        return 1e3 * creep_speed(scene) if holds(scene) else None

    def words(self, track, short=False):
        """`words` of a run's kept states (a recording.Track), of its body unless short."""
        return ("" if short else f"{track.scene.body} ") + words(track.scene, *slips(track), short)

    def mark(self, track):
        """(when, short `words`) of a run, plots.png's mark and legend: when it dropped, or where
        a held block's creep fit starts (outcome's since); None where it slips or is not fitted."""
        (t, s), scene = slips(track), track.scene
        held, t_drop, _, measured, _, since = outcome(scene, t, s)
        when = t_drop if not held else since if measured < scene.epsv else None
        return when, words(scene, t, s, short=True)

    def pads(self, x, depth):
        """Each finger's pad, (4, 2) corners: pad_length along the lift, `depth` behind it."""
        along = 0.5 * self.pad_length * np.array([-1.0, 1.0, 1.0, -1.0])[:, None] * self.tangent
        behind = depth * np.array([0.0, 0.0, 1.0, 1.0])[:, None]
        return [x_f + along - behind * n_f for n_f, x_f in zip(self.n, x[len(x) - len(self.n):])]


def check_params(overrides):
    """GRASP updated by `overrides`, each value checked (a ValueError naming the parameter)."""
    checks = {**dict.fromkeys(("width", "height", "mass", "squeeze", "finger_mass", "lift_accel",
                               "lift_speed", "pad_length"), utils.check_positive),
              **dict.fromkeys(("nx", "ny"), utils.check_whole),
              **dict.fromkeys(("mu", "t_lift"), utils.check_nonnegative), **utils.SOLVER_CHECKS}
    p = utils.check_params(checks, GRASP, overrides, "grasp")
    if not p["gravity"][1] < 0.0 or p["gravity"][0] != 0.0:
        raise utils.ParameterError("gravity", f"gravity must point down the fingers (0, y < 0), "
                                              f"got {p['gravity']}")
    return p


GROWS = types.MappingProxyType({        # what the block's sizes grow with (scenes.ranges)
    "M": {"mass": 1}, "size": {"width": 1, "height": 1}, "X": {"width": 1, "dhat": 1},
    "l": {"width": 1, "nx": -1, "height": 1, "ny": -1}, "N": {"nx": 1, "ny": 1}})


def build_grasp_scene(**overrides):
    """The block centred at the origin, a finger each side at the gap where the barrier holds N."""
    p = check_params(overrides)
    for name, other in sorted((("nx", "ny"), ("ny", "nx")), key=lambda pair: -p[pair[0]]):
        ranges.check_memory(name, p[name], lambda n: (n + 1) * (p[other] + 1))
    w, h, nb = p["width"], p["height"], (p["nx"] + 1) * (p["ny"] + 1)
    block, e = square_mesh.rectangle(w, h, p["nx"], p["ny"], (-w / 2, -h / 2))
    spacing = min(w / p["nx"], h / p["ny"])
    ranges.check_start(p, GRASP, GROWS, block, np.full(nb, p["mass"] / nb), spacing, h / p["ny"],
                       np.array([-w / 2, 0]), block[:, 0] + w / 2 + p["dhat"])  # d = dhat at left
    load = p["squeeze"] / (p["ny"] + 1)
    ranges.check_carries(p, GRASP, load, h / p["ny"], {"kappa": -1, "squeeze": 1, "height": -1,
                                                      "ny": 2, "dhat": -1}, "the squeeze")
    d0 = gap_carrying(load, h / p["ny"], p["dhat"], p["kappa"])
    x = np.vstack([block, [[-w / 2 - d0, 0.0], [w / 2 + d0, 0.0]]])   # the fingers' nodes, last
    fingers = Fingers(n=readonly([[1.0, 0.0], [-1.0, 0.0]]), squeeze=readonly([p["squeeze"]] * 2),
                      tangent=readonly([0.0, 1.0]), lift_accel=p["lift_accel"],
                      lift_speed=p["lift_speed"], t_lift=p["t_lift"], pad_length=p["pad_length"])
    pairs = np.column_stack([np.tile(np.arange(nb), 2), np.repeat([nb, nb + 1], nb)])  # (i, f)
    terms = ("inertia", "spring", "gravity", "fingers") + ("friction",) * (p["mu"] > 0.0)
    m = np.append(np.full(nb, p["mass"] / nb), [p["finger_mass"]] * 2)
    w_contact = np.append(np.full(nb, h / p["ny"]), [0.0, 0.0])     # the fingers' nodes: none
    return assemble(p, x, e, m, w_contact, terms, (p["nx"], p["ny"]), elements=[pairs],
                    contact=fingers, pushed=fingers, body="the block")


# ---- The closed forms: a block of mass m between two fingers pressed with N each -----------------

def grip(scene):
    """2 mu N / m: the largest acceleration the two fingers' friction can give the block, m/s^2."""
    return scene.mu * float(scene.contact.squeeze.sum()) / scene.params["mass"]


def load_ratio(scene, lift_accel=0.0):
    """m (g + a) / (2 mu N): the load on friction while the lift accelerates at a (inf: mu 0)."""
    load = float(-scene.g[1]) + lift_accel        # a Python float: inf past float64, as it is
    return load / grip(scene) if grip(scene) > 0.0 else math.inf


def squeeze_for(ratio, mu, lift_accel=0.0, p=GRASP):
    """N with m (g + a) / (2 mu N) = ratio for the block of `p` (ratio 1: on the line)."""
    return p["mass"] * (-p["gravity"][1] + lift_accel) / (2 * mu * ratio)


def holds(scene):
    """2 mu N >= m (g + a) while the lift accelerates, and >= m g after."""
    return max(load_ratio(scene, scene.contact.lift_accel), load_ratio(scene)) <= 1.0


def creep_speed(scene, lift_accel=0.0):
    """Held, u* = eps_v (1 - sqrt(1 - m (g + a) / (2 mu N))) (f1_inverse); nan where it slips."""
    ratio = load_ratio(scene, lift_accel)
    return FrictionEnergy.f1_inverse(ratio, scene.epsv) if ratio <= 1.0 else math.nan


def slip_acceleration(scene, lift_accel=0.0):
    """(g + a) - 2 mu N / m: the block's acceleration down the fingers while it slips."""
    return -scene.g[1] + lift_accel - grip(scene)


def phases(scene):
    """The lift's phases: (words, start, end, acceleration a), still, accelerating, steady."""
    f = scene.contact
    t_a = f.t_lift + f.lift_speed / f.lift_accel
    return [("before the lift", 0.0, f.t_lift, 0.0),
            ("while the lift accelerates", f.t_lift, t_a, f.lift_accel),
            ("in the steady lift", t_a, math.inf, 0.0)]


def coulomb_phases(scene):
    """A rigid Coulomb block through the lift's phases: (t0, t1, s0, u0, du) each, its slip s0 and
    speed u0 at t0, slipping at du = slip_acceleration (du < 0: until it sticks, t1)."""
    s = u = 0.0
    for _, t0, t1, a in phases(scene):
        du = float(slip_acceleration(scene, a))     # a Python float: inf * 0 gives no warning
        t1 = t1 if du >= 0.0 else min(t1, t0 + u / -du)         # until it sticks again
        yield t0, t1, s, u, du
        T = t1 - t0                     # inf in the last phase, whose end nothing reads
        s, u = s + u * T + du * T * T / 2, u + du * T


def coulomb_slip(scene, t):
    """A rigid Coulomb block's slip by time t (m): s0 + u0 T + du T^2 / 2, T into its phase."""
    t0, t1, s0, u0, du = [phase for phase in coulomb_phases(scene) if phase[0] <= t][-1]
    T = min(t, t1) - t0
    return s0 + u0 * T + du * T * T / 2


def coulomb_drop(scene):
    """When a rigid Coulomb block has slid past the pads (its slip reaches D = drop_slip), s; inf
    where it never does: T = 2 (D - s0) / (u0 + sqrt(u0^2 + 2 du (D - s0))) into its phase."""
    D = drop_slip(scene)
    for t0, t1, s0, u0, du in coulomb_phases(scene):
        root = u0 * u0 + 2 * du * (D - s0)
        if root >= 0.0 and u0 + math.sqrt(root) > 0.0:
            T = 2 * (D - s0) / (u0 + math.sqrt(root))
            if T <= t1 - t0:
                return t0 + T
    return math.inf


def slip(scene, x):
    """The block's slide down the fingers since t = 0 (m): their lift minus its centre's rise."""
    f = scene.contact
    rise = np.average(x[f.rows] - scene.x0[f.rows], axis=0, weights=scene.m[f.rows]) @ f.tangent
    return float(f.along(x).mean()) - float(rise)


def slips(track):
    """(t, slip) of a run's kept states (a recording.Track), (K,) each."""
    return np.array([(x.t, x.slip) for x in track.samples.all()]).T


def drop_slip(scene):
    """The slip at which the block has slid past the pads (its top below their bottom), m."""
    return (scene.contact.pad_length + scene.params["height"]) / 2


# ---- In words: held (its creep beside u*), dropped (its slip acceleration beside the closed form)

SETTLE = 0.05       # s left out of a fit after a phase of the lift begins (the springs take it up)


def fitted_rate(t, s, start, end, order=1):
    """The slip's speed (order 1) or acceleration (order 2) fitted to s over the states with
    start <= t <= end (to round-off); nan on fewer than 4."""
    w = (t >= start - 1e-9) & (t <= end + 1e-9)
    return float(np.polyfit(t[w], s[w], order)[0]) * order if w.sum() >= 4 else math.nan


def outcome(scene, t, s):
    """(held, t_drop or None, phase words, measured, closed form, since) from the slip s at times
    t: the speed and u*, or the acceleration where it dropped, fitted over the phase it ended in
    from SETTLE into it (else its middle) to its end; since: the first state fitted (grasp.md)."""
    dropped = np.flatnonzero(s >= drop_slip(scene))
    end = float(t[dropped[0]]) if dropped.size else float(t[-1])
    words, start, _, a = next(p for p in phases(scene) if p[1] <= max(end - 1e-9, 0.0) < p[2])
    order, since = 2 if dropped.size else 1, start + SETTLE
    measured = fitted_rate(t, s, since, end, order)
    if math.isnan(measured):                    # a short phase: fitted from its middle
        since = (start + end) / 2
        measured = fitted_rate(t, s, since, end, order)
    exact = slip_acceleration(scene, a) if dropped.size else creep_speed(scene, a)
    since = float(t[t >= since - 1e-9][0]) if not math.isnan(measured) else since
    return not dropped.size, end if dropped.size else None, words, measured, exact, since


TOO_FEW = "too short a run to fit {} (fewer than 4 states in its window)"


def words(scene, t, s, short=False):
    """'held (slid 0.66 mm, Coulomb 0); creeps 0.498 mm/s in the steady lift from 0.55 s (u*
    0.500)', 'dropped at 0.62 s (Coulomb 0.61); ...', 'slips on the pads at 0.60 s (...); ...' or,
    too few states to fit a rate, 'is on the pads at 0.01 s (...); too short a run to fit ...';
    each rate with the start of its fit, `outcome`'s since (docs/grasp.md). Its parts, split at
    '; ', each fit a closing line."""
    on_pads, t_drop, phase, measured, exact, since = outcome(scene, t, s)
    since = f"{round(since, 3):g}"                      # 0.55, 0.015: a state's time
    phase = f"{phase} from {since} s"
    if not on_pads:
        rate, sign = ("it slips", 1) if not measured < 0.0 else ("its slip slows at", -1)
        t_coulomb = coulomb_drop(scene)
        coulomb = f"{t_coulomb:.2f}" if t_coulomb < math.inf else "holds"
        said = f"{rate} {sign * measured:.3f} m/s^2 {phase} (closed form {sign * exact:.3f})"
        said = TOO_FEW.format("its acceleration") if math.isnan(measured) else said
        return f"dropped at {t_drop:.2f} s (Coulomb {coulomb})" + ("" if short else f"; {said}")
    slid = f"slid {1e3 * s[-1]:.2f} mm, Coulomb {1e3 * coulomb_slip(scene, float(t[-1])):.3g}"
    if math.isnan(measured):                    # neither held nor slipping: not measured
        return (f"on the pads at {t[-1]:.2f} s, too short to fit its speed" if short else
                f"is on the pads at {t[-1]:.2f} s ({slid}); " + TOO_FEW.format("its speed"))
    if not measured < scene.epsv:
        return f"slips on the pads at {t[-1]:.2f} s" + ("" if short else (
            f" ({slid}); at {1e3 * measured:.1f} mm/s {phase}"))
    creeps, u_star = f"creeps {1e3 * measured:.3f} mm/s", f"(u* {fixed(1e3 * exact, 3)})"
    return (f"held, {creeps} from {since} s {u_star}" if short else
            f"held ({slid}); {creeps} {phase} {u_star}")


# ---- What the command line and log.csv read (scenes.UNITS) ---------------------------------------

PARAMS, BUILD = GRASP, build_grasp_scene
FLAGS = [(("--squeeze",), "squeeze", "NEWTONS", "--scene grasp: each finger's force N in N"),
         (("--lift-accel",), "lift_accel", "M_PER_S2", "--scene grasp: the lift's a in m/s^2")]
LABEL = "squeeze = {squeeze:g} N, mu = {mu:g}"      # a single run's label
HEADER = ("block {width:g} x {height:g} m, {mass:g} kg   squeeze N = {squeeze:g} N a finger   lift "
          "at a = {lift_accel:g} m/s^2 to {lift_speed:g} m/s from t = {t_lift:g} s   mu = {mu:g}")
HELP = "a block lifted between two pressed fingers"
TITLE = "Block lifted between fingers"                  # the page's
DURATION = 1.5      # s: the lift's acceleration (0.1 s to 0.5 s), then 1 s of steady lift
LOG_COLUMNS = [     # (name, unit, label, meaning, format, value(sample)): analysis/log.py's Column
    ("E_fingers", "J", "fingers' energy", "the barrier against the fingers plus their squeeze's "
     "potential -N n_f . x_f (the grasp)", ".9g", lambda s: s.energies["fingers"]),
    ("slip", "m", "slip", "how far the block has slid down relative to the fingers since t = 0: "
     "their lift minus the rise of its centre of mass (the grasp)", ".9f", lambda s: s.slip)] + [
    (f"normal_force_{side}", "N", f"{side} finger's force", f"the {side} finger's normal force on "
     "the block, the sum of its lambda_i (the grasp)", ".9g", lambda s, f=f: s.finger_forces[f])
    for f, side in enumerate(("left", "right"))]
