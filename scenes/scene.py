"""What a scene *is*: built once by a scene's builder, never changed by stepping (MuJoCo's model).

`Scene` holds what every scene has. What only some scenes have is one optional part each, None when
the scene has none: the hand (`HandEnergy.Hand`, the chalk's grip), static friction
(`StaticFriction`: a static coefficient above the kinetic one, the chalk's), a moving surface
(`MovingSurface`: the half-space sliding along itself, the tablecloth). Its `contact` (None: no
ground) is what the time step, the analysis and the pictures ask about the surfaces it touches: a
`HalfSpace`, or another unit's object with the same methods (docs/code-tour.md, "The contact").
"""
from dataclasses import dataclass
import types

import numpy as np

import BarrierEnergy
import FrictionEnergy
import HandEnergy
import MassSpringEnergy
import utils
from scenes import ranges


@dataclass(frozen=True)
class StaticFriction:
    """mu falls from mu_s at rest to the scene's kinetic mu over slip speeds of about v_c
    (FrictionEnergy.slip_weakened_mu); not in the lecture: its stick-slip remark."""
    mu_s: float                 # static friction coefficient, above the scene's mu
    v_c: float                  # m/s


@dataclass(frozen=True)
class MovingSurface:
    """The half-space sliding along its tangent t = (n_y, -n_x): a cloth pulled a length L at speed
    U from t_pull, then still. The same set at every time, so the barrier and CCD are unchanged;
    friction slips on v - v_s."""
    pull_speed: float           # U, m/s
    pull_length: float          # L, m
    t_pull: float               # when the pull starts, s
    tangent: np.ndarray         # (2,) t, the direction of the pull

    def offset(self, t):
        """How far the surface has moved along t by time t (m): U min(max(t - t_pull, 0), L / U)."""
        return self.pull_speed * min(max(t - self.t_pull, 0.0), self.pull_length / self.pull_speed)

    def velocity(self, t, h):
        """v_s of the time step of length h ending at t: its displacement over the step, over h, as
        v = (x - x^n) / h (U t inside the pull, 0 outside; the pull moves the cloth L for any h)."""
        return self.tangent * ((self.offset(t) - self.offset(t - h)) / h)


@dataclass(frozen=True)
class HalfSpace:
    """The contact {x : n . (x - o) >= 0}: the slope, the board, the table, still or (`moving`) the
    tablecloth. Its surfaces' distances d_k, normal forces mu lambda_k, CCD bound and tangent are
    BarrierEnergy's and FrictionEnergy's; no rows of x are its own, none prescribed."""
    n: np.ndarray               # (2,) unit normal
    o: np.ndarray               # (2,) a point on it
    moving: MovingSurface = None
    rows = slice(None)          # the body's rows of x: all
    moves = property(lambda self: self.moving is not None)      # along itself

    @property
    def tangent(self):
        """t = (n_y, -n_x), friction's direction."""
        return FrictionEnergy.tangent(self.n)

    @property
    def normals(self):
        """(1, 2): one surface's n."""
        return self.n[None]

    friction_n = property(lambda self: self.n)      # FrictionEnergy's n: the tangent's

    def distances(self, x):
        """d_k = n . (x_k - o), (N,)."""
        return BarrierEnergy.distances(x, self.n, self.o)

    def lambdas(self, scene, x, mu=1.0):
        """mu lambda_k (1, N), one row per surface."""
        return BarrierEnergy.compute_mu_lambda_kernel(x, self.n, self.o, scene.contact_area, mu,
                                                      scene.dhat, scene.kappa)[None]

    def init_step_size(self, x, p):
        """Algorithm 4, line 1 (BarrierEnergy.init_step_size_kernel)."""
        return BarrierEnergy.init_step_size_kernel(x, self.n, self.o, p)

    def prescribe(self, lagged, t):
        """`lagged` as it is, x^n checked above the half-space (NotAboveHalfSpace)."""
        BarrierEnergy.check_above(lagged.x_n, self.n, self.o)
        return lagged

    def free(self, g):
        """g (N, 2) on the unknowns: all of it."""
        return g

    def velocity(self, t, h):
        """v_s (2,) of the step ending at t: the moving surface's, else zero."""
        return np.zeros(2) if self.moving is None else self.moving.velocity(t, h)

    def work(self, scene, x_n, v_n, x):
        """The work that held prescribed rows on their path over a step: none (J)."""
        return 0.0

    def figures(self, scene, x):
        """What log.csv adds for a state x: nothing."""
        return {}


@dataclass(frozen=True)
class Scene:
    """What a scene is: its mesh, masses, contact half-space and the solver's numbers."""
    params: types.MappingProxyType  # the checked parameters it was built from
    x0: np.ndarray              # (N, 2) initial positions
    v0: np.ndarray              # (N, 2) initial velocities
    e: np.ndarray               # (E, 2) spring node indices
    l2: np.ndarray              # (E,) squared rest lengths
    k: np.ndarray               # (E,) spring stiffnesses
    m: np.ndarray               # (N,) node masses
    contact_area: np.ndarray    # (N,) contact weight per node
    g: np.ndarray               # (2,) gravity
    n: np.ndarray               # (2,) unit normal of the half-space (the slope), or None
    o: np.ndarray               # (2,) a point on it, or None
    mu: float                   # the (kinetic) friction coefficient
    dhat: float
    kappa: float
    epsv: float
    h: float
    tol: float
    friction_updates: int
    newton_start: str           # "x_n" or "x_tilde" (time_integrator.predicted_start)
    max_newton_iterations: int
    max_halvings: int
    terms: tuple                # the energy terms the Incremental Potential sums
    warnings: tuple             # what this scene's results cannot be trusted for, as sentences
    solver: utils.SPDSolver     # how H p = -grad E is solved on this mesh
    cells: tuple                # (nx, ny): the mesh's cells (square_mesh.rectangle)
    hand: HandEnergy.Hand = None            # the grip's held nodes and moving targets, or None
    static: StaticFriction = None           # static friction above kinetic, or None
    surface: MovingSurface = None           # the half-space's own tangential motion, or None
    contact: HalfSpace = None               # what it touches (a HalfSpace, or alike), or None
    pushed: object = None                   # the grasp's fingers (its contact), or None
    body: str = "the square"                # the mesh in words (its builder's), as runs say it

    def surface_velocity(self, t):
        """v_s (2,) of the step ending at t (the contact's velocity); zero without one."""
        return np.zeros(2) if self.contact is None else self.contact.velocity(t, self.h)

    @property
    def friction_n(self):
        """The normal friction's tangent comes from (the contact's)."""
        return self.contact.friction_n

    def __reduce__(self):
        """Pickled (a run's frames' process draws it) with its params as a dict."""
        return scene_of, (dict(vars(self), params=dict(self.params)),)


def scene_of(fields):
    """The Scene of pickled `fields` (Scene.__reduce__'s), its params read-only again."""
    return Scene(**dict(fields, params=types.MappingProxyType(fields["params"])))


def readonly(a):
    """`a` as a new numpy array that cannot be written to: a scene's arrays never change."""
    a = np.array(a)
    a.setflags(write=False)
    return a


def assemble(p, x, e, m, w, terms, cells, n=None, o=None, v0=None, warnings=(), elements=(),
             **parts):
    """The Scene a builder returns, from its checked parameters p (the numbers every scene has: k,
    gravity, mu, dhat, kappa, epsv, h, tol and the solver's) and what it made: the mesh x (N, 2) at
    rest, its springs e (E, 2) (rest lengths measured on x), node masses m, contact weight w per
    node (a number, or (N,)), its terms, its cells (nx, ny); the half-space's n, o (None: none),
    its `contact` unless parts give one; v0 (N, 2) (None: at rest); the solver's extra `elements`;
    its optional parts (hand=, ...)."""
    if n is not None:
        parts.setdefault("contact", HalfSpace(readonly(n), readonly(o), parts.get("surface")))
    return Scene(
        params=types.MappingProxyType(p), x0=readonly(x),
        v0=readonly(np.zeros_like(x) if v0 is None else v0),
        e=readonly(np.asfortranarray(e)),       # column by column: e[:, 0] and e[:, 1] gather fast
        l2=readonly(MassSpringEnergy.squared_lengths(x, e)), k=readonly(np.full(len(e), p["k"])),
        m=readonly(m), contact_area=readonly(np.full(len(x), w)), g=readonly(p["gravity"]),
        n=None if n is None else readonly(n), o=None if o is None else readonly(o),
        mu=p["mu"], dhat=p["dhat"], kappa=p["kappa"], epsv=p["epsv"], h=p["h"], tol=p["tol"],
        friction_updates=p["friction_updates"], newton_start=p["newton_start"],
        max_newton_iterations=p["max_newton_iterations"], max_halvings=p["max_halvings"],
        terms=tuple(terms), warnings=tuple(warnings),
        solver=utils.SPDSolver.for_mesh(len(x), e, elements=elements), cells=cells, **parts)


def gap_carrying(load, w, dhat, kappa):
    """d0, the gap at which the barrier pushes a node of contact area w with `load` (N):
    w dhat (-b'(d0)) = load, a root between ranges.CLOSEST_GAP dhat and dhat (a settled start,
    not a dropped one; ranges.check_carries refuses a load the barrier cannot carry)."""
    import scipy.optimize           # here, not at start-up: only a settled start needs it
    return scipy.optimize.brentq(lambda d: -BarrierEnergy.dP_dd(d, w, dhat, kappa) - load,
                                 ranges.CLOSEST_GAP * dhat, dhat, xtol=1e-15)


def fixed(value, decimals):
    """`value` with `decimals` decimals, as a run's closing words write a figure; in 3 digits
    (1e+300) where that would run past 10 digits before the point (a pull speed of 1e-300 m/s)."""
    return f"{value:.{decimals}f}" if abs(value) < 1e10 else f"{value:.3g}"
