"""Every scene's range checks, shared: what float64 and this machine can hold (docs/limits.md).
A scene's builder calls check_memory before it makes its mesh and check_start on the mesh it made;
each raises a ParameterError naming the parameter that moved the scene furthest out of range.
Not the lecture's path: a student can skip this module.

    ranges.check_start(p, defaults, grows, x, m, spacing, w)

`grows` says what each of the scene's sizes grows with, as {parameter: exponent}:
"M" the total mass, "size" the body's extent, "X" where it is placed, "l" the mesh spacing,
"N" the node count; e.g. the tablecloth's {"M": {"mass": 1}, "size": {"width": 1},
"X": {}, "l": {"width": 1, "nx": -1, "height": 1, "ny": -1}, "N": {"nx": 1, "ny": 1}}.
"""
import collections
import decimal
import math
import os

import numpy as np

import BarrierEnergy
from utils import ParameterError

EPS = np.finfo(float).eps
# A node nearer the half-space than ROUNDOFF_ULPS eps (max_i |x_i| + |o|) touches it as far as
# float64 can tell: x_i, n and d = n . (x_i - o) carry about 5 roundings of eps/2 each.
ROUNDOFF_ULPS = 8
# Squares of 1e150 summed over the 1e8 nodes that fit in memory stay below float64's 1.8e308.
FLOAT64_SCALE_LIMIT = 1e150
# M + h^2 K: LAPACK's banded Cholesky loses the node mass m from h^2 k / m = 0.5/eps (measured);
# 0.1/eps leaves a factor 5 for the barrier's curvature.
NEWTON_RATIO_LIMIT = 0.1 / EPS
# The most steps a run takes, asked for (--steps, --duration) or by default (the tablecloth's: till
# its dish stops): log.csv holds about 180 bytes a step (18 GB), at about 3 ms a step on one core
# (3.5 days).
MAX_STEPS = 10 ** 8
# Peak resident memory per node of build_scene plus one step, measured at n_seg 128 to 400
# (7.6 to 10 KiB), rounded up.
MEMORY_PER_NODE = 16 * 1024
# A settled start's gap is sought in [CLOSEST_GAP dhat, dhat] (scenes.scene.gap_carrying).
CLOSEST_GAP = 1e-12


def physical_memory():
    """This machine's physical memory in bytes, or None where the OS does not say."""
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return None


def check_memory(name, value, nodes_of):
    """`value` of the count `name`, or a ValueError if its nodes_of(value) nodes, MEMORY_PER_NODE
    each, do not fit here; the message names the largest value that fits (nodes_of increasing)."""
    nodes, have = nodes_of(value), physical_memory()      # Python ints: exact at any count
    if have is None or MEMORY_PER_NODE * nodes <= have:
        return value
    low, high = 0, value                # the largest that fits, by bisection: nodes_of(low) fits
    while high - low > 1:
        middle = (low + high) // 2
        low, high = (middle, high) if MEMORY_PER_NODE * nodes_of(middle) <= have else (low, middle)
    need = decimal.Decimal(MEMORY_PER_NODE * nodes) / 2**30
    raise ParameterError(name, f"{name} = {float(value):g}: {decimal.Decimal(nodes):.3g} nodes, "
                               f"{need:.3g} GiB > {have / 2**30:.3g} GiB ({name} <= {low})")


def roundoff(x, o):
    """How near the half-space a node can be and still be told apart from touching it."""
    return ROUNDOFF_ULPS * EPS * (float(np.hypot(x[:, 0], x[:, 1]).max()) + float(np.hypot(*o)))


def shown(value):
    """A parameter's value as the user typed it: a number, or a vector's numbers joined by ', '."""
    return ", ".join(f"{float(a):g}" for a in value) if np.ndim(value) else f"{value:g}"


def powers(*parts, scale=1):
    """The exponents of parts ({parameter: exponent} each) summed, times `scale`."""
    total = collections.Counter()
    for part in parts:
        total.update(part)
    return {name: scale * exponent for name, exponent in total.items()}


def culprit(p, defaults, grows_with):
    """Of the parameters a scale grows with ({name: exponent}), the one that moved it furthest
    from the scene's defaults: the largest exponent * log10(size / default size)."""
    def size(value):
        return float(np.hypot(*value)) if np.ndim(value) else abs(value)

    def push(name):
        return grows_with[name] * math.log10(max(size(p[name]), 1e-300)
                                             / (size(defaults[name]) or 1.0))
    return max((name for name in grows_with if p.get(name) is not None), key=push)


def _scales(p, grows, x, m, spacing, w, o, d):
    """The first step's scales (what, value, the parameters it grows with), docs/limits.md's: M,
    1/2 M |v0|^2, 1/2 M (|v0| h + |g| h^2)^2, h^2 M |g| (max |x| + |v0| h + |g| h^2), h^2 k,
    h^2 k l^2, h^2 kappa w dhat, h^2 kappa w (1/d + dhat/d^2) / 2, h max(mu, mu_s) M |g| / eps_v
    (the chalk's static mu_s where it has one)."""
    h, k, g = p["h"], p["k"], math.hypot(*p["gravity"])
    v = math.hypot(*p.get("v0", (0.0, 0.0)))
    M, X, l = float(np.sum(m)), float(np.abs(x).max()), spacing
    D, Mp = v * h + g * h * h, grows["M"]
    scales = [
        ("total mass", M, Mp),
        ("kinetic energy", 0.5 * M * v * v, powers(Mp, {"v0": 2})),
        ("first inertia term", 0.5 * M * D * D,
         powers(Mp, {"v0": 2, "h": 2, "gravity": 2})),
        ("gravity's term", h * h * M * g * (X + D),
         powers(Mp, {"h": 2, "gravity": 1}, grows["X"], grows["size"])),
        ("springs' stiffness", h * h * k, {"h": 2, "k": 1}),
        ("springs' energy", h * h * k * l * l,
         powers({"h": 2, "k": 1}, powers(grows["l"], scale=2)))]
    if d is None:
        return scales
    barrier = powers({"h": 2, "kappa": 1}, grows["l"])              # the contact area w ~ l
    kappa_w = h * h * p["kappa"] * w
    near = min(max(float(d.min()), roundoff(x, o)), p["dhat"])
    return scales + [
        ("barrier's energy", kappa_w * p["dhat"],
         powers(barrier, {"dhat": 1})),
        ("barrier's curvature",
         kappa_w * (1 / near + p["dhat"] / near / near) / 2, powers(barrier, {"dhat": -1})),
        ("friction's stiffness", h * max(p["mu"], p.get("mu_s", 0.0)) * M * g / p["epsv"],
         powers(Mp, {"h": 1, "mu": 1, "mu_s": 1, "gravity": 1, "epsv": -1}))]


def check_start(p, defaults, grows, x, m, spacing, w, o=None, d=None):
    """ValueError, naming the parameter and its value, where the first step from x (node masses m,
    least rest length `spacing`, contact weight w per node, distances d to the half-space through o,
    or None) leaves float64:
    a scale above FLOAT64_SCALE_LIMIT, h^2 k / m above NEWTON_RATIO_LIMIT, h^2 below float64's
    least normal number, or the spacing or dhat below the coordinates' round-off."""
    for what, value, grows_with in _scales(p, grows, x, m, spacing, w, o, d):
        if not value <= FLOAT64_SCALE_LIMIT:
            name = culprit(p, defaults, grows_with)
            message = (f"{name} = {shown(p[name])}: {what} {value:.3g} > "
                       f"{FLOAT64_SCALE_LIMIT:g} (float64)")
            raise ParameterError(name, message)
    h, k, m_node = p["h"], p["k"], float(np.min(m))
    ratio = h * h * k / m_node if m_node > 0.0 else math.inf    # an underflowed mass: no M
    if not ratio <= NEWTON_RATIO_LIMIT:
        name = culprit(p, defaults, powers({"k": 1, "h": 2}, grows["N"], powers(grows["M"],
                                                                                scale=-1)))
        message = (f"{name} = {shown(p[name])}: h^2 k / m = {ratio:.3g} > 0.1/eps (m lost in "
                   f"float64)")
        raise ParameterError(name, message)
    if not h * h >= np.finfo(float).tiny:
        raise ParameterError("h", f"h = {h:g} s: h^2 underflows float64 (h >= 1.5e-154 s)")
    travel = math.hypot(*p.get("v0", (0.0, 0.0))) * h + math.hypot(*p["gravity"]) * h * h
    scale = float(np.abs(x).max()) + (0.0 if o is None else float(np.abs(o).max())) + travel
    moved = powers({"v0": 1, "gravity": 1, "h": 1}, grows["X"])
    lengths = (("spacing", spacing,
                powers(moved, powers(grows["l"], scale=-1))),
               ("dhat", p["dhat"], {**powers(moved, grows["size"]), "dhat": -1}))
    for what, length, grows_with in lengths:
        if not length > ROUNDOFF_ULPS * EPS * scale:
            name = culprit(p, defaults, grows_with)
            message = (f"{name} = {shown(p[name])}: {what} {length:.3g} m is below round-off at "
                       f"{scale:.3g} m")
            raise ParameterError(name, message)


def check_carries(p, defaults, load, w, grows_with, what):
    """ParameterError, naming the parameter that moved furthest (culprit of `grows_with`), where
    the barrier cannot carry `load` (N) on a node of contact weight w even at a gap of CLOSEST_GAP
    dhat: kappa below load / (w dhat (-b'(CLOSEST_GAP dhat)) at kappa 1), to 3 digits rounded up;
    or cannot resolve it: `load` below its push at the gap (1 - ROUNDOFF_ULPS eps) dhat, a gap
    that round-off cannot tell from dhat (resolves)."""
    dhat, kappa = p["dhat"], p["kappa"]
    load_min = -BarrierEnergy.dP_dd(dhat * (1.0 - ROUNDOFF_ULPS * EPS), w, dhat, kappa)
    if load_min > 0.0:              # 0: a kappa that underflows it carries nothing (below)
        resolves(p, defaults, (math.log10(load) if load > 0.0 else -math.inf)
                 - math.log10(load_min), grows_with, what)
    kappa_min = load / -BarrierEnergy.dP_dd(CLOSEST_GAP * dhat, w, dhat, 1.0)
    digit = 10.0 ** (math.floor(math.log10(kappa_min)) - 2)
    kappa_min = math.ceil(kappa_min / digit) * digit
    if not kappa >= kappa_min:
        name = culprit(p, defaults, grows_with)
        raise ParameterError(name, f"{name} = {shown(p[name])}: cannot carry {what} (kappa >= "
                                   f"{kappa_min:.3g})")


def resolves(p, defaults, log_ratio, grows_with, what):
    """ParameterError where log_ratio = log10(load / load_min) < 0, naming the parameter that moved
    the load furthest down (its exponents `grows_with`) and the value of it that reaches load_min.
    In logarithms: a load that underflows float64 (a subnormal parameter) still has its bound."""
    if log_ratio >= 0.0:
        return
    name = culprit(p, defaults, powers(grows_with, scale=-1))
    size = float(np.hypot(*p[name])) if np.ndim(p[name]) else p[name]
    bound = 10.0 ** (math.log10(size) - log_ratio / grows_with[name])
    said = f"|{name}|" if np.ndim(p[name]) else name
    op = ">=" if grows_with[name] > 0 else "<="
    bound = f"{said} {op} {bound:.3g}" if 0.0 < bound < math.inf else "it underflows"  # load 0
    raise ParameterError(name, f"{name} = {shown(p[name])}: lost in round-off ({bound})")
