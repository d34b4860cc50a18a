"""The lecture's case study: an elastic mass-spring square dropped onto a slope with friction.

Library use:   scene = build_scene(mu=0.2);  for record in simulate(scene, steps=300): ...
Command line:  python simulator.py --help

`build_scene` validates every parameter and builds the model once (mesh, masses, rest lengths,
slope, which energy terms exist); `simulate` steps it with time_integrator.step; `run` is the
command line's run, and what it writes (frames, log.csv, plots, summary, index.html) is drawn by the
viewer/ package. pygame is imported only where frames are drawn, so importing this module opens no
window and needs no display.
"""
import os

if __name__ == "__main__":
    # The command line runs on one BLAS thread, set before numpy loads (see benchmarks/README.md, Time per step).
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import decimal
import math
import re
import signal
import sys
import threading
import time
import types
from dataclasses import dataclass, field

import numpy as np

import BarrierEnergy
import square_mesh
import time_integrator
import utils
from viewer import draw, files, recording
from viewer.diagnostics import energies     # noqa: F401  (simulator.energies, as tests and notebooks call it)

DEFAULTS = types.MappingProxyType({
    "side_len": 1.0,            # m
    "n_seg": 4,                 # segments per side
    "rho": 1000.0,              # kg/m^2 (ignored when `mass` is given)
    "mass": None,               # total mass in kg, instead of rho
    "k": 2e4,                   # spring stiffness
    "h": 0.01,                  # time step, s
    "gravity": (0.0, -9.81),    # m/s^2
    "slope": (0.1, 1.0),        # slope normal (normalized when the scene is built); None: no slope
    "slope_point": (0.0, -1.0), # a point on the slope, o
    "mu": 0.11,                 # friction coefficient
    "dhat": BarrierEnergy.DHAT,
    "kappa": BarrierEnergy.KAPPA,
    "epsv": 1e-3,               # m/s
    "tol": 1e-2,                # Newton tolerance on ||p||_inf / h, m/s
    "v0": (0.0, 0.0),           # initial velocity of every node, m/s
    "center": (0.0, 0.0),       # initial centre of the square
    "angle": 0.0,               # initial rotation of the square about its centre, radians
    "friction_updates": 0,      # fixed-point friction updates per step (0: lagged, as the lecture)
    "max_newton_iterations": 1000,  # a safety cap: the hardest tested cases need about 200
    "max_halvings": 60,
})


@dataclass(frozen=True)
class Scene:
    """What a scene *is*; built once by `build_scene` and never changed by stepping."""
    params: types.MappingProxyType  # the validated parameters it was built from (read-only)
    x0: np.ndarray              # (N, 2) initial positions
    v0: np.ndarray              # (N, 2) initial velocities
    e: np.ndarray               # (E, 2) spring node indices
    l2: np.ndarray              # (E,) squared rest lengths
    k: np.ndarray               # (E,) spring stiffnesses
    m: np.ndarray               # (N,) node masses
    contact_area: np.ndarray    # (N,) contact weight per node (side_len / n_seg)
    g: np.ndarray               # (2,) gravity
    n: np.ndarray               # (2,) unit slope normal, or None without a slope
    o: np.ndarray               # (2,) point on the slope, or None
    mu: float
    dhat: float
    kappa: float
    epsv: float
    h: float
    tol: float
    n_seg: int
    side_len: float
    friction_updates: int
    max_newton_iterations: int
    max_halvings: int
    terms: tuple = field(default=())    # the energy terms the Incremental Potential sums
    warnings: tuple = field(default=())  # what this scene's results cannot be trusted for
    solver: utils.SPDSolver = None      # how the Newton system H p = -grad E is solved on this mesh


def _finite(name, value):
    value = utils.as_float(name, value, "must be a finite number")
    if not math.isfinite(value):
        raise ValueError(f"{name} must be finite, got {value}")
    return value


def _whole(name, value, minimum):
    number = utils.as_float(name, value, f"must be a whole number >= {minimum}")
    if not math.isfinite(number) or not number.is_integer() or number < minimum:
        raise ValueError(f"{name} must be a whole number >= {minimum}, got {value}")
    return int(number)


def _vector(name, value):
    try:
        return utils.check_vector(name, value)
    except (TypeError, ValueError) as err:
        if "must" in str(err):
            raise
        raise ValueError(f"{name} must be a 2-vector of numbers, got {value!r}") from None


def _readonly(a):
    a = np.array(a)
    a.setflags(write=False)
    return a


def validate_params(**overrides):
    """The full parameter set (DEFAULTS updated by `overrides`), each checked; ValueError names the bad one."""
    overrides = _resolve_aliases(overrides)
    p = {**DEFAULTS, **overrides}
    for name in ("side_len", "rho", "k", "h", "dhat", "kappa", "tol"):
        p[name] = utils.check_positive(name, p[name])
    p["epsv"] = utils.check_epsv(p["epsv"])
    if p["mass"] is not None:
        p["mass"] = utils.check_positive("mass", p["mass"])
    p["n_seg"] = _whole("n_seg", p["n_seg"], 1)
    _check_memory(p["n_seg"])
    p["friction_updates"] = _whole("friction_updates", p["friction_updates"], 0)
    p["max_newton_iterations"] = _whole("max_newton_iterations", p["max_newton_iterations"], 1)
    p["max_halvings"] = _whole("max_halvings", p["max_halvings"], 1)
    p["mu"] = _finite("mu", p["mu"])
    if p["mu"] < 0:
        raise ValueError(f"mu must be >= 0, got {p['mu']}")
    p["angle"] = _finite("angle", p["angle"])
    for name in ("gravity", "slope_point", "v0", "center"):
        p[name] = tuple(_vector(name, p[name]).tolist())
    if p["slope"] is not None:
        normal = _vector("slope", p["slope"])
        if not np.hypot(*normal) > 0.0:
            raise ValueError(f"slope normal must be non-zero, got {normal.tolist()}")
        if not np.isfinite(np.hypot(*normal)):
            raise ValueError(f"slope normal is too large to normalize, got {normal.tolist()}")
        p["slope"] = tuple(normal.tolist())
    return p


ALIASES = {"dt": "h"}     # other names a user may pass for a parameter (the command line's --dt)


def _resolve_aliases(overrides):
    """`overrides` with each alias renamed to its parameter; ValueError for an unknown name (listing
    the valid ones, and the parameter a command-line flag's name stands for) or a name given twice."""
    out = {}
    for name, value in overrides.items():
        target = ALIASES.get(name, name)
        if target != name and target in overrides:
            raise ValueError(f"{target} is given twice, as {target} and as its alias {name}; give one")
        out[target] = value
    unknown = sorted(set(out) - set(DEFAULTS))
    if unknown:
        hints = [f"{name} is {param} here" for name in unknown for param, flag in FLAGS.items()
                 if param in DEFAULTS and flag == "--" + name.replace("_", "-")]
        raise ValueError(f"unknown scene parameter(s): {', '.join(unknown)}"
                         + (f" ({'; '.join(hints)})" if hints else "")
                         + f"; valid: {', '.join(sorted([*DEFAULTS, *ALIASES]))}")
    return out


# Memory a scene takes per node, measured as the peak resident memory of build_scene plus one time
# step (less the interpreter's) at n_seg = 128 (banded solve, 7.6 KiB/node) to 400 (SuperLU,
# 8.4 to 10 KiB/node, slowly growing with its fill-in), rounded up.
MEMORY_PER_NODE = 16 * 1024


def _physical_memory():
    """This machine's physical memory in bytes, or None where the OS does not say."""
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return None


def _check_memory(n_seg):
    """ValueError if a mesh of n_seg segments per side would not fit this machine's memory,
    estimated as MEMORY_PER_NODE for each of its (n_seg + 1)^2 nodes, before anything is allocated."""
    nodes, have = (n_seg + 1) ** 2, _physical_memory()      # Python ints: exact at any n_seg
    if have is not None and MEMORY_PER_NODE * nodes > have:
        gib = decimal.Decimal(MEMORY_PER_NODE * nodes) / 2**30
        raise ValueError(f"n_seg = {float(n_seg):g} makes {decimal.Decimal(nodes):.3g} nodes, about "
                         f"{gib:.3g} GiB of memory at {MEMORY_PER_NODE // 1024} KiB each, more than this "
                         f"machine's {have / 2**30:.3g} GiB (largest n_seg that fits: "
                         f"{math.isqrt(have // MEMORY_PER_NODE) - 1})")


def resolution_warnings(p, x0=None, n=None, o=None):
    """Parameter combinations the scheme runs stably but cannot resolve, as sentences for the user.

    1. Implicit Euler stays stable at any h, but when one step moves the body by more than its own
       size (|v0| h + |g| h^2 > side_len) the fall and the impact happen inside a single step: the
       landing is perfectly inelastic whatever the physics, and bounce, impact time and contact
       forces mean nothing.
    2. A square that starts at rest on the slope (a node within dhat, tangential speed below eps_v)
       and should slide gains a h = g (sin theta - mu cos theta) h of speed per step. Newton stops once
       its step is below tol (m/s); where a h < tol it can stop before the square ever leaves static
       friction (the static branch's curvature keeps each Newton step small), so the square stays put.
    3. The line search compares values of E, which float64 holds to about eps |E|. A Newton step of
       ||p||_inf = h r moves a node of mass m by h r and lowers E by at least about m (h r)^2 (H >= M);
       below r_floor = sqrt(eps E_scale / m) / h that decrease drowns in E's rounding, and Newton stops
       there (the step is flagged stalled) whatever tol asks. E_scale is gravity's term, the largest:
       h^2 M |g| (max |x0| + side_len). (On the lecture's scene this gives 2.9e-7 m/s; stalls were
       measured from 1e-7 to 2.1e-7 m/s, none at tol = 3e-7.)
    """
    warnings = []
    travel = math.hypot(*p["v0"]) * p["h"] + math.hypot(*p["gravity"]) * p["h"] * p["h"]
    if travel > p["side_len"]:
        warnings.append(f"time step h = {p['h']:g} s moves the square {travel:.3g} m per step, more than its "
                        f"size {p['side_len']:g} m: impacts are not resolved in time (results are qualitative "
                        f"only; use h <= {_floor_digits(_largest_resolving_h(p), 3)} s)")
    if n is not None and p["mu"] > 0:
        g = np.array(p["gravity"])
        g_normal = float(g @ n)
        slide = float(np.hypot(*(g - g_normal * n))) + p["mu"] * min(g_normal, 0.0)
        v_tangential = float(np.hypot(*(np.array(p["v0"]) - (np.array(p["v0"]) @ n) * n)))
        resting = (x0 - o) @ n < p["dhat"]
        if resting.any() and v_tangential < p["epsv"] and 0.0 < slide * p["h"] < p["tol"]:
            warnings.append(f"the square starts at rest on the slope and should slide at {slide:.3g} m/s^2, "
                            f"gaining {slide * p['h']:.3g} m/s per step, less than tol = {p['tol']:g} m/s: "
                            f"Newton may stop before it leaves static friction (use tol <= "
                            f"{slide * p['h'] / 10:.2g})")
    if x0 is not None and p["tol"] < (floor := _round_off_floor(p, x0)):
        warnings.append(f"tol = {p['tol']:g} m/s is below the residual float64 can resolve in this scene (about "
                        f"{floor:.2g} m/s: E's rounding hides smaller Newton steps): Newton stops at that floor where "
                        f"it must, and log.csv flags those steps newton_stalled")
    return tuple(warnings)


def _round_off_floor(p, x0):
    """r_floor = sqrt(eps E_scale / m) / h, at least eps max|x| / h (see resolution_warnings, 3)."""
    total_mass = p["mass"] if p["mass"] is not None else p["rho"] * p["side_len"] ** 2
    reach = float(np.abs(x0).max()) + p["side_len"]
    E_scale = p["h"] ** 2 * total_mass * math.hypot(*p["gravity"]) * reach
    eps = np.finfo(float).eps
    return max(math.sqrt(eps * E_scale / (total_mass / len(x0))), eps * reach) / p["h"]


def _largest_resolving_h(p):
    """The h at which |v0| h + |g| h^2 = side_len: the positive root of g h^2 + v h - L = 0, in the form
    2 L / (v + sqrt(v^2 + 4 g L)), which neither cancels (-v + sqrt(...) is 0 in float64 once
    v^2 >> 4 g L, e.g. v = 1e10 m/s) nor overflows (the root by hypot, not v^2)."""
    v, g, L = math.hypot(*p["v0"]), math.hypot(*p["gravity"]), p["side_len"]
    return 2.0 * L / (v + math.hypot(v, 2.0 * math.sqrt(g * L)))


def _floor_digits(value, digits):
    """`value` > 0 rounded down to `digits` significant digits, as text: a bound stays a bound."""
    exact = decimal.Decimal(value)
    step = decimal.Decimal(1).scaleb(exact.adjusted() - digits + 1)
    return f"{exact.quantize(step, rounding=decimal.ROUND_FLOOR).normalize():g}"


# A node closer to the slope than this many ulps of the coordinates' scale, eps (max_i |x_i| + |o|),
# touches it as far as float64 can tell: x_i itself carries up to 2 roundings (rotation, centre),
# the normalized n 1, and d = n . x_i - n . o 2 more per dot product, each at most eps/2 of its
# scale; 8 covers their sum with a margin (the lecture's 45 degree corner lands 1.1e-16 m away).
ROUNDOFF_ULPS = 8


def _roundoff(x, o):
    """How near the slope a node can be and still be told apart from touching it: ROUNDOFF_ULPS eps
    (max_i |x_i| + |o|)."""
    return ROUNDOFF_ULPS * np.finfo(float).eps * (float(np.hypot(x[:, 0], x[:, 1]).max()) + float(np.hypot(*o)))


def _check_clear_of_slope(p, x, n, o):
    """ValueError unless every node starts above the slope by more than the round-off of the
    coordinates (ROUNDOFF_ULPS): a start within it touches the slope as much as one below it."""
    d = BarrierEnergy.distances(x, n, o)
    i = int(np.argmin(d))
    roundoff = _roundoff(x, o)
    if d[i] > roundoff:
        return
    center = np.array(p["center"])
    moved = center + (p["dhat"] - d[i]) * n
    raise ValueError(
        f"the square starts touching or below the slope: node {i} at {x[i].tolist()} has distance "
        f"{d[i]:.3g} m, not above the round-off of its coordinates ({roundoff:.2g} m); move center "
        f"(now {_show(center)}) away from the slope, e.g. to {_show(moved, ',')}, which puts that "
        f"node dhat = {p['dhat']:g} m above it")


def _show(value, sep=", "):
    """A parameter's value as the user typed it: a number, or a vector's numbers joined by `sep`."""
    if value is None or np.ndim(value) == 0:
        return f"{value:g}" if isinstance(value, float) else str(value)
    return sep.join(f"{float(a):g}" for a in value)


# Every scale the first step computes (an energy term's value or curvature, see _float64_scales)
# must stay below this: the solver squares and sums them (||grad E||_2, dot products, the energies
# summed over nodes), and 1e150^2 summed over the 1e8 nodes that at most fit in memory is still 1e308.
FLOAT64_SCALE_LIMIT = 1e150

# The Newton matrix M + h^2 K: K (the springs, PSD) is singular along the translations, where M alone
# makes it definite, so its smallest eigenvalue is a node mass m and its largest about m + h^2 k (times
# a mesh constant). Cholesky's backward error is a few eps times the largest entry, so m is lost once
# h^2 k / m nears 1/eps: measured, LAPACK's banded Cholesky fails from 0.5/eps (n_seg 4 and 16, h 0.01
# and 1 s); 0.1/eps leaves that factor 5 for the barrier's curvature, which enlarges the largest
# entry at contact but not the smallest eigenvalue (sliding along the slope).
NEWTON_RATIO_LIMIT = 0.1 / np.finfo(float).eps


def _mass_powers(p):
    """The total mass M as powers of the parameters: mass, or rho side_len^2."""
    return {"mass": 1} if p["mass"] is not None else {"rho": 1, "side_len": 2}


def _float64_scales(p, x, n, o):
    """(what, value, powers) for each scale of the first time step's arithmetic, `powers` the
    parameters it grows with (a product of their powers) to name the one that made it too large.
    M total mass, l spring rest length, w contact area, D = |v0| h + |g| h^2 how far
    the first step moves, X the largest coordinate, d the nearest node's distance to the slope (at
    most dhat, where the barrier starts, and at least the round-off below which the start is refused
    as touching). Plain float products: an overflow gives inf, never raises."""
    h, k, v, g = p["h"], p["k"], math.hypot(*p["v0"]), math.hypot(*p["gravity"])
    M = p["mass"] if p["mass"] is not None else p["rho"] * p["side_len"] * p["side_len"]
    l, D, X = p["side_len"] / p["n_seg"], v * h + g * h * h, float(np.abs(x).max())
    mass = _mass_powers(p)
    scales = [
        ("the total mass M", M, mass),
        ("the kinetic energy 1/2 M |v0|^2", 0.5 * M * v * v, {**mass, "v0": 2}),
        ("the first step's inertia term 1/2 M (|v0| h + |g| h^2)^2", 0.5 * M * D * D, {**mass, "v0": 2, "h": 2, "gravity": 2}),
        ("gravity's term h^2 M |g| (max |x| + |v0| h + |g| h^2)", h * h * M * g * (X + D),
         {**mass, "h": 2, "gravity": 1, "center": 1, "side_len": 1}),
        ("the springs' stiffness h^2 k", h * h * k, {"h": 2, "k": 1}),
        ("the springs' energy scale h^2 k l^2", h * h * k * l * l, {"h": 2, "k": 1, "side_len": 2, "n_seg": -2}),
    ]
    if n is not None:
        w, dhat, kappa = p["side_len"] / p["n_seg"], p["dhat"], p["kappa"]
        d = min(max(float(BarrierEnergy.distances(x, n, o).min()), _roundoff(x, o)), dhat)
        barrier = {"h": 2, "kappa": 1, "side_len": 1, "n_seg": -1}
        scales += [
            ("the barrier's energy scale h^2 kappa w dhat", h * h * kappa * w * dhat, {**barrier, "dhat": 1}),
            ("the barrier's curvature h^2 kappa w (1/d + dhat/d^2) / 2", h * h * kappa * w * (1 / d + dhat / d / d) / 2,
             {**barrier, "dhat": 1}),
            ("friction's stiffness h mu M |g| / eps_v", h * p["mu"] * M * g / p["epsv"],
             {**mass, "h": 1, "mu": 1, "gravity": 1, "epsv": -1}),
        ]
    return scales


def _culprit(p, powers):
    """Of the parameters a scale grows with (`powers`, name -> exponent), the one that moved it
    furthest from the lecture's scene: the largest exponent * log10(|value| / |lecture's value|)
    (1 m or 1 m/s for the vectors that are zero there, rho side_len^2 for the mass)."""
    def size(value):
        return float(np.hypot(*value)) if np.ndim(value) else abs(value)

    def reference(name):
        if name == "mass":
            return DEFAULTS["rho"] * DEFAULTS["side_len"] ** 2
        return size(DEFAULTS[name]) or 1.0

    def push(name):
        return powers[name] * math.log10(max(size(p[name]), 1e-300) / reference(name))
    return max(powers, key=push)


def _check_resolved(p, x, o):
    """ValueError where the round-off of the first step's coordinates (ROUNDOFF_ULPS ulps of
    max |x| + |o| + |v0| h + |g| h^2) swallows the mesh spacing l = side_len / n_seg (the springs'
    rest lengths) or dhat (the barrier's reach), or l^2 underflows: the square is too far from the
    origin, or too small, for float64."""
    l, h = p["side_len"] / p["n_seg"], p["h"]
    travel = math.hypot(*p["v0"]) * h + math.hypot(*p["gravity"]) * h * h
    scale = float(np.abs(x).max()) + (0.0 if o is None else float(np.abs(o).max())) + travel
    roundoff = ROUNDOFF_ULPS * np.finfo(float).eps * scale
    if not l * l >= np.finfo(float).tiny:
        raise ValueError(f"side_len = {p['side_len']:g} is too small for float64: the squared spring rest "
                         f"length (side_len / n_seg)^2 = {l * l:.3g} underflows")
    where = {"center": 1, "slope_point": 1, "v0": 1, "gravity": 1, "h": 1}
    for what, length, powers in (("the mesh spacing side_len / n_seg", l, {"side_len": -1, "n_seg": 1}),
                                 ("dhat", p["dhat"], {"dhat": -1, "side_len": 1})):
        if not length > roundoff:
            name = _culprit(p, {**where, **powers})
            raise ValueError(f"{name} = {_show(p[name])} leaves {what} = {length:.3g} m below the round-off "
                             f"of the first step's coordinates, which reach {scale:.3g} m and are rounded to "
                             f"{roundoff:.2g} m (keep every coordinate below {1 / (ROUNDOFF_ULPS * np.finfo(float).eps):.2g} "
                             f"times the spacing and dhat)")


def _check_float64_range(p, x, n, o):
    """ValueError, naming the parameter and value, for a scene whose first time step would overflow
    float64 (a scale of _float64_scales above FLOAT64_SCALE_LIMIT) or whose Newton matrix float64
    cannot resolve (h^2 k / m above NEWTON_RATIO_LIMIT)."""
    for what, value, powers in _float64_scales(p, x, n, o):
        if not value <= FLOAT64_SCALE_LIMIT:
            name = _culprit(p, powers)
            raise ValueError(f"{name} = {_show(p[name])} is beyond float64's range in this scene: {what} "
                             f"would be {value:.3g}, above the {FLOAT64_SCALE_LIMIT:g} whose squares still "
                             f"sum to a finite number")
    m = (p["mass"] if p["mass"] is not None else p["rho"] * p["side_len"] * p["side_len"]) / len(x)
    ratio = p["h"] * p["h"] * p["k"] / m if m > 0.0 else math.inf
    if not ratio <= NEWTON_RATIO_LIMIT:
        name = _culprit(p, {"k": 1, "h": 2, "n_seg": 2, **{a: -b for a, b in _mass_powers(p).items()}})
        raise ValueError(f"{name} = {_show(p[name])}: float64 cannot resolve the Newton matrix M + h^2 K, as "
                         f"h^2 k / m = {ratio:.3g} (h = {p['h']:g} s, k = {p['k']:g}, node mass m = {m:.3g} kg) "
                         f"is above 0.1/eps = {NEWTON_RATIO_LIMIT:.2g}, where m is lost in the round-off of "
                         f"h^2 k (lower k or h, or raise the mass)")


def build_scene(**overrides):
    """Validate the parameters (see DEFAULTS) and build the scene's model once."""
    p = validate_params(**overrides)
    x, e = square_mesh.generate(p["side_len"], p["n_seg"])
    c, s = math.cos(p["angle"]), math.sin(p["angle"])
    x = x @ np.array([[c, s], [-s, c]]) + np.array(p["center"])
    n = o = None
    if p["slope"] is not None:
        n = np.array(p["slope"]) / np.hypot(*p["slope"])
        o = np.array(p["slope_point"])
    _check_float64_range(p, x, n, o)
    _check_resolved(p, x, o)
    if n is not None:
        _check_clear_of_slope(p, x, n, o)
    diff = x[e[:, 0]] - x[e[:, 1]]
    n_nodes = len(x)
    total_mass = p["mass"] if p["mass"] is not None else p["rho"] * p["side_len"] ** 2
    g = np.array(p["gravity"])

    terms = ["inertia", "spring"]
    if np.any(g != 0.0):
        terms.append("gravity")
    if n is not None:
        terms.append("barrier")
        if p["mu"] > 0.0:
            terms.append("friction")

    return Scene(
        params=types.MappingProxyType(p), x0=_readonly(x), v0=_readonly(np.tile(p["v0"], (n_nodes, 1))),
        e=_readonly(np.asfortranarray(e)),      # column by column: e[:, 0] and e[:, 1] gather fast
        l2=_readonly(np.einsum("ij,ij->i", diff, diff)), k=_readonly(np.full(len(e), p["k"])),
        m=_readonly(np.full(n_nodes, total_mass / n_nodes)),
        contact_area=_readonly(np.full(n_nodes, p["side_len"] / p["n_seg"])),
        g=_readonly(g), n=None if n is None else _readonly(n), o=None if o is None else _readonly(o),
        mu=p["mu"], dhat=p["dhat"], kappa=p["kappa"], epsv=p["epsv"], h=p["h"], tol=p["tol"],
        n_seg=p["n_seg"], side_len=p["side_len"], friction_updates=p["friction_updates"],
        max_newton_iterations=p["max_newton_iterations"], max_halvings=p["max_halvings"],
        terms=tuple(terms), warnings=resolution_warnings(p, x, n, o),
        solver=utils.SPDSolver.for_mesh(n_nodes, e))


@dataclass
class StepRecord:
    """One step of a run: its index, time after it, the new state, its report and wall time."""
    index: int
    t: float
    x: np.ndarray
    v: np.ndarray
    report: time_integrator.StepReport
    wall: float


def simulate(scene, steps, x=None, v=None):
    """Yield a StepRecord for each of `steps` time steps from (x, v) (default: the scene's start)."""
    steps = _whole("steps", steps, 1)
    x = scene.x0.copy() if x is None else x
    v = scene.v0.copy() if v is None else v
    for i in range(steps):
        start = time.perf_counter()
        x, v, report = time_integrator.step(scene, x, v, step_index=i)
        yield StepRecord(i, (i + 1) * scene.h, x, v, report, time.perf_counter() - start)


# ------------------------------------------------------------------------------------------------
# Command line
# ------------------------------------------------------------------------------------------------

class CommandLineError(Exception):
    """A bad command line: reported in one line, exit code 2."""


class Parser(argparse.ArgumentParser):
    def error(self, message):
        raise CommandLineError(message)


def _pair(text):
    try:
        values = [float(s) for s in text.replace(",", " ").split()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected two numbers 'X,Y', got {text!r}") from None
    if len(values) != 2:
        raise argparse.ArgumentTypeError(f"expected two numbers 'X,Y', got {text!r}")
    return tuple(values)


def make_parser():
    d = DEFAULTS
    ap = Parser(prog="simulator.py", description="Simulate the lecture's elastic square on a slope "
                "(implicit Euler as optimization, log-barrier contact, semi-implicit friction) and "
                "write PNG frames, OBJ meshes, a CSV log and a summary picture.")
    g = ap.add_argument_group("scene")
    g.add_argument("--mu", type=float, default=d["mu"], help="friction coefficient (default %(default)s)")
    g.add_argument("--h", "--dt", dest="h", type=float, default=d["h"], help="time step in s (default %(default)s)")
    g.add_argument("--n-seg", type=float, default=d["n_seg"], help="segments per side (default %(default)s)")
    g.add_argument("--side", dest="side_len", type=float, default=d["side_len"], help="side length in m (default %(default)s)")
    g.add_argument("--k", type=float, default=d["k"], help="spring stiffness (default %(default)s)")
    g.add_argument("--density", dest="rho", type=float, default=d["rho"], help="kg/m^2 (default %(default)s)")
    g.add_argument("--mass", type=float, default=None, help="total mass in kg, instead of --density")
    slope = g.add_mutually_exclusive_group()
    slope.add_argument("--slope-normal", type=_pair, default=d["slope"], metavar="NX,NY",
                       help="slope normal, normalized for you (default 0.1,1)")
    slope.add_argument("--slope-angle", type=float, metavar="DEG",
                       help="slope angle in degrees, descending to the right")
    slope.add_argument("--no-slope", action="store_true", help="free fall: no slope, no contact")
    g.add_argument("--slope-point", type=_pair, default=d["slope_point"], metavar="OX,OY",
                   help="a point on the slope (default 0,-1)")
    g.add_argument("--center", type=_pair, default=d["center"], metavar="X,Y",
                   help="initial centre of the square in m (default 0,0)")
    g.add_argument("--v0", type=_pair, default=d["v0"], metavar="VX,VY", help="initial velocity in m/s (default 0,0)")
    g.add_argument("--gravity", type=_pair, default=d["gravity"], metavar="GX,GY", help="m/s^2 (default 0,-9.81)")
    g.add_argument("--dhat", type=float, default=d["dhat"], help="barrier activation distance in m (default %(default)s)")
    g.add_argument("--kappa", type=float, default=d["kappa"], help="barrier stiffness (default %(default)s)")
    g.add_argument("--epsv", type=float, default=d["epsv"], help="friction eps_v in m/s (default %(default)s)")
    g.add_argument("--tol", type=float, default=d["tol"], help="Newton tolerance on ||p||_inf/h in m/s (default %(default)s)")
    g.add_argument("--friction-iterations", dest="friction_updates", type=float, default=0,
                   help="fixed-point friction updates per step for fully implicit friction (default 0: lagged)")
    g.add_argument("--max-newton", dest="max_newton_iterations", type=float, default=d["max_newton_iterations"],
                   help="Newton iteration cap per solve (default %(default)s)")
    r = ap.add_argument_group("run and output")
    length = r.add_mutually_exclusive_group()
    length.add_argument("--duration", type=float, default=3.0, help="simulated seconds (default %(default)s)")
    length.add_argument("--steps", type=float, help="number of time steps, instead of --duration")
    r.add_argument("--out", help="output folder (default output; with --window, files only when given)")
    r.add_argument("--frame-stride", type=float, help="write a frame every N steps (default: 30 or more a simulated second)")
    r.add_argument("--no-forces", action="store_true", help="draw no force arrows in the frames")
    r.add_argument("--no-frames", action="store_true", help="write only the CSV log and summary picture")
    r.add_argument("--window", action="store_true", help="show the run live in a pygame window (see README, Live demo)")
    r.add_argument("--size", type=float, help="--window: its side in pixels (default: fit the display)")
    r.add_argument("--speed", type=float, default=1.0,
                   help="--window: simulated seconds per wall-clock second (default %(default)s; 0.25: slow motion)")
    return ap


def scene_from_args(args):
    overrides = {name: getattr(args, name) for name in (
        "mu", "h", "n_seg", "side_len", "k", "rho", "mass", "slope_point", "center", "v0", "gravity", "dhat",
        "kappa", "epsv", "tol", "friction_updates", "max_newton_iterations")}
    if args.no_slope:
        overrides["slope"] = None
    elif args.slope_angle is not None:
        theta = math.radians(_finite("slope-angle", args.slope_angle))
        if not -90.0 < args.slope_angle < 90.0:
            raise ValueError(f"slope-angle must be in (-90, 90) degrees, got {args.slope_angle}")
        overrides["slope"] = (math.sin(theta), math.cos(theta))
    else:
        overrides["slope"] = args.slope_normal
    return build_scene(**overrides)


def steps_from_args(args, scene):
    if args.steps is not None:
        return _whole("steps", args.steps, 1)
    duration = utils.check_positive("duration", args.duration)
    if duration < scene.h:
        raise ValueError(f"duration {duration:g} s is shorter than one time step h = {scene.h:g} s")
    steps = duration / scene.h
    if not math.isfinite(steps):
        raise ValueError(f"duration {duration:g} s is more time steps of h = {scene.h:g} s than float64 "
                         f"can count (use --steps, or a larger h)")
    return int(round(steps))


def prepare_output(folder):
    """Create the output folder and prove it can be written; ValueError otherwise."""
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as err:
        raise ValueError(f"out folder {folder!r} cannot be created: {err.strerror or err}") from None
    try:
        probe = os.path.join(folder, ".write-test")
        with open(probe, "w") as f:
            f.write("ok")
        os.remove(probe)
    except OSError as err:      # e.g. /proc/self: a folder, where creating a file says ENOENT
        raise ValueError(f"out folder {folder!r} cannot be written: creating a file in it failed "
                         f"({err.strerror or err})") from None


DEFAULT_OUT = "output"      # the output folder without --out
FRAMES_PER_SECOND = 30      # at least this many frames per simulated second by default
COMPARISON_DURATION = 6.0   # s: a comparison's default, long enough to see mu = 0.11 stop (about 5.5 s)


def parse_command_line(parser, argv):
    """One argparse Namespace per run. Any one scalar scene flag may take a comma-separated list
    (`--mu 0.1,0.11,0.2`), a pair flag a ';'-separated list of pairs (`--v0 "1,0;2,0"`): the
    command line is then parsed once per value, each Namespace carrying its run's `label` and file
    `tag`, and without --duration or --steps a comparison runs COMPARISON_DURATION seconds."""
    scene = next(group for group in parser._action_groups if group.title == "scene")
    options = {name: action for action in scene._group_actions for name in action.option_strings}
    lists = []                      # (token index, flag, values, whether written --flag=value)
    for i, token in enumerate(argv):
        flag, joined, value = token.partition("=")
        action = options.get(flag)
        if action is None or action.nargs == 0 or (not joined and i + 1 == len(argv)):
            continue                # not a scene flag, a switch, or a flag without its value
        value = value if joined else argv[i + 1]
        separator = ";" if "," in (action.metavar or "") else ","       # a pair flag's metavar is 'X,Y'
        if separator in value:
            lists.append((i, flag, [v.strip().replace(" ", "") for v in value.split(separator)], bool(joined)))
    if not lists:
        args = parser.parse_args(argv)
        args.label, args.tag = "", ""
        return [args]
    if len(lists) > 1:
        raise CommandLineError(f"only one scene flag may take a list of values, got {lists[0][1]} and {lists[1][1]}")
    i, flag, values, joined = lists[0]
    if len(set(values)) < len(values):
        raise CommandLineError(f"{flag}: the list {','.join(values)} repeats a value")
    runs = []
    for value in values:
        one = argv[:i] + ([f"{flag}={value}"] if joined else [flag, value]) + argv[i + (1 if joined else 2):]
        if not {"--duration", "--steps"} & {t.partition("=")[0] for t in argv}:
            one += ["--duration", str(COMPARISON_DURATION)]
        args = parser.parse_args(one)
        args.label, args.tag = f"{flag.lstrip('-')} = {value}", f"{flag.lstrip('-')}={value.replace(',', '_')}"
        runs.append(args)
    return runs


def frame_stride(args, scenes):
    """--frame-stride, or by default the largest stride giving FRAMES_PER_SECOND frames per
    simulated second at the smallest h (3 at h = 0.01: 33 frames per second)."""
    if args.frame_stride is not None:
        return _whole("frame-stride", args.frame_stride, 1)
    return max(1, math.floor(1.0 / (FRAMES_PER_SECOND * min(s.h for s in scenes)) + 1e-9))


class Terminated(KeyboardInterrupt):
    """SIGTERM, handled as Ctrl+C is: the run stops, says so, and keeps what it wrote."""


def _raise_terminated(signum, frame):
    raise Terminated()


def _main_thread():
    """Signal handlers can only be set from the main thread (run() may be called from another)."""
    return threading.current_thread() is threading.main_thread()


def run(runs, log=None):
    """Run the command line's scene (or, for a comparison, its scenes side by side), writing frames,
    OBJs, log.csv, summary.png, plots.png and index.html; messages go to `log` (default stderr).
    Returns the exit code."""
    log = sys.stderr if log is None else log
    runs = runs if isinstance(runs, list) else [runs]
    for args_k in runs:                                 # a Namespace from make_parser alone is one run
        args_k.label, args_k.tag = getattr(args_k, "label", ""), getattr(args_k, "tag", "")
    scenes = [scene_from_args(args) for args in runs]
    steps = [steps_from_args(args, scene) for args, scene in zip(runs, scenes)]
    args = runs[0]
    out = DEFAULT_OUT if args.out is None else args.out     # --window writes files only when --out is given
    stride = frame_stride(args, scenes)
    prepare_output(out)
    for args_k, scene in zip(runs, scenes):
        for warning in scene.warnings:
            print(f"simulator.py: warning: {args_k.label + ': ' if args_k.label else ''}{warning}", file=log)
    frames, tracks, frame_log, failure = not args.no_frames, [], [], None
    start = time.perf_counter()
    previous = signal.signal(signal.SIGTERM, _raise_terminated) if _main_thread() else None
    try:
        files.remove_earlier_run(out)
        for k, (args_k, scene, n) in enumerate(zip(runs, scenes, steps)):
            tracks.append(recording.Track(scene, n, simulate(scene, n), args_k.label or f"mu = {scene.mu:g}",
                                          args_k.tag, draw.run_color(k), os.path.join(out, files.log_csv(args_k.tag))))
        recording.record(tracks, out, stride, frames, not args.no_forces, log, frame_log)
    except time_integrator.SimulationError as err:
        failure = (1, f"stopped: simulation failed: {err}")
    except KeyboardInterrupt as err:
        failure = (143, "stopped: terminated (SIGTERM)") if isinstance(err, Terminated) else (130, "stopped: interrupted")
    except OSError as err:
        failure = (1, _write_error(err, out))
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
        for track in tracks:
            track.csv.close()
    wall = time.perf_counter() - start
    if tracks and (failure is None or not failure[1].startswith("error")):     # not on a full disk
        try:
            recording.finish(tracks, out, stride, frames, frame_log, _summary_header(tracks, runs))
        except OSError as err:
            failure = (1, _write_error(err, out))
    if failure is not None:
        print(f"simulator.py: {failure[1]}; {tracks[0].step if tracks else 0} steps kept in {out}/", file=log)
        return failure[0]
    written = ("frames, OBJs, log.csv, plots.png, summary.png and index.html" if frames
               else "log.csv, plots.png and summary.png")
    print(f"simulated {steps[0]} steps ({steps[0] * scenes[0].h:.2f} s){f' x {len(runs)} runs' if len(runs) > 1 else ''}"
          f" in {wall:.2f} s wall; {written} in {out}/", file=log)
    return 0


def _write_error(err, out):
    """A failed write (a full disk, a folder gone) as the one line's text."""
    return f"error: cannot write {err.filename or out}: {err.strerror or err}"


def _summary_header(tracks, runs):
    """The parameters, written on summary.png."""
    scene, p = tracks[0].scene, tracks[0].scene.params
    lines = [f"mu = {scene.mu:g}   h = {scene.h:g} s   k = {p['k']:g}   n_seg = {scene.n_seg}",
             f"slope normal = {None if scene.n is None else np.round(scene.n, 4).tolist()}   "
             f"dhat = {scene.dhat:g}   kappa = {scene.kappa:g}   eps_v = {scene.epsv:g}"]
    if len(runs) > 1:
        lines.insert(0, "comparison: " + ", ".join(tr.label for tr in tracks) + "; otherwise as the first:")
    return lines


# scene parameter -> the flag that sets it, so a command-line error names what the user typed
FLAGS = {"side_len": "--side", "n_seg": "--n-seg", "rho": "--density", "mass": "--mass", "k": "--k", "h": "--h",
         "mu": "--mu", "dhat": "--dhat", "kappa": "--kappa", "epsv": "--epsv", "tol": "--tol",
         "friction_updates": "--friction-iterations", "max_newton_iterations": "--max-newton",
         "slope": "--slope-normal", "slope normal": "--slope-normal", "slope-angle": "--slope-angle",
         "slope_point": "--slope-point", "center": "--center", "v0": "--v0", "gravity": "--gravity", "steps": "--steps",
         "duration": "--duration", "frame-stride": "--frame-stride", "out folder": "--out",
         "the square starts": "--center"}


def _flag_for(message):
    for name in sorted(FLAGS, key=len, reverse=True):
        if message.startswith(name + " "):
            return f"{FLAGS[name]}: "
    return ""


def _attach_negative_values(argv):
    """['--k', '-2e4'] -> ['--k=-2e4']: argparse takes '-2e4', '-1,2' or '-inf' for an option, but no
    flag starts with a digit, a dot, 'inf' or 'nan', so such a token is always the previous option's value."""
    out = []
    for token in argv:
        if out and out[-1].startswith("--") and "=" not in out[-1] and re.match(r"^-([0-9.]|inf|nan)", token, re.I):
            out[-1] = f"{out[-1]}={token}"
        else:
            out.append(token)
    return out


def main(argv=None):
    try:
        runs = parse_command_line(make_parser(), _attach_negative_values(sys.argv[1:] if argv is None else argv))
        if runs[0].window:
            if len(runs) > 1:
                raise CommandLineError(f"--window shows one run; --{runs[0].label.split(' = ')[0]} was given "
                                       f"{len(runs)} values (compare them without --window)")
            from viewer.window import run_window
            return run_window(runs[0])
        return run(runs)
    except CommandLineError as err:
        print(f"simulator.py: error: {err}", file=sys.stderr)
        return 2
    except ValueError as err:
        print(f"simulator.py: error: {_flag_for(str(err))}{err}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
