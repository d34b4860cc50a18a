"""The chalk's scene checks, run once by simulator.build_chalk_scene: each parameter by name
(simulator.CHALK). Not the lecture's path: a student can skip this module."""
import numpy as np

import utils
from utils import ParameterError


def check_params(defaults, overrides):
    """`defaults` (simulator.CHALK) updated by `overrides`, every value checked."""
    checks = {**dict.fromkeys(("length", "width", "rho", "v_c", "k_hand", "t_press", "t_hold"),
                              utils.check_positive),
              **dict.fromkeys(("mu", "mu_s", "press", "drive"), utils.check_nonnegative),
              **dict.fromkeys(("nx", "ny", "held_columns"), utils.check_whole),
              **utils.SOLVER_CHECKS}
    p = utils.check_params(checks, defaults, overrides, "chalk")
    p["tilt"] = utils.as_float("tilt", p["tilt"], "must be a number of degrees in (0, 180)")
    if not 0.0 < p["tilt"] < 180.0:
        message = f"tilt must be a number of degrees in (0, 180), got {p['tilt']}"
        raise ParameterError("tilt", message)
    if p["held_columns"] > p["nx"]:
        raise ParameterError("held_columns", f"held_columns must leave the tip free: at most "
                                             f"nx = {p['nx']}, got {p['held_columns']}")
    if not isinstance(p["drag"], (bool, np.bool_)):
        raise ParameterError("drag", f"drag must be True or False, got {p['drag']!r}")
    return p
