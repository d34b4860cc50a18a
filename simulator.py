"""The lecture's case study: an elastic mass-spring square dropped onto a slope with friction; and its
closing remark, Rabinowicz's chalk pushed or dragged across a board by a hand (stick-slip).

    scene = build_scene(mu=0.2)                     # the lecture's numbers (DEFAULTS), one of them changed
    for record in simulate(scene, steps=300):       # implicit Euler, one time_integrator.step at a time
        print(record.t, record.x.mean(axis=0))
    chalk = build_chalk_scene(k_hand=4000.0)        # the chalk's numbers (CHALK), one of them changed

`python simulator.py` runs the scene and writes what it shows (frames, a page, plots, a log): the
command line lives in viewer/cli.py (`python simulator.py --help`), the drawing in viewer/.
"""
if __name__ == "__main__":      # python simulator.py [flags]: the command line, before numpy loads
    from viewer import startup
    raise SystemExit(startup.run_command_line())

import math
import time
import types
from dataclasses import dataclass

import numpy as np

import BarrierEnergy
import HandEnergy
import MassSpringEnergy
import chalk_checks
import square_checks
import square_mesh
import time_integrator
import utils

DEFAULTS = types.MappingProxyType({
    "side_len": 1.0,            # m
    "n_seg": 4,                 # segments per side: (n_seg + 1)^2 nodes
    "rho": 1000.0,              # kg/m^2
    "mass": None,               # total mass in kg, instead of rho side_len^2
    "k": 2e4,                   # spring stiffness, N/m
    "h": 0.01,                  # time step, s
    "gravity": (0.0, -9.81),    # m/s^2
    "slope": (0.1, 1.0),        # the slope's normal, normalized when the scene is built; None: no slope
    "slope_point": (0.0, -1.0), # o, a point on the slope, m
    "mu": 0.11,                 # friction coefficient
    "dhat": BarrierEnergy.DHAT,     # barrier activation distance, m (0.01)
    "kappa": BarrierEnergy.KAPPA,   # barrier stiffness (1e5)
    "epsv": 1e-3,               # friction's eps_v, m/s
    "tol": 1e-2,                # Newton tolerance on ||p||_inf / h, m/s
    "v0": (0.0, 0.0),           # initial velocity of every node, m/s
    "center": (0.0, 0.0),       # initial centre of the square, m
    "angle": 0.0,               # initial rotation of the square about its centre, radians
    "friction_updates": 0,      # fixed-point friction updates per step (Algorithm 5); 0: lagged, as the lecture
    "newton_start": "x_n",      # where Newton starts: x^n, as the lecture; "x_tilde": x^n + h v^n, cut by CCD
    "max_newton_iterations": 1000,  # a safety cap: the hardest tested cases need about 320 (docs/limits.md)
    "max_halvings": 60,         # line-search halvings before Newton gives up on a direction
})
ALIASES = {"dt": "h"}           # other names a parameter may be passed by


@dataclass(frozen=True)
class Scene:
    """What a scene *is*: built once by `build_scene` or `build_chalk_scene`, never changed by stepping."""
    params: types.MappingProxyType  # the checked parameters it was built from
    x0: np.ndarray              # (N, 2) initial positions
    v0: np.ndarray              # (N, 2) initial velocities
    e: np.ndarray               # (E, 2) spring node indices
    l2: np.ndarray              # (E,) squared rest lengths
    k: np.ndarray               # (E,) spring stiffnesses
    m: np.ndarray               # (N,) node masses
    contact_area: np.ndarray    # (N,) contact weight per node (side_len / n_seg)
    g: np.ndarray               # (2,) gravity
    n: np.ndarray               # (2,) unit slope normal, or None without a slope
    o: np.ndarray               # (2,) point on the slope, or None
    mu: float
    dhat: float
    kappa: float
    epsv: float
    h: float
    tol: float
    n_seg: int                  # the square's (None for the chalk: see cells)
    side_len: float             # the square's, m (None for the chalk)
    friction_updates: int
    newton_start: str           # "x_n" or "x_tilde" (time_integrator.newton_start)
    max_newton_iterations: int
    max_halvings: int
    terms: tuple                # the energy terms the Incremental Potential sums
    warnings: tuple             # what this scene's results cannot be trusted for, as sentences
    solver: utils.SPDSolver     # how H p = -grad E is solved on this mesh
    cells: tuple = None         # (nx, ny): the mesh's cells (square_mesh.rectangle); the square's (n_seg, n_seg)
    hand: HandEnergy.Hand = None    # the grip's held nodes and moving targets, or None
    mu_s: float = None          # static friction coefficient, or None: one coefficient, mu
    v_c: float = None           # m/s: mu falls from mu_s to mu over slip speeds of about v_c (with mu_s)


def _readonly(a):
    a = np.array(a)
    a.setflags(write=False)
    return a


def build_scene(**overrides):
    """The scene's model, built once from DEFAULTS with `overrides`; a ValueError names a bad parameter
    (square_checks.check_params, square_checks.check_start)."""
    p = square_checks.check_params(DEFAULTS, ALIASES, overrides)
    x, e = square_mesh.generate(p["side_len"], p["n_seg"])      # the square, centred at the origin
    c, s = math.cos(p["angle"]), math.sin(p["angle"])
    x = x @ np.array([[c, s], [-s, c]]) + np.array(p["center"])
    n = o = d = None
    if p["slope"] is not None:
        n, o = square_checks.slope_normal(p["slope"]), np.array(p["slope_point"])      # slope / |slope|
        d = BarrierEnergy.distances(x, n, o)
    square_checks.check_start(p, DEFAULTS, x, n, o, d)

    total_mass = square_checks.total_mass(p)                            # mass, or rho side_len^2
    terms = ["inertia", "spring"] + ["gravity"] * any(p["gravity"])
    if n is not None:
        terms += ["barrier"] + ["friction"] * (p["mu"] > 0.0)
    return Scene(
        params=types.MappingProxyType(p), x0=_readonly(x), v0=_readonly(np.tile(p["v0"], (len(x), 1))),
        e=_readonly(np.asfortranarray(e)),      # column by column: e[:, 0] and e[:, 1] gather fast
        l2=_readonly(MassSpringEnergy.squared_lengths(x, e)), k=_readonly(np.full(len(e), p["k"])),
        m=_readonly(np.full(len(x), total_mass / len(x))),
        contact_area=_readonly(np.full(len(x), p["side_len"] / p["n_seg"])),
        g=_readonly(p["gravity"]), n=None if n is None else _readonly(n), o=None if o is None else _readonly(o),
        mu=p["mu"], dhat=p["dhat"], kappa=p["kappa"], epsv=p["epsv"], h=p["h"], tol=p["tol"],
        n_seg=p["n_seg"], side_len=p["side_len"], friction_updates=p["friction_updates"],
        newton_start=p["newton_start"], max_newton_iterations=p["max_newton_iterations"],
        max_halvings=p["max_halvings"], terms=tuple(terms), warnings=square_checks.scene_warnings(p, x, n, d),
        solver=utils.SPDSolver.for_mesh(len(x), e), cells=(p["n_seg"], p["n_seg"]))


CHALK = types.MappingProxyType({
    "length": 0.09, "width": 0.01,  # m: the chalk, along its axis and across
    "nx": 18, "ny": 2,          # cells along and across: (nx + 1)(ny + 1) nodes
    "rho": 15.0,                # kg/m^2
    "k": 1e5,                   # spring stiffness, N/m
    "h": 1e-3,                  # time step, s
    "gravity": (0.0, -9.81),    # m/s^2
    "mu": 0.35,                 # kinetic friction coefficient
    "mu_s": 0.5,                # static coefficient; mu_s = mu: one coefficient, the lecture's friction
    "v_c": 1e-3,                # slip speed over which mu falls from mu_s to mu, m/s
    "dhat": 1e-3, "kappa": 1e3,     # barrier activation distance (m) and stiffness
    "epsv": 1e-4,               # friction's eps_v, m/s
    "tol": 1e-6,                # Newton tolerance on ||p||_inf / h, m/s: eps_v / 100 (docs/chalk.md)
    "tilt": 60.0,               # degrees between the chalk and the board
    "drag": False,              # False: pushed (the hand behind the tip, obtuse angle); True: dragged (acute)
    "k_hand": 2000.0,           # the grip: stiffness of each held node's spring, N/m
    "held_columns": 3,          # the hand holds the nodes of this many columns at the far end
    "press": 5e-4, "t_press": 0.1,  # the targets press this far into the board (m) over t_press (s),
    "t_hold": 0.1, "drive": 0.01,   # hold for t_hold (s), then move along the board at drive (m/s)
    "friction_updates": 0, "max_newton_iterations": 1000, "max_halvings": 60,
    "newton_start": "x_tilde",  # Newton from x^n + h v^n cut by CCD: a sliding tip starts sliding (not at v = 0)
})


def build_chalk_scene(**overrides):
    """Rabinowicz's chalk: a mass-spring rectangle at `tilt` to a flat board (normal (0, 1) through the
    origin), its tip corner at dhat, held by the hand at the far end, which moves along +x: pushed, the
    chalk leans back over the tip; dragged, forward. A ValueError names a bad parameter."""
    p = chalk_checks.check_params(CHALK, overrides)
    x, e = square_mesh.rectangle(p["length"], p["width"], p["nx"], p["ny"], (0.0, -p["width"] / 2.0))
    tilt = math.radians(p["tilt"])
    a = np.array([math.cos(tilt) * (1.0 if p["drag"] else -1.0), math.sin(tilt)])     # the axis, tip to hand
    x = x @ np.array([a, [-a[1], a[0]]])                       # rows (u, w) -> u a + w a_perp
    x = x - [x[np.argmin(x[:, 1]), 0], x[:, 1].min() - p["dhat"]]      # the tip corner at (0, dhat)
    held = np.arange((p["nx"] + 1 - p["held_columns"]) * (p["ny"] + 1), len(x))
    t1, t2, down = p["t_press"], p["t_press"] + p["t_hold"], -p["press"]
    hand = HandEnergy.Hand(nodes=_readonly(held), rest=_readonly(x[held]), k_hand=p["k_hand"],
                           key_t=_readonly([0.0, t1, t2, t2 + 1.0]),       # then on at drive
                           key_d=_readonly([[0.0, 0.0], [0.0, down], [0.0, down], [p["drive"], down]]))
    terms = ["inertia", "spring"] + ["gravity"] * any(p["gravity"]) + ["hand", "barrier"]
    return Scene(
        params=types.MappingProxyType(p), x0=_readonly(x), v0=_readonly(np.zeros_like(x)),
        e=_readonly(np.asfortranarray(e)), l2=_readonly(MassSpringEnergy.squared_lengths(x, e)),
        k=_readonly(np.full(len(e), p["k"])),
        m=_readonly(np.full(len(x), p["rho"] * p["length"] * p["width"] / len(x))),
        contact_area=_readonly(np.full(len(x), p["width"] / p["ny"])), g=_readonly(p["gravity"]),
        n=_readonly([0.0, 1.0]), o=_readonly([0.0, 0.0]), mu=p["mu"], dhat=p["dhat"], kappa=p["kappa"],
        epsv=p["epsv"], h=p["h"], tol=p["tol"], n_seg=None, side_len=None, friction_updates=p["friction_updates"],
        newton_start=p["newton_start"], max_newton_iterations=p["max_newton_iterations"],
        max_halvings=p["max_halvings"], terms=tuple(terms + ["friction"] * (max(p["mu"], p["mu_s"]) > 0.0)), warnings=(),
        solver=utils.SPDSolver.for_mesh(len(x), e, elements=[held[:, None]]),      # the hand: node blocks
        cells=(p["nx"], p["ny"]), hand=hand, mu_s=p["mu_s"], v_c=p["v_c"])


@dataclass
class StepRecord:
    """One step of a run: its index, the time after it, the new state, its report and wall time."""
    index: int
    t: float
    x: np.ndarray
    v: np.ndarray
    report: time_integrator.StepReport
    wall: float


def simulate(scene, steps):
    """Yield a StepRecord for each of `steps` time steps from the scene's start (x0, v0)."""
    x, v = scene.x0, scene.v0           # read-only: each step returns new arrays
    for i in range(utils.check_whole("steps", steps, 1)):
        start = time.perf_counter()
        x, v, report = time_integrator.step(scene, x, v, step_index=i)
        yield StepRecord(i, time_integrator.step_time(scene, i), x, v, report, time.perf_counter() - start)
