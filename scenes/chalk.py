"""The lecture's closing remark: Rabinowicz's chalk, pushed or dragged across a board by a hand,
stick-slips (docs/chalk.md: the scene as data, and where it departs from the lecture). Its numbers
(CHALK), its builder, and its checks (each parameter by name: a student can skip them).

    chalk = build_chalk_scene(k_hand=4000.0)    # the chalk's numbers (CHALK), one of them changed
"""
import math
import types

import numpy as np

import HandEnergy
import square_mesh
import utils
from scenes import ranges
from scenes.scene import StaticFriction, assemble, readonly
from utils import ParameterError

CHALK = types.MappingProxyType({
    "length": 0.09, "width": 0.01,  # m: the chalk, along its axis and across
    "nx": 18, "ny": 2,          # cells along and across: (nx + 1)(ny + 1) nodes
    "rho": 15.0,                # kg/m^2
    "k": 1e5,                   # spring stiffness, N/m
    "h": 1e-3,                  # time step, s
    "gravity": (0.0, -9.81),    # m/s^2
    "mu": 0.35,                 # kinetic friction coefficient
    "mu_s": 0.5,                # static coefficient; mu_s = mu: one coefficient, the lecture's
    "v_c": 1e-3,                # slip speed over which mu falls from mu_s to mu, m/s
    "dhat": 1e-3, "kappa": 1e3,     # barrier activation distance (m) and stiffness
    "epsv": 1e-4,               # friction's eps_v, m/s
    "tol": 1e-6,                # Newton tolerance on ||p||_inf / h, m/s: eps_v / 100
    "tilt": 60.0,               # degrees between the chalk and the board
    "drag": False,              # False: pushed (the hand behind the tip); True: dragged
    "k_hand": 2000.0,           # the grip: stiffness of each held node's spring, N/m
    "held_columns": 3,          # the hand holds the nodes of this many columns at the far end
    "press": 5e-4, "t_press": 0.1,  # the targets press this far into the board (m) in t_press (s),
    "t_hold": 0.1, "drive": 0.01,   # hold for t_hold (s), then move along the board at drive (m/s)
    "friction_updates": 0, "max_newton_iterations": 1000, "max_halvings": 60,
    "newton_start": "x_tilde",  # from x^n + h v^n cut by CCD: a sliding tip starts sliding
})

GROWS = types.MappingProxyType({        # what the chalk's sizes grow with (scenes.ranges)
    "M": {"rho": 1, "length": 1, "width": 1}, "size": {"length": 1, "width": 1}, "X": {"dhat": 1},
    "l": {"length": 1, "nx": -1, "width": 1, "ny": -1}, "N": {"nx": 1, "ny": 1}})
GRIP = types.MappingProxyType({         # h^2 k_hand / m, the grip beside a node's mass
    "h": 2, "k_hand": 1, "rho": -1, "length": -1, "width": -1, "nx": 1, "ny": 1})


def check_params(defaults, overrides):
    """`defaults` (CHALK) updated by `overrides`, every value checked."""
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


def build_chalk_scene(**overrides):
    """Rabinowicz's chalk: a mass-spring rectangle at `tilt` to a flat board (normal (0, 1) through
    the origin), its tip corner at dhat, held by the hand at the far end, which moves along +x:
    pushed, the chalk leans back over the tip; dragged, forward. A ValueError names a bad
    parameter."""
    p = check_params(CHALK, overrides)
    for name, other in sorted((("nx", "ny"), ("ny", "nx")), key=lambda pair: -p[pair[0]]):
        ranges.check_memory(name, p[name], lambda n: (n + 1) * (p[other] + 1))
    x, e = square_mesh.rectangle(p["length"], p["width"], p["nx"], p["ny"], (0.0, -p["width"] / 2))
    tilt = math.radians(p["tilt"])
    a = np.array([math.cos(tilt) * (1.0 if p["drag"] else -1.0), math.sin(tilt)])   # tip to hand
    x = x @ np.array([a, [-a[1], a[0]]])                       # rows (u, w) -> u a + w a_perp
    x = x - [x[np.argmin(x[:, 1]), 0], x[:, 1].min() - p["dhat"]]      # the tip corner at (0, dhat)
    m = np.full(len(x), p["rho"] * p["length"] * p["width"] / len(x))
    ranges.check_start(p, CHALK, GROWS, x, m, min(p["length"] / p["nx"], p["width"] / p["ny"]),
                       p["width"] / p["ny"], np.zeros(2), x[:, 1])
    grip = 2 * math.log10(p["h"]) + math.log10(p["k_hand"]) - math.log10(m[0])    # h^2 k_hand / m
    ranges.resolves(p, CHALK, grip - math.log10(ranges.ROUNDOFF_ULPS * ranges.EPS), GRIP,
                    "the grip")     # lost beside m in M + h^2 K: no hand
    held = np.arange((p["nx"] + 1 - p["held_columns"]) * (p["ny"] + 1), len(x))
    t1, t2, down = p["t_press"], p["t_press"] + p["t_hold"], -p["press"]
    hand = HandEnergy.Hand(nodes=readonly(held), rest=readonly(x[held]), k_hand=p["k_hand"],
                           key_t=readonly([0.0, t1, t2, t2 + 1.0]),       # then on at drive
                           key_d=readonly([[0.0, 0.0], [0.0, down], [0.0, down],
                                           [p["drive"], down]]))
    terms = ["inertia", "spring"] + ["gravity"] * any(p["gravity"]) + ["hand", "barrier"]
    terms += ["friction"] * (max(p["mu"], p["mu_s"]) > 0.0)
    static = StaticFriction(p["mu_s"], p["v_c"]) if p["mu_s"] != p["mu"] else None
    return assemble(p, x, e, m, w=p["width"] / p["ny"], terms=terms, cells=(p["nx"], p["ny"]),
                    n=[0.0, 1.0], o=[0.0, 0.0], elements=[held[:, None]],   # the hand: nodes
                    hand=hand, static=static, body="the chalk")
