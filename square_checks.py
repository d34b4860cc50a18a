"""The square's scene checks, run once by simulator.build_scene: each parameter, then the start,
against what float64 and this machine can hold, and the warnings of what a scene's results cannot be
trusted for. Not the lecture's path: a student can skip this module. Each check knows the square's
parameters by name (simulator.DEFAULTS); generic input checks are utils'.
"""
import decimal
import math
import os

import numpy as np

from utils import (NEWTON_STARTS, ParameterError, as_float, check_choice, check_epsv, check_positive, check_vector,
                   check_whole)

# ----------------------------------------------------------------------------------------------

EPS = np.finfo(float).eps
# A node nearer the slope than ROUNDOFF_ULPS eps (max_i |x_i| + |o|) touches it as far as float64 can
# tell: x_i carries up to 2 roundings (rotation, centre), the normalized n 1, d = n . (x_i - o) 2 more
# per dot product, each at most eps/2 of its scale; 8 covers their sum with a margin.
ROUNDOFF_ULPS = 8
# The first step squares and sums its scales (||grad E||_2, the energies over the nodes): 1e150^2
# summed over the 1e8 nodes that at most fit in memory is still below float64's 1.8e308.
FLOAT64_SCALE_LIMIT = 1e150
# M + h^2 K: its smallest eigenvalue is a node mass m (K is singular along translations), its largest
# about m + h^2 k. Cholesky loses m once h^2 k / m nears 1/eps (measured: LAPACK's banded Cholesky
# fails from 0.5/eps); 0.1/eps leaves a factor 5 for the barrier's curvature at contact.
NEWTON_RATIO_LIMIT = 0.1 / EPS
# Peak resident memory of build_scene plus one step, per node, measured at n_seg 128 (banded solve,
# 7.6 KiB) to 400 (SuperLU, 8.4 to 10 KiB, growing slowly with its fill-in), rounded up.
MEMORY_PER_NODE = 16 * 1024


def check_params(defaults, aliases, overrides):
    """`defaults` updated by `overrides` (each alias renamed to its parameter), every value checked."""
    unknown = sorted(set(overrides) - set(defaults) - set(aliases))
    if unknown:
        raise ParameterError(unknown[0], f"unknown scene parameter(s): {', '.join(unknown)}; valid: "
                         f"{', '.join(sorted([*defaults, *aliases]))}")
    p = dict(defaults)
    for name, value in overrides.items():
        if aliases.get(name, name) != name and aliases[name] in overrides:
            raise ParameterError(aliases[name], f"{aliases[name]} is given twice, as {aliases[name]} and as its alias {name}; give one")
        p[aliases.get(name, name)] = value
    if p["mass"] is not None and "rho" in overrides:
        raise ParameterError("mass", f"mass = {p['mass']} and rho = {p['rho']} are both given: the total mass is mass, "
                         f"or rho side_len^2; give one")
    for name in ("side_len", "rho", "k", "h", "dhat", "kappa", "tol") + ("mass",) * (p["mass"] is not None):
        p[name] = check_positive(name, p[name])
    p["epsv"] = check_epsv(p["epsv"])
    for name, minimum in (("n_seg", 1), ("friction_updates", 0), ("max_newton_iterations", 1), ("max_halvings", 1)):
        p[name] = check_whole(name, p[name], minimum)
    check_memory(p["n_seg"])
    p["newton_start"] = check_choice("newton_start", p["newton_start"], NEWTON_STARTS)
    for name in ("mu", "angle"):
        p[name] = as_float(name, p[name], "must be a finite number")
        if not np.isfinite(p[name]):
            raise ParameterError(name, f"{name} must be finite, got {p[name]}")
    if p["mu"] < 0:
        raise ParameterError("mu", f"mu must be >= 0, got {p['mu']}")
    for name in ("gravity", "slope_point", "v0", "center") + ("slope",) * (p["slope"] is not None):
        p[name] = tuple(check_vector(name, p[name]).tolist())
    if p["slope"] is not None:
        slope_normal(p["slope"])
    return p


def slope_normal(slope):
    """The slope's unit normal n = s / |s|, with s = slope / max_i |slope_i| first: scaled so, any
    components float64 holds (subnormal ones too, 1e-320) normalize to unit length within 1 eps, and
    the lecture's (0.1, 1) bit for bit as slope / |slope|. ValueError for a zero or non-finite slope."""
    scale = float(np.abs(slope).max())
    if not 0.0 < scale < np.inf:
        problem = "must be non-zero" if scale == 0.0 else "must be finite"
        raise ParameterError("slope", f"slope normal {problem}, got {list(slope)}")
    s = np.array(slope) / scale
    return s / np.hypot(*s)


def total_mass(p):
    """The scene's total mass M, kg: `mass` where given, else rho side_len^2 (a product: inf, never an
    OverflowError, for a size beyond float64)."""
    return p["mass"] if p["mass"] is not None else p["rho"] * p["side_len"] * p["side_len"]


def physical_memory():
    """This machine's physical memory in bytes, or None where the OS does not say."""
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return None


def check_memory(n_seg):
    """ValueError if the (n_seg + 1)^2 nodes, MEMORY_PER_NODE each, would not fit this machine's memory."""
    nodes, have = (n_seg + 1) ** 2, physical_memory()      # Python ints: exact at any n_seg
    if have is not None and MEMORY_PER_NODE * nodes > have:
        raise ParameterError("n_seg", f"n_seg = {float(n_seg):g} makes {decimal.Decimal(nodes):.3g} nodes, about "
                         f"{decimal.Decimal(MEMORY_PER_NODE * nodes) / 2**30:.3g} GiB of memory at "
                         f"{MEMORY_PER_NODE // 1024} KiB each, more than this machine's {have / 2**30:.3g} GiB "
                         f"(largest n_seg that fits: {math.isqrt(have // MEMORY_PER_NODE) - 1})")


def roundoff(x, o):
    """How near the slope a node can be and still be told apart from touching it: ROUNDOFF_ULPS eps
    (max_i |x_i| + |o|)."""
    return ROUNDOFF_ULPS * EPS * (float(np.hypot(x[:, 0], x[:, 1]).max()) + float(np.hypot(*o)))


def _shown(value):
    """A parameter's value as the user typed it: a number, or a vector's numbers joined by ', '."""
    return ", ".join(f"{float(a):g}" for a in value) if np.ndim(value) else f"{value:g}"


def _culprit(p, defaults, powers):
    """Of the parameters a scale grows with (name -> exponent), the one that moved it furthest from the
    lecture's scene: the largest exponent * log10(size / lecture's size) (1 for a zero vector)."""
    def size(name, of):
        if name == "mass":
            return total_mass(of)
        return float(np.hypot(*of[name])) if np.ndim(of[name]) else abs(of[name])
    def push(name):
        return powers[name] * math.log10(max(size(name, p), 1e-300) / (size(name, defaults) or 1.0))
    return max(powers, key=push)


def check_start(p, defaults, x, n, o, d):
    """ValueError, naming the parameter and its value, where the first time step from x leaves what
    float64 can do: a scale of its arithmetic above FLOAT64_SCALE_LIMIT (M total mass, D = |v0| h + |g|
    h^2 how far it moves, X = max |x|, l = side_len / n_seg, w the contact area, d the nearest node's
    distance to the slope); h^2 k / m above NEWTON_RATIO_LIMIT; the spacing l or dhat below the
    coordinates' round-off; or a node within round-off of the slope (d from BarrierEnergy.distances)."""
    h, k, v, g = p["h"], p["k"], math.hypot(*p["v0"]), math.hypot(*p["gravity"])
    Mp = {"mass": 1} if p["mass"] is not None else {"rho": 1, "side_len": 2}
    M = total_mass(p)
    l, D, X = p["side_len"] / p["n_seg"], v * h + g * h * h, float(np.abs(x).max())
    scales = [("the total mass M", M, Mp), ("the kinetic energy 1/2 M |v0|^2", 0.5 * M * v * v, {**Mp, "v0": 2}),
              ("the first step's inertia term 1/2 M (|v0| h + |g| h^2)^2", 0.5 * M * D * D,
               {**Mp, "v0": 2, "h": 2, "gravity": 2}),
              ("gravity's term h^2 M |g| (max |x| + |v0| h + |g| h^2)", h * h * M * g * (X + D),
               {**Mp, "h": 2, "gravity": 1, "center": 1, "side_len": 1}),
              ("the springs' stiffness h^2 k", h * h * k, {"h": 2, "k": 1}),
              ("the springs' energy scale h^2 k l^2", h * h * k * l * l, {"h": 2, "k": 1, "side_len": 2, "n_seg": -2})]
    if d is not None:
        w, barrier = l, {"h": 2, "kappa": 1, "side_len": 1, "n_seg": -1}
        near = min(max(float(d.min()), roundoff(x, o)), p["dhat"])     # at most dhat: grows like 1/dhat
        scales += [("the barrier's energy scale h^2 kappa w dhat", h * h * p["kappa"] * w * p["dhat"],
                    {**barrier, "dhat": 1}),
                   ("the barrier's curvature h^2 kappa w (1/d + dhat/d^2) / 2",
                    h * h * p["kappa"] * w * (1 / near + p["dhat"] / near / near) / 2, {**barrier, "dhat": -1}),
                   ("friction's stiffness h mu M |g| / eps_v", h * p["mu"] * M * g / p["epsv"],
                    {**Mp, "h": 1, "mu": 1, "gravity": 1, "epsv": -1})]
    for what, value, powers in scales:
        if not value <= FLOAT64_SCALE_LIMIT:
            name = _culprit(p, defaults, powers)
            raise ParameterError(name, f"{name} = {_shown(p[name])} is beyond float64's range in this scene: {what} would "
                             f"be {value:.3g}, above the {FLOAT64_SCALE_LIMIT:g} whose squares still sum to a "
                             f"finite number")
    m = M / len(x)
    ratio = h * h * k / m if m > 0.0 else math.inf         # a mass that underflowed to 0 resolves nothing
    if not ratio <= NEWTON_RATIO_LIMIT:
        name = _culprit(p, defaults, {"k": 1, "h": 2, "n_seg": 2, **{a: -b for a, b in Mp.items()}})
        raise ParameterError(name, f"{name} = {_shown(p[name])}: float64 cannot resolve the Newton matrix M + h^2 K, as "
                         f"h^2 k / m = {ratio:.3g} (h = {h:g} s, k = {k:g}, node mass m = {m:.3g} kg) is "
                         f"above 0.1/eps = {NEWTON_RATIO_LIMIT:.2g}, where m is lost in the round-off of h^2 k "
                         f"(lower k or h, or raise the mass)")
    if not h * h >= np.finfo(float).tiny:
        raise ParameterError("h", f"h = {h:g} s is too small for float64: h^2 = {h * h:.3g} underflows (h >= 1.5e-154 s)")
    scale = X + (0.0 if o is None else float(np.abs(o).max())) + D
    for what, length, powers in (("the mesh spacing side_len / n_seg", l, {"side_len": -1, "n_seg": 1}),
                                 ("dhat", p["dhat"], {"dhat": -1, "side_len": 1})):
        if not length > ROUNDOFF_ULPS * EPS * scale:
            name = _culprit(p, defaults, {"center": 1, "slope_point": 1, "v0": 1, "gravity": 1, "h": 1, **powers})
            raise ParameterError(name, f"{name} = {_shown(p[name])} leaves {what} = {length:.3g} m below the round-off of "
                             f"the first step's coordinates, which reach {scale:.3g} m (keep every coordinate "
                             f"below {1 / (ROUNDOFF_ULPS * EPS):.2g} times the spacing and dhat)")
    if d is not None and not d.min() > roundoff(x, o):
        i = int(np.argmin(d))
        moved = np.array(p["center"]) + (p["dhat"] - d[i]) * n
        raise ParameterError("center", f"the square starts touching or below the slope: node {i} at {x[i].tolist()} has distance "
                         f"{d[i]:.3g} m, not above the round-off of its coordinates ({roundoff(x, o):.2g} m); move "
                         f"center (now {_shown(p['center'])}) away from the slope, e.g. to "
                         f"{_shown(moved).replace(', ', ',')}, which puts that node dhat = {p['dhat']:g} m above it")


def scene_warnings(p, x, n, d):
    """What a scene's results cannot be trusted for, as sentences for the user (each stable, unresolved):
    1. One step moves the body more than its size (|v0| h + |g| h^2 > side_len): the impact happens inside
       a step, inelastic whatever the physics. The largest h that resolves is the root of |g| h^2 + |v0| h
       = side_len, as 2 L / (v + sqrt(v^2 + 4 g L)) (no cancellation, no overflow), rounded down.
    2. A square resting on the slope gains a h = (|g_t| - mu |g_n|) h of speed per step; where that is below
       tol, Newton may stop before it ever leaves static friction.
    3. Newton cannot resolve a residual below r_floor = sqrt(eps E_scale / m) / h: a step of ||p||_inf = h r
       lowers E by about m (h r)^2, which drowns in E's rounding eps E_scale, E_scale = h^2 M |g| (max|x| +
       side_len) (2.9e-7 m/s estimated on the lecture's scene, stalls measured at 1e-7 to 2.1e-7)."""
    warnings, h, v, g = [], p["h"], math.hypot(*p["v0"]), math.hypot(*p["gravity"])
    travel = v * h + g * h * h
    if travel > p["side_len"]:
        largest = 2.0 * p["side_len"] / (v + math.hypot(v, 2.0 * math.sqrt(g * p["side_len"])))
        exact = decimal.Decimal(largest)
        rounded = exact.quantize(decimal.Decimal(1).scaleb(exact.adjusted() - 2), rounding=decimal.ROUND_FLOOR)
        warnings.append(f"time step h = {h:g} s moves the square {travel:.3g} m per step, more than its "
                        f"size {p['side_len']:g} m: impacts are not resolved in time (results are qualitative "
                        f"only; use h <= {rounded.normalize():g} s)")
    if n is not None and p["mu"] > 0:
        gn = float(np.dot(p["gravity"], n))
        slide = float(np.hypot(*(np.array(p["gravity"]) - gn * n))) + p["mu"] * min(gn, 0.0)
        v_t = float(np.hypot(*(np.array(p["v0"]) - np.dot(p["v0"], n) * n)))
        if (d < p["dhat"]).any() and v_t < p["epsv"] and 0.0 < slide * h < p["tol"]:
            warnings.append(f"the square starts at rest on the slope and should slide at {slide:.3g} m/s^2, gaining "
                            f"{slide * h:.3g} m/s per step, less than tol = {p['tol']:g} m/s: Newton may stop "
                            f"before it leaves static friction (use tol <= {slide * h / 10:.2g})")
    M = total_mass(p)
    reach = float(np.abs(x).max()) + p["side_len"]
    floor = max(math.sqrt(EPS * h * h * M * g * reach / (M / len(x))), EPS * reach) / h
    if p["tol"] < floor:
        warnings.append(f"tol = {p['tol']:g} m/s is below the residual float64 can resolve in this scene (about "
                        f"{floor:.2g} m/s: E's rounding hides smaller Newton steps): Newton stops at that floor "
                        f"where it must, and log.csv flags those steps newton_stalled")
    return tuple(warnings)
