"""The square's scene checks, run once by simulator.build_scene: each parameter, then the start,
against what float64 and this machine can hold, and the warnings of what a scene's results cannot
be trusted for. Not the lecture's path: a student can skip this module.
"""
import decimal
import math

import numpy as np

import utils
from utils import ParameterError

EPS = np.finfo(float).eps


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
    """What the square's sizes grow with (scenes.ranges.check_start)."""
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
    floor = max(math.sqrt(EPS * h * h * M * g * reach / (M / len(x))), EPS * reach) / h
    if p["tol"] < floor:
        warnings.append(f"tol = {p['tol']:g} m/s is below the residual float64 can resolve in this "
                        f"scene, about {floor:.2g} m/s: Newton stops at that floor where it must, "
                        f"and log.csv flags those steps newton_stalled (docs/limits.md)")
    return tuple(warnings)
