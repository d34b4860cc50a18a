"""The square's scene checks, run once by simulator.build_scene: each parameter, then the start,
against what float64 and this machine can hold, and the warnings of what a scene's results cannot
be trusted for. Not the lecture's path: a student can skip this module.
"""
import decimal
import math
import os

import numpy as np

import utils
from utils import ParameterError

EPS = np.finfo(float).eps
# A node nearer the slope than ROUNDOFF_ULPS eps (max_i |x_i| + |o|) touches it as far as float64
# can tell: x_i, n and d = n . (x_i - o) carry about 5 roundings of eps/2 each.
ROUNDOFF_ULPS = 8
# Squares of 1e150 summed over the 1e8 nodes that fit in memory stay below float64's 1.8e308.
FLOAT64_SCALE_LIMIT = 1e150
# M + h^2 K: LAPACK's banded Cholesky loses the node mass m from h^2 k / m = 0.5/eps (measured);
# 0.1/eps leaves a factor 5 for the barrier's curvature.
NEWTON_RATIO_LIMIT = 0.1 / EPS
# Peak resident memory per node of build_scene plus one step, measured at n_seg 128 to 400
# (7.6 to 10 KiB), rounded up.
MEMORY_PER_NODE = 16 * 1024


def check_params(defaults, aliases, overrides):
    """`defaults` updated by `overrides` (aliases renamed to their parameter), values checked."""
    checks = {**dict.fromkeys(("side_len", "rho"), utils.check_positive), **utils.SOLVER_CHECKS,
              "n_seg": lambda name, value: check_memory(utils.check_whole(name, value)),
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


def _mass_powers(p):
    """The parameters the total mass grows with, and their exponents."""
    return {"mass": 1} if p["mass"] is not None else {"rho": 1, "side_len": 2}


def physical_memory():
    """This machine's physical memory in bytes, or None where the OS does not say."""
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return None


def check_memory(n_seg):
    """n_seg, or a ValueError if (n_seg + 1)^2 nodes of MEMORY_PER_NODE each do not fit here."""
    nodes, have = (n_seg + 1) ** 2, physical_memory()      # Python ints: exact at any n_seg
    if have is not None and MEMORY_PER_NODE * nodes > have:
        need = decimal.Decimal(MEMORY_PER_NODE * nodes) / 2**30
        message = (f"n_seg = {float(n_seg):g} makes {decimal.Decimal(nodes):.3g} nodes, about "
                   f"{need:.3g} GiB of memory at {MEMORY_PER_NODE // 1024} KiB each, more than "
                   f"this machine's {have / 2**30:.3g} GiB (largest n_seg that fits: "
                   f"{math.isqrt(have // MEMORY_PER_NODE) - 1})")
        raise ParameterError("n_seg", message)
    return n_seg


def roundoff(x, o):
    """How near the slope a node can be and still be told apart from touching it."""
    return ROUNDOFF_ULPS * EPS * (float(np.hypot(x[:, 0], x[:, 1]).max()) + float(np.hypot(*o)))


def _shown(value):
    """A parameter's value as the user typed it: a number, or a vector's numbers joined by ', '."""
    return ", ".join(f"{float(a):g}" for a in value) if np.ndim(value) else f"{value:g}"


def _culprit(p, defaults, powers):
    """Of the parameters a scale grows with (name -> exponent), the one that moved it furthest
    from the lecture's scene: the largest exponent * log10(size / lecture's size)."""
    def size(name, of):
        if name == "mass":
            return total_mass(of)
        return float(np.hypot(*of[name])) if np.ndim(of[name]) else abs(of[name])

    def push(name):
        return powers[name] * math.log10(max(size(name, p), 1e-300) / (size(name, defaults) or 1.0))
    return max(powers, key=push)


def _scales(p, x, o, d):
    """The first step's scales (what, value, the parameters' exponents in it) (docs/limits.md)."""
    h, k, v, g = p["h"], p["k"], math.hypot(*p["v0"]), math.hypot(*p["gravity"])
    M, Mp = total_mass(p), _mass_powers(p)
    l, D, X = p["side_len"] / p["n_seg"], v * h + g * h * h, float(np.abs(x).max())
    scales = [
        ("the total mass M", M, Mp),
        ("the kinetic energy 1/2 M |v0|^2", 0.5 * M * v * v, {**Mp, "v0": 2}),
        ("the first step's inertia term 1/2 M (|v0| h + |g| h^2)^2", 0.5 * M * D * D,
         {**Mp, "v0": 2, "h": 2, "gravity": 2}),
        ("gravity's term h^2 M |g| (max |x| + |v0| h + |g| h^2)", h * h * M * g * (X + D),
         {**Mp, "h": 2, "gravity": 1, "center": 1, "side_len": 1}),
        ("the springs' stiffness h^2 k", h * h * k, {"h": 2, "k": 1}),
        ("the springs' energy scale h^2 k l^2", h * h * k * l * l,
         {"h": 2, "k": 1, "side_len": 2, "n_seg": -2})]
    if d is None:
        return scales
    barrier = {"h": 2, "kappa": 1, "side_len": 1, "n_seg": -1}
    kappa_w = h * h * p["kappa"] * l                                # the contact area w = l
    near = min(max(float(d.min()), roundoff(x, o)), p["dhat"])
    return scales + [
        ("the barrier's energy scale h^2 kappa w dhat", kappa_w * p["dhat"],
         {**barrier, "dhat": 1}),
        ("the barrier's curvature h^2 kappa w (1/d + dhat/d^2) / 2",
         kappa_w * (1 / near + p["dhat"] / near / near) / 2, {**barrier, "dhat": -1}),
        ("friction's stiffness h mu M |g| / eps_v", h * p["mu"] * M * g / p["epsv"],
         {**Mp, "h": 1, "mu": 1, "gravity": 1, "epsv": -1})]


def check_start(p, defaults, x, n, o, d):
    """ValueError, naming the parameter and its value, where the first step from x leaves float64:
    a scale above FLOAT64_SCALE_LIMIT, h^2 k / m above NEWTON_RATIO_LIMIT, the spacing or dhat
    below the coordinates' round-off, or a node (distances d) within round-off of the slope."""
    for what, value, powers in _scales(p, x, o, d):
        if not value <= FLOAT64_SCALE_LIMIT:
            name = _culprit(p, defaults, powers)
            message = (f"{name} = {_shown(p[name])} is beyond float64's range in this scene: "
                       f"{what} would be {value:.3g}, above the {FLOAT64_SCALE_LIMIT:g} whose "
                       f"squares still sum to a finite number")
            raise ParameterError(name, message)
    h, k = p["h"], p["k"]
    m = total_mass(p) / len(x)
    ratio = h * h * k / m if m > 0.0 else math.inf     # a mass that underflowed resolves nothing
    if not ratio <= NEWTON_RATIO_LIMIT:
        mass = {a: -b for a, b in _mass_powers(p).items()}
        name = _culprit(p, defaults, {"k": 1, "h": 2, "n_seg": 2, **mass})
        message = (f"{name} = {_shown(p[name])}: float64 cannot resolve the Newton matrix "
                   f"M + h^2 K, as h^2 k / m = {ratio:.3g} (node mass m = {m:.3g} kg) is above "
                   f"0.1/eps = {NEWTON_RATIO_LIMIT:.2g}: lower k or h, or raise the mass")
        raise ParameterError(name, message)
    if not h * h >= np.finfo(float).tiny:
        raise ParameterError("h", f"h = {h:g} s is too small for float64: h^2 = {h * h:.3g} "
                                  f"underflows (h >= 1.5e-154 s)")
    travel = math.hypot(*p["v0"]) * h + math.hypot(*p["gravity"]) * h * h
    scale = float(np.abs(x).max()) + (0.0 if o is None else float(np.abs(o).max())) + travel
    lengths = (("the mesh spacing side_len / n_seg", p["side_len"] / p["n_seg"],
                {"side_len": -1, "n_seg": 1}),
               ("dhat", p["dhat"], {"dhat": -1, "side_len": 1}))
    for what, length, powers in lengths:
        if not length > ROUNDOFF_ULPS * EPS * scale:
            moved = {"center": 1, "slope_point": 1, "v0": 1, "gravity": 1, "h": 1, **powers}
            name = _culprit(p, defaults, moved)
            message = (f"{name} = {_shown(p[name])} leaves {what} = {length:.3g} m below the "
                       f"round-off of the first step's coordinates, which reach {scale:.3g} m "
                       f"(keep every coordinate below {1 / (ROUNDOFF_ULPS * EPS):.2g} times the "
                       f"spacing and dhat)")
            raise ParameterError(name, message)
    if d is not None and not d.min() > roundoff(x, o):
        i = int(np.argmin(d))
        moved = _shown(np.array(p["center"]) + (p["dhat"] - d[i]) * n).replace(", ", ",")
        message = (f"the square starts touching or below the slope: node {i} at {x[i].tolist()} "
                   f"has distance {d[i]:.3g} m, not above the round-off of its coordinates "
                   f"({roundoff(x, o):.2g} m); move center (now {_shown(p['center'])}) away from "
                   f"the slope, e.g. to {moved}, which puts that node dhat = {p['dhat']:g} m "
                   f"above it")
        raise ParameterError("center", message)


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
    floor = max(math.sqrt(EPS * h * h * M * g * reach / (M / len(x))), EPS * reach) / h
    if p["tol"] < floor:
        warnings.append(f"tol = {p['tol']:g} m/s is below the residual float64 can resolve in this "
                        f"scene, about {floor:.2g} m/s: Newton stops at that floor where it must, "
                        f"and log.csv flags those steps newton_stalled (docs/limits.md)")
    return tuple(warnings)
