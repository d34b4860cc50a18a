"""The tablecloth trick (the slide "Tangential Relative Velocity"): a dish at rest on a cloth
pulled a length L at speed U across a flat table. Pulled fast, the dish barely moves; slowly, it
rides along (`travel`, `stop_time`: its closed forms, a rigid dish under Coulomb friction).

    scene = build_tablecloth_scene(pull_speed=8.0)  # the numbers (TABLECLOTH), one of them changed
"""
import types

import numpy as np

import square_mesh
import utils
from scenes import ranges
from scenes.scene import MovingSurface, assemble, gap_carrying, readonly

TABLECLOTH = types.MappingProxyType({
    "width": 0.2, "height": 0.05,   # m: the dish, a plate
    "nx": 4, "ny": 1,           # cells along and across: (nx + 1)(ny + 1) nodes
    "mass": 0.5,                # kg
    "k": 2e5,                   # spring stiffness, N/m: stiff, so it settles and slides as one body
    "h": 5e-3,                  # time step, s
    "gravity": (0.0, -9.81),    # m/s^2
    "mu": 0.2,                  # one friction coefficient, the cloth's and the table's
    "pull_speed": 4.0,          # U, m/s
    "pull_length": 1.0,         # L, m
    "t_pull": 0.05,             # the pull starts, s
    "dhat": 1e-3, "kappa": 1e5,     # barrier activation distance (m) and stiffness
    "epsv": 1e-3,               # friction's eps_v, m/s
    "tol": 1e-6,                # Newton tolerance on ||p||_inf / h, m/s: eps_v / 1000
    "friction_updates": 0, "max_newton_iterations": 1000, "max_halvings": 60,
    "newton_start": "x_n",
})


def check_params(overrides):
    """TABLECLOTH updated by `overrides`, each value checked (a ValueError naming the parameter)."""
    checks = {**dict.fromkeys(("width", "height", "mass", "pull_speed", "pull_length"),
                              utils.check_positive),
              **dict.fromkeys(("nx", "ny"), utils.check_whole),
              **dict.fromkeys(("mu", "t_pull"), utils.check_nonnegative), **utils.SOLVER_CHECKS}
    p = utils.check_params(checks, TABLECLOTH, overrides, "tablecloth")
    if not p["gravity"][1] < 0.0:
        raise utils.ParameterError("gravity", f"gravity must press the dish down (y < 0), got "
                                   f"{p['gravity']}")
    for name in ("pull_speed", "pull_length"):
        if not p[name] <= ranges.FLOAT64_SCALE_LIMIT:
            raise utils.ParameterError(name, f"{name} must be <= {ranges.FLOAT64_SCALE_LIMIT:g} "
                                       f"(its square), got {p[name]:g}")
    return p


PULL_STEPS = 2      # fewer steps in the pull than this: its travel is not resolved (warnings)


def warnings(p):
    """What the scene's results cannot be trusted for: a pull of fewer than PULL_STEPS steps of h
    (measured on the defaults' L = 1 m, h = 5 ms: travel +1.9 % of the closed form at U = 100 m/s,
    2 steps; +8 % at 200 m/s, 1 step; +2599 % at 1000 m/s, 0.2 step)."""
    pull, h = p["pull_length"] / p["pull_speed"], p["h"]
    if pull >= PULL_STEPS * h:
        return ()
    return (f"the pull lasts {pull:.2g} s, under {PULL_STEPS} steps of h = {h:g} s: its travel "
            f"cannot be trusted (use U <= {p['pull_length'] / (PULL_STEPS * h):.3g} m/s)",)


GROWS = types.MappingProxyType({        # what the dish's sizes grow with (scenes.ranges)
    "M": {"mass": 1}, "size": {"width": 1, "height": 1}, "X": {"dhat": 1},   # at the gap
    "l": {"width": 1, "nx": -1, "height": 1, "ny": -1}, "N": {"nx": 1, "ny": 1}})


def resting_gap(p):
    """d0, the gap at which the barrier carries the dish's weight on its nx + 1 bottom nodes:
    w dhat (-b'(d0)) = m |g_y| / (nx + 1) (gap_carrying; refused where it cannot be carried)."""
    w, load = p["width"] / p["nx"], -p["mass"] * p["gravity"][1] / (p["nx"] + 1)
    ranges.check_carries(p, TABLECLOTH, load, w, {"kappa": -1, "mass": 1, "gravity": 1,
                                                  "width": -1, "nx": 2, "dhat": -1},
                         "the dish")
    return gap_carrying(load, w, p["dhat"], p["kappa"])


def build_tablecloth_scene(**overrides):
    """The dish on a flat table (normal (0, 1) through the origin), at rest at the gap where the
    barrier carries its weight (settled, not dropped), the cloth under it pulled along +x from
    t_pull. A ValueError names a bad parameter."""
    p = check_params(overrides)
    for name, other in sorted((("nx", "ny"), ("ny", "nx")), key=lambda pair: -p[pair[0]]):
        ranges.check_memory(name, p[name], lambda n: (n + 1) * (p[other] + 1))
    m = np.full((p["nx"] + 1) * (p["ny"] + 1), p["mass"] / ((p["nx"] + 1) * (p["ny"] + 1)))
    x, e = square_mesh.rectangle(p["width"], p["height"], p["nx"], p["ny"],
                                 (-p["width"] / 2, p["dhat"]))     # at dhat: the check's start
    spacing = min(p["width"] / p["nx"], p["height"] / p["ny"])
    ranges.check_start(p, TABLECLOTH, GROWS, x, m, spacing, p["width"] / p["nx"], np.zeros(2),
                       x[:, 1])
    x, e = square_mesh.rectangle(p["width"], p["height"], p["nx"], p["ny"],
                                 (-p["width"] / 2, resting_gap(p)))
    terms = ("inertia", "spring", "gravity", "barrier") + ("friction",) * (p["mu"] > 0.0)
    cloth = MovingSurface(p["pull_speed"], p["pull_length"], p["t_pull"], readonly([1.0, 0.0]))
    return assemble(p, x, e, m, w=p["width"] / p["nx"], terms=terms, cells=(p["nx"], p["ny"]),
                    n=[0.0, 1.0], o=[0.0, 0.0], warnings=warnings(p), surface=cloth,
                    body="the dish")


# ---- Its closed forms: a rigid dish, Coulomb friction ------------------------------------------

def travel(pull_speed, pull_length, mu, g=9.81):
    """How far a dish on a cloth pulled a length L at speed U travels, friction driving it at mu g:
    mu g T^2 = mu g L^2 / U^2 where the cloth outruns it (U^2 >= mu g L: speed mu g T at T = L / U,
    then as far again to a stop), else L (it rides along, stops as far past the end as it lags)."""
    U, L = pull_speed, pull_length
    return mu * g * L * L / (U * U) if U * U >= mu * g * L else L


def stop_time(pull_speed, pull_length, mu, t_pull, g=9.81):
    """When the closed form's dish stops: the cloth leaves at t_pull + T, T = L / U, the dish then
    moving at min(U, mu g T), which friction takes away in min(U / (mu g), T) more."""
    T = pull_length / pull_speed
    return t_pull + T + (T if mu * g * T <= pull_speed else pull_speed / (mu * g))
