"""The chalk's scene checks, run once by simulator.build_chalk_scene: each parameter by name
(simulator.CHALK). Not the lecture's path: a student can skip this module."""
import math

import numpy as np

import utils
from utils import ParameterError


def check_params(defaults, overrides):
    """`defaults` (simulator.CHALK) updated by `overrides`, every value checked."""
    unknown = sorted(set(overrides) - set(defaults))
    if unknown:
        raise ParameterError(unknown[0], f"unknown chalk parameter(s): {', '.join(unknown)}; "
                                         f"valid: {', '.join(sorted(defaults))}")
    p = {**defaults, **overrides}
    for name in ("length", "width", "rho", "k", "h", "v_c", "dhat", "kappa", "tol", "k_hand",
                 "t_press", "t_hold"):
        p[name] = utils.check_positive(name, p[name])
    for name in ("mu", "mu_s", "press", "drive"):
        p[name] = utils.as_float(name, p[name], "must be a finite number >= 0")
        if not 0.0 <= p[name] < math.inf:
            raise ParameterError(name, f"{name} must be a finite number >= 0, got {p[name]}")
    p["tilt"] = utils.as_float("tilt", p["tilt"], "must be a number of degrees in (0, 180)")
    if not 0.0 < p["tilt"] < 180.0:
        message = f"tilt must be a number of degrees in (0, 180), got {p['tilt']}"
        raise ParameterError("tilt", message)
    for name, minimum in (("nx", 1), ("ny", 1), ("held_columns", 1), ("friction_updates", 0),
                          ("max_newton_iterations", 1), ("max_halvings", 1)):
        p[name] = utils.check_whole(name, p[name], minimum)
    p["newton_start"] = utils.check_choice("newton_start", p["newton_start"], utils.NEWTON_STARTS)
    if p["held_columns"] > p["nx"]:
        raise ParameterError("held_columns", f"held_columns must leave the tip free: at most "
                                             f"nx = {p['nx']}, got {p['held_columns']}")
    if not isinstance(p["drag"], (bool, np.bool_)):
        raise ParameterError("drag", f"drag must be True or False, got {p['drag']!r}")
    p["epsv"] = utils.check_epsv(p["epsv"])
    p["gravity"] = tuple(utils.check_vector("gravity", p["gravity"]).tolist())
    return p
