"""The lecture's case study: an elastic mass-spring square dropped onto a slope, with friction.

    scene = build_scene(mu=0.2)     # the lecture's numbers (DEFAULTS), one of them changed
"""
import math
import types

import numpy as np

import BarrierEnergy
import MassSpringEnergy
import square_checks
import square_mesh
import utils
from scenes import ranges
from scenes.scene import Scene, readonly

DEFAULTS = types.MappingProxyType({
    "side_len": 1.0,            # m
    "n_seg": 4,                 # segments per side: (n_seg + 1)^2 nodes
    "rho": 1000.0,              # kg/m^2
    "mass": None,               # total mass in kg, instead of rho side_len^2
    "k": 2e4,                   # spring stiffness, N/m
    "h": 0.01,                  # time step, s
    "gravity": (0.0, -9.81),    # m/s^2
    "slope": (0.1, 1.0),        # the slope's normal, normalized when built; None: no slope
    "slope_point": (0.0, -1.0),  # o, a point on the slope, m
    "mu": 0.11,                 # friction coefficient
    "dhat": BarrierEnergy.DHAT,     # barrier activation distance, m (0.01)
    "kappa": BarrierEnergy.KAPPA,   # barrier stiffness (1e5)
    "epsv": 1e-3,               # friction's eps_v, m/s
    "tol": 1e-2,                # Newton tolerance on ||p||_inf / h, m/s
    "v0": (0.0, 0.0),           # initial velocity of every node, m/s
    "center": (0.0, 0.0),       # initial centre of the square, m
    "angle": 0.0,               # initial rotation of the square about its centre, radians
    "friction_updates": 0,      # Algorithm 5's friction updates per step; 0: lagged, as the lecture
    "newton_start": "x_n",      # x^n, as the lecture; "x_tilde": x^n + h v^n, cut back by CCD
    "max_newton_iterations": 1000,  # a safety cap: the hardest tested cases need about 320
    "max_halvings": 60,         # line-search halvings before Newton gives up on a direction
})
ALIASES = {"dt": "h"}           # other names a parameter may be passed by


def build_scene(**overrides):
    """The square's scene, built once from DEFAULTS with `overrides`; a ValueError names a bad
    parameter (square_checks.check_params, scenes.ranges)."""
    p = square_checks.check_params(DEFAULTS, ALIASES, overrides)
    ranges.check_memory("n_seg", p["n_seg"], lambda n_seg: (n_seg + 1) ** 2)
    x, e = square_mesh.generate(p["side_len"], p["n_seg"])      # the square, centred at the origin
    c, s = math.cos(p["angle"]), math.sin(p["angle"])
    x = x @ np.array([[c, s], [-s, c]]) + np.array(p["center"])
    n = o = d = None
    if p["slope"] is not None:
        n, o = square_checks.slope_normal(p["slope"]), np.array(p["slope_point"])
        d = BarrierEnergy.distances(x, n, o)
    m = np.full(len(x), square_checks.total_mass(p) / len(x))      # or rho side_len^2
    spacing = p["side_len"] / p["n_seg"]
    defaults = {**DEFAULTS, "mass": square_checks.total_mass(DEFAULTS)}
    ranges.check_start(p, defaults, square_checks.grows(p), x, m, spacing, spacing, o, d)
    if d is not None:
        square_checks.check_touching(p, x, n, d, ranges.roundoff(x, o))

    terms = ["inertia", "spring"] + ["gravity"] * any(p["gravity"])
    if n is not None:
        terms += ["barrier"] + ["friction"] * (p["mu"] > 0.0)
    return Scene(
        params=types.MappingProxyType(p), x0=readonly(x),
        v0=readonly(np.tile(p["v0"], (len(x), 1))),
        e=readonly(np.asfortranarray(e)),       # column by column: e[:, 0] and e[:, 1] gather fast
        l2=readonly(MassSpringEnergy.squared_lengths(x, e)), k=readonly(np.full(len(e), p["k"])),
        m=readonly(m), contact_area=readonly(np.full(len(x), spacing)),
        g=readonly(p["gravity"]),
        n=None if n is None else readonly(n), o=None if o is None else readonly(o),
        mu=p["mu"], dhat=p["dhat"], kappa=p["kappa"], epsv=p["epsv"], h=p["h"], tol=p["tol"],
        friction_updates=p["friction_updates"], newton_start=p["newton_start"],
        max_newton_iterations=p["max_newton_iterations"], max_halvings=p["max_halvings"],
        terms=tuple(terms), warnings=square_checks.scene_warnings(p, x, n, d),
        solver=utils.SPDSolver.for_mesh(len(x), e), cells=(p["n_seg"], p["n_seg"]))
