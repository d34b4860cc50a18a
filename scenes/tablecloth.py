"""The tablecloth trick (the slide "Tangential Relative Velocity"): a dish at rest on a cloth
pulled a length L at speed U across a flat table. Pulled fast, the dish barely moves; slowly, it
rides along (closed_forms.tablecloth_travel).

    scene = build_tablecloth_scene(pull_speed=8.0)  # the numbers (TABLECLOTH), one of them changed
"""
import types

import numpy as np

import MassSpringEnergy
import square_mesh
import utils
from scenes import ranges
from scenes.scene import MovingSurface, Scene, gap_carrying, readonly

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
        raise utils.ParameterError("gravity", f"gravity must press the dish down on the table "
                                   f"(y < 0), got {p['gravity']}")
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
                         "the dish's weight")
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
    return Scene(
        params=types.MappingProxyType(p), x0=readonly(x), v0=readonly(np.zeros_like(x)),
        e=readonly(np.asfortranarray(e)), l2=readonly(MassSpringEnergy.squared_lengths(x, e)),
        k=readonly(np.full(len(e), p["k"])), m=readonly(m),
        contact_area=readonly(np.full(len(x), p["width"] / p["nx"])), g=readonly(p["gravity"]),
        n=readonly([0.0, 1.0]), o=readonly([0.0, 0.0]), mu=p["mu"], dhat=p["dhat"],
        kappa=p["kappa"], epsv=p["epsv"], h=p["h"], tol=p["tol"],
        friction_updates=p["friction_updates"], newton_start=p["newton_start"],
        max_newton_iterations=p["max_newton_iterations"], max_halvings=p["max_halvings"],
        terms=terms, warnings=warnings(p), solver=utils.SPDSolver.for_mesh(len(x), e),
        cells=(p["nx"], p["ny"]),
        surface=MovingSurface(p["pull_speed"], p["pull_length"], p["t_pull"], readonly([1.0, 0.0])))
