"""The lecture's case study: an elastic mass-spring square dropped onto a slope, with friction. Its
numbers (DEFAULTS) and builder; its checks, run once by the builder (what float64 and this machine
can hold: not the lecture's path, a student can skip them); its closed forms, a rigid square
sliding or sticking on the slope and in free fall (tests/physics/test_accuracy.py asserts them,
benchmarks/error_vs_runtime.py reports them, closed_forms.py measures runs against them).

    scene = build_scene(mu=0.2)     # the lecture's numbers (DEFAULTS), one of them changed
"""
import decimal
import math
import types

import numpy as np

import BarrierEnergy
import FrictionEnergy
import square_mesh
import utils
from scenes import ranges
from scenes.scene import assemble
from utils import ParameterError

DEFAULTS = types.MappingProxyType({
    "side_len": 1.0,            # m
    "n_seg": 4,                 # segments per side: (n_seg + 1)^2 nodes
    "rho": 1000.0,              # kg/m^2
    "mass": None,               # total mass in kg, instead of rho side_len^2
    "k": 2e4,                   # spring stiffness, N/m
    "h": 0.01,                  # time step, s
    "gravity": (0.0, -9.81),    # m/s^2
    "slope": (0.1, 1.0),        # the slope's normal, normalized when built; None: no slope
    "slope_point": (0.0, -1.0),  # o, a point on the slope, m
    "mu": 0.11,                 # friction coefficient
    "dhat": BarrierEnergy.DHAT,     # barrier activation distance, m (0.01)
    "kappa": BarrierEnergy.KAPPA,   # barrier stiffness (1e5)
    "epsv": 1e-3,               # friction's eps_v, m/s
    "tol": 1e-2,                # Newton tolerance on ||p||_inf / h, m/s
    "v0": (0.0, 0.0),           # initial velocity of every node, m/s
    "center": (0.0, 0.0),       # initial centre of the square, m
    "angle": 0.0,               # initial rotation of the square about its centre, radians
    "friction_updates": 0,      # Algorithm 5's friction updates per step; 0: lagged, as the lecture
    "newton_start": "x_n",      # x^n, as the lecture; "x_tilde": x^n + h v^n, cut back by CCD
    "max_newton_iterations": 1000,  # a safety cap: the hardest tested cases need about 320
    "max_halvings": 60,         # line-search halvings before Newton gives up on a direction
})
ALIASES = {"dt": "h"}           # other names a parameter may be passed by


def build_scene(**overrides):
    """The square's scene, built once from DEFAULTS with `overrides`; a ValueError names a bad
    parameter (check_params, scenes.ranges)."""
    p = check_params(DEFAULTS, ALIASES, overrides)
    ranges.check_memory("n_seg", p["n_seg"], lambda n_seg: (n_seg + 1) ** 2)
    x, e = square_mesh.generate(p["side_len"], p["n_seg"])      # the square, centred at the origin
    c, s = math.cos(p["angle"]), math.sin(p["angle"])
    x = x @ np.array([[c, s], [-s, c]]) + np.array(p["center"])
    n = o = d = None
    if p["slope"] is not None:
        n, o = slope_normal(p["slope"]), np.array(p["slope_point"])
        d = BarrierEnergy.distances(x, n, o)
    m = np.full(len(x), total_mass(p) / len(x))      # or rho side_len^2
    spacing = p["side_len"] / p["n_seg"]
    defaults = {**DEFAULTS, "mass": total_mass(DEFAULTS)}
    ranges.check_start(p, defaults, grows(p), x, m, spacing, spacing, o, d)
    if d is not None:
        check_touching(p, x, n, d, ranges.roundoff(x, o))

    terms = ["inertia", "spring"] + ["gravity"] * any(p["gravity"])
    if n is not None:
        terms += ["barrier"] + ["friction"] * (p["mu"] > 0.0)
    return assemble(p, x, e, m, w=spacing, terms=terms, cells=(p["n_seg"], p["n_seg"]), n=n, o=o,
                    v0=np.tile(p["v0"], (len(x), 1)), warnings=scene_warnings(p, x, n, d))


# ---- Its checks: each parameter, then the start, and what its results cannot be trusted for -----

def check_params(defaults, aliases, overrides):
    """`defaults` updated by `overrides` (aliases renamed to their parameter), values checked."""
    checks = {**dict.fromkeys(("side_len", "rho"), utils.check_positive), **utils.SOLVER_CHECKS,
              "n_seg": utils.check_whole,
              **dict.fromkeys(("slope_point", "v0", "center"), utils.check_pair)}
    p = utils.check_params(checks, defaults, overrides, "scene", aliases)
    if p["mass"] is not None and "rho" in overrides:
        raise ParameterError("mass", f"mass = {p['mass']} and rho = {p['rho']} are both given: the "
                                     f"total mass is mass, or rho side_len^2; give one")
    if p["mass"] is not None:
        p["mass"] = utils.check_positive("mass", p["mass"])
    for name in ("mu", "angle"):
        p[name] = utils.as_float(name, p[name], "must be a finite number")
        if not np.isfinite(p[name]):
            raise ParameterError(name, f"{name} must be finite, got {p[name]}")
    if p["mu"] < 0:
        raise ParameterError("mu", f"mu must be >= 0, got {p['mu']}")
    if p["slope"] is not None:
        p["slope"] = utils.check_pair("slope", p["slope"])
        slope_normal(p["slope"])
    return p


def slope_normal(slope):
    """n = s / |s|, s = slope / max_i |slope_i|: unit length within 1 eps for any components
    (subnormal too), the lecture's (0.1, 1) bit for bit; `slope` finite, a ValueError if zero."""
    scale = float(np.abs(slope).max())
    if scale == 0.0:
        raise ParameterError("slope", f"slope normal must be non-zero, got {list(slope)}")
    s = np.array(slope) / scale
    return s / np.hypot(*s)


def total_mass(p):
    """The total mass, kg: `mass` where given, else rho side_len^2 (inf beyond float64)."""
    return p["mass"] if p["mass"] is not None else p["rho"] * p["side_len"] * p["side_len"]


def check_touching(p, x, n, d, roundoff):
    """ValueError naming center where a node (distances d) is within `roundoff` of the slope, and
    a centre that puts it dhat above."""
    if d is not None and not d.min() > roundoff:
        i = int(np.argmin(d))
        moved = ",".join(f"{a:.5g}" for a in np.array(p["center"]) + (p["dhat"] - d[i]) * n)
        message = f"node {i} touches the slope ({d[i]:.1g} m): try --center {moved}"
        raise ParameterError("center", message)


def grows(p):
    """What the square's sizes grow with (ranges.check_start)."""
    mass = {"mass": 1} if p["mass"] is not None else {"rho": 1, "side_len": 2}
    return {"M": mass, "size": {"side_len": 1}, "X": {"center": 1, "slope_point": 1},
            "l": {"side_len": 1, "n_seg": -1}, "N": {"n_seg": 2}}


def scene_warnings(p, x, n, d):
    """What a scene's results cannot be trusted for, as sentences for the user (docs/limits.md):
    one step moves the body more than its size; a resting start that gains less than tol per step;
    a tol below Newton's round-off floor sqrt(eps E_scale / m) / h."""
    warnings, h, v, g = [], p["h"], math.hypot(*p["v0"]), math.hypot(*p["gravity"])
    travel = v * h + g * h * h
    if travel > p["side_len"]:
        # the root of |g| h^2 + |v0| h = side_len, without cancellation, rounded down
        largest = decimal.Decimal(2.0 * p["side_len"]
                                  / (v + math.hypot(v, 2.0 * math.sqrt(g * p["side_len"]))))
        digits = decimal.Decimal(1).scaleb(largest.adjusted() - 2)
        rounded = largest.quantize(digits, rounding=decimal.ROUND_FLOOR)
        warnings.append(f"time step h = {h:g} s moves the square {travel:.3g} m per step, more "
                        f"than its size {p['side_len']:g} m: impacts are not resolved in time "
                        f"(results are qualitative only; use h <= {rounded.normalize():g} s)")
    if n is not None and p["mu"] > 0:
        gn = float(np.dot(p["gravity"], n))
        slide = float(np.hypot(*(np.array(p["gravity"]) - gn * n))) + p["mu"] * min(gn, 0.0)
        v_t = float(np.hypot(*(np.array(p["v0"]) - np.dot(p["v0"], n) * n)))
        if (d < p["dhat"]).any() and v_t < p["epsv"] and 0.0 < slide * h < p["tol"]:
            warnings.append(f"the square starts at rest on the slope and should slide at "
                            f"{slide:.3g} m/s^2, gaining {slide * h:.3g} m/s per step, less than "
                            f"tol = {p['tol']:g} m/s: Newton may stop before it leaves static "
                            f"friction (use tol <= {slide * h / 10:.2g})")
    M = total_mass(p)
    reach = float(np.abs(x).max()) + p["side_len"]
    eps = ranges.EPS
    floor = max(math.sqrt(eps * h * h * M * g * reach / (M / len(x))), eps * reach) / h
    if p["tol"] < floor:
        warnings.append(f"tol = {p['tol']:g} m/s is below the residual float64 can resolve in this "
                        f"scene, about {floor:.2g} m/s: Newton stops at that floor where it must, "
                        f"and log.csv flags those steps newton_stalled (docs/limits.md)")
    return tuple(warnings)


# ---- Its closed forms: a rigid square on the slope (sliding, sticking, at rest), in free fall ----

# Rigid for the formulas: deforms by 5e-6 m under its weight (the lecture's k = 2e4 sags by 2 cm).
STIFF_K = 1e8

LECTURE_TAN = 0.1                           # the lecture's slope, normal (0.1, 1)
STEEP_TAN = math.tan(math.radians(20.0))    # the steeper slope of the tests: 20 degrees


def normal_of_tan(tan_theta):
    """Unit normal (sin theta, cos theta) of a slope descending to the right at tan(theta)."""
    theta = math.atan(tan_theta)
    return (math.sin(theta), math.cos(theta))


def downhill(scene):
    """Unit tangent of the slope pointing downhill, (n_y, -n_x)."""
    return FrictionEnergy.tangent(scene.n)


def com(scene, x):
    """Centre of mass of positions (or velocities) x."""
    return np.average(x, axis=0, weights=scene.m)


def loads(scene):
    """Normal load N, downhill drive G_t and friction force F = min(G_t, mu N) on the square, N."""
    total = float(np.sum(scene.m))
    normal_load = -total * float(scene.g @ scene.n)
    drive = total * float(scene.g @ downhill(scene))
    return normal_load, drive, min(drive, scene.mu * normal_load)


def sliding_acceleration(scene):
    """Rigid block, Coulomb friction: a = g (sin theta - mu cos theta) downhill."""
    normal_load, drive, _ = loads(scene)
    return (drive - scene.mu * normal_load) / float(np.sum(scene.m))


def holds(scene):
    """Whether Coulomb friction holds a rigid square on the slope, 0 <= G_t < mu N: where
    closed_forms.creep_speed applies."""
    normal_load, drive, _ = loads(scene)
    return 0.0 <= drive < scene.mu * normal_load


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
    normal_load, _, friction = loads(scene)
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
    overrides = {"slope": normal_of_tan(tan_theta), "mu": mu, "k": k, **overrides}
    probe = build_scene(**{**overrides, "center": (0.0, 10.0)})    # masses, loads
    d0, tilt = resting_pose(probe)
    theta = math.atan2(probe.n[0], probe.n[1])
    angle = -theta - math.asin(tilt)
    half = probe.params["side_len"] / 2
    base = probe.o + d0 * probe.n                                  # midpoint of the bottom edge
    center = base + half * np.array([-math.sin(angle), math.cos(angle)])
    return build_scene(**{**overrides, "angle": angle, "center": tuple(center)})


def free_fall_scene(**overrides):
    """No slope; the square thrown upwards and sideways so both axes are tested."""
    return build_scene(**{"slope": None, "v0": (1.0, 2.0), **overrides})


def free_fall_com(scene, t):
    """x0 + v0 t + 1/2 g t^2 for the centre of mass, at the times t (array)."""
    t = np.asarray(t, dtype=np.float64)[:, None]
    return com(scene, scene.x0) + com(scene, scene.v0) * t + 0.5 * scene.g * t * t
