"""One implicit Euler time step as minimizing the Incremental Potential (IP)

    E(x) = 1/2 ||x - x_tilde||_M^2 + h^2 sum P(x),  x_tilde = x^n + h v^n,  P over `scene.terms`,

by projected Newton with Algorithm 4's line search; friction lagged from x^n, or Algorithm 5's
fixed point (`scene.friction_updates` > 0). What a scene prescribes is taken at t^{n+1}, rows of
x its contact prescribes as a Dirichlet condition: docs/code-tour.md, "The time step".

`step(scene, x, v, step_index=n)` maps (x^n, v^n) at t^n = n h to (x^{n+1}, v^{n+1}) and a
StepReport, printing nothing, changing no input; `newton_iterates`: one Newton iteration at a time.
"""
import dataclasses
from dataclasses import dataclass, field
import math

import numpy as np

import BarrierEnergy
import FrictionEnergy
import GravityEnergy
import HandEnergy
import InertiaEnergy
import MassSpringEnergy
import utils


class SimulationError(RuntimeError):
    """A time step that could not be completed: its number and the figures of what went wrong. The
    step from x^n (`step_index` n, from 0) is step n + 1, as log.csv numbers the state it ends."""

    def __init__(self, message, step_index, **figures):
        self.step, self.figures = step_index + 1, figures
        self.what = f"step {self.step}: {message}"
        self.figures_said = ", ".join(f"{k}={v:.6g}" if isinstance(v, float) else f"{k}={v}"
                                      for k, v in figures.items())
        super().__init__(self.what + (f" ({self.figures_said})" if figures else ""))


class NewtonNotConverged(SimulationError):
    """Newton hit `scene.max_newton_iterations` with ||p||_inf / h still above `scene.tol`."""


class LineSearchFailed(SimulationError):
    """The line search found no decrease of E along a direction that is not a descent direction."""


class NonFiniteState(SimulationError):
    """An energy overflowed, or H could not be factored (never stepped on)."""


@dataclass
class StepReport:
    """The figures of one time step."""
    residual: float = math.inf      # ||p||_inf / h (m/s) at the end, or ||grad E||_2 / (min m h)
    stalled: bool = False           # the last solve stopped at float64's floor, residual > tol
    alphas: list = field(default_factory=list)  # accepted line-search step sizes, in order
    min_distance: float = math.inf  # smallest node distance to a surface after the step
    friction_updates: int = 0       # Algorithm 5's updates that re-solved the step (0: lagged)
    friction_converged: bool = True  # Algorithm 5 reached its fixed point (always True when lagged)
    friction_work: float = 0.0      # F_f . (x^{n+1} - x^n): friction's work in the lab frame (J)
    surface_work: float = 0.0       # F_f . v_s h: the moving surface's work (J, 0 if still); heat
    #                                 surface_work - friction_work >= 0 (friction's, surface frame)
    friction_force: np.ndarray = None   # (N, 2) with the step's last mu*lambda; None without

    @property
    def newton_iterations(self):
        """Newton iterations, summed over the solves of the step: one accepted alpha each."""
        return len(self.alphas)


@dataclass(frozen=True)
class NewtonIterate:
    """One Newton iteration: the direction at x, the CCD bound, the step the line search took."""
    x: np.ndarray           # (N, 2) the iterate x^i
    p: np.ndarray           # (N, 2) the search direction at x^i
    residual: float         # ||p||_inf / h (m/s); Newton stops when it is <= scene.tol
    alpha_ccd: float        # Algorithm 4, line 1
    alpha: float            # accepted: alpha_ccd / 2^halvings
    halvings: int
    x_next: np.ndarray      # x^i + alpha p (not taken where E did not decrease: Newton stops)
    friction_update: int    # 0: the lagged solve; j >= 1: the j-th re-solve of Algorithm 5


@dataclass(frozen=True)
class Lagged:
    """What E holds fixed during one Newton solve (T^n = I - n n^T is the slope's); None: the scene
    has no such part."""
    x_n: np.ndarray             # (N, 2) x^n; rows the contact prescribes at t^{n+1}
    x_tilde: np.ndarray         # (N, 2) x^n + h v^n; rows the contact prescribes at t^{n+1}
    mu_lambda: np.ndarray       # (N,) mu*lambda, or None without friction
    targets: np.ndarray = None  # the hand's targets at t^{n+1}, or None without a hand
    v_s: np.ndarray = field(default_factory=lambda: np.zeros(2))    # the surface's, over the step


def step_time(scene, step_index):
    """t^{n+1} = (n + 1) h, the time the step from x^n (step_index n) goes to, as simulate says."""
    return (step_index + 1) * scene.h


def friction_update(scene, lagged, x, v=None):
    """FrictionUpdate(x) of Algorithm 5: mu*lambda at x (`lagged` as it is without friction), mu
    scene.mu or, with static friction, slip_weakened_mu at the state (x, v)."""
    if "friction" not in scene.terms:
        return lagged
    mu = scene.mu if scene.static is None else slip_weakened_mu(scene, lagged, x, v)
    return dataclasses.replace(lagged, mu_lambda=scene.contact.lambdas(scene, x, mu).sum(axis=0))


def slip_weakened_mu(scene, lagged, x, v=None):
    """mu_k = mu + (mu_s - mu) exp(-|t . (v_k - v_s)| / v_c) per node (not in the lecture: its chalk
    remark, static friction above kinetic), v the velocity of the state x: v^n at x^n (the lagged
    solve), (x - x^n) / h (v None) at an iterate of Algorithm 5; held through the solve."""
    v = (x - lagged.x_n) / scene.h if v is None else v
    vbarnorm = np.abs((v - lagged.v_s) @ FrictionEnergy.tangent(scene.n))   # |t . (v_k - v_s)|
    return FrictionEnergy.slip_weakened_mu(vbarnorm, scene.mu, scene.static.mu_s, scene.static.v_c)


# --- the Incremental Potential -------------------------------------------------------------------

@dataclass(frozen=True)
class Term:
    """A potential term: its module, `args(scene, lagged, x, v)` of its val/grad/hess in the
    lecture's order (v = (x - x^n) / h - v_s), whether it stores energy (friction dissipates)."""
    module: object
    args: object
    stores_energy: bool


TERMS = {
    "spring": Term(MassSpringEnergy, lambda s, lagged, x, v: (x, s.e, s.l2, s.k), True),
    "gravity": Term(GravityEnergy, lambda s, lagged, x, v: (x, s.m, s.g), True),
    "barrier": Term(BarrierEnergy,
                    lambda s, lagged, x, v: (x, s.n, s.o, s.contact_area, s.dhat, s.kappa), True),
    "friction": Term(FrictionEnergy,
                     lambda s, lagged, x, v: (v, lagged.mu_lambda, s.h, s.friction_n, s.epsv),
                     False),
    "hand": Term(HandEnergy,
                 lambda s, lagged, x, v: (x, s.hand.nodes, lagged.targets, s.hand.k_hand), True),
}


def potential_terms(scene, lagged, x):
    """[(energy module, its arguments)] at x of the scene's terms: TERMS', or the contact's own."""
    v = (x - lagged.x_n) / scene.h - lagged.v_s     # v_p - v_s: friction's slip against the surface
    terms = [TERMS.get(t, scene.contact) for t in scene.terms if t != "inertia"]
    return [(term.module, term.args(scene, lagged, x, v)) for term in terms]


def IP_val(scene, lagged, x):
    """E(x) = 1/2 ||x - x_tilde||_M^2 + h^2 sum P(x); +inf where a node is on or below a surface,
    so Algorithm 4's line search halves away from it."""
    try:
        P = sum(term.val_kernel(*args) for term, args in potential_terms(scene, lagged, x))
    except BarrierEnergy.NotAboveHalfSpace:
        return math.inf
    return InertiaEnergy.val_kernel(x, lagged.x_tilde, scene.m) + scene.h ** 2 * P


def IP_grad(scene, lagged, x):
    """grad E(x) = M (x - x_tilde) + h^2 sum grad P(x), (N, 2)."""
    grad_P = sum(term.grad_kernel(*args) for term, args in potential_terms(scene, lagged, x))
    return InertiaEnergy.grad_kernel(x, lagged.x_tilde, scene.m) + scene.h ** 2 * grad_P


def IP_hess(scene, lagged, x):
    """H(x) = M + h^2 sum hess P(x), terms PSD-projected (H >= M), as [(nodes, blocks)], summed by
    the solver; the springs' blocks are scene.solver's, kept for the run."""
    hess_P = [term.hess_kernel(*args, out=scene.solver.edge_blocks) if term is MassSpringEnergy
              else term.hess_kernel(*args) for term, args in potential_terms(scene, lagged, x)]
    for _, blocks in hess_P:        # in place: each term's blocks are its own (springs': solver's)
        blocks *= scene.h ** 2
    return [InertiaEnergy.hess_kernel(x, lagged.x_tilde, scene.m)] + hess_P


def search_dir(scene, lagged, x, grad_E):
    """Projected Newton's direction p = -H^-1 grad E(x), (N, 2)."""
    return scene.solver.solve(IP_hess(scene, lagged, x), -grad_E.ravel()).reshape(-1, 2)


def predicted_start(scene, lagged):
    """Newton's start with scene.newton_start "x_tilde" (the lecture's is x^n): x^n + alpha h v^n,
    alpha Algorithm 4's CCD along h v^n (why: docs/chalk.md, "Where Newton starts")."""
    prediction = lagged.x_tilde - lagged.x_n
    return lagged.x_n + init_step_size(scene, lagged.x_n, prediction) * prediction


def init_step_size(scene, x, p):
    """Algorithm 4, line 1: CCD against the scene's contact (1 without one)."""
    return 1.0 if scene.contact is None else scene.contact.init_step_size(x, p)


# --- the time step --------------------------------------------------------------------------------

def newton(scene, lagged, x, report, step_index, update=0, start=None):
    """Minimize E from x by projected Newton and Algorithm 4, yielding a NewtonIterate each
    iteration; returns the minimizer once ||p||_inf / h <= tol after one iteration at least, or at
    E's round-off floor (report.stalled). `update`: Algorithm 5's solve; `start`: (p, residual)."""
    E = IP_val(scene, lagged, x)
    p, residual = start or _direction(scene, lagged, x, step_index, False)
    for _ in range(scene.max_newton_iterations):
        if not math.isfinite(E):            # x^n, or an accepted iterate, beyond float64's range
            raise NonFiniteState("the Incremental Potential is not finite", step_index, E=E)
        alpha = alpha_ccd = init_step_size(scene, x, p)                 # Algorithm 4, line 1
        halvings, E_next = 0, IP_val(scene, lagged, x + alpha * p)
        while not E_next <= E and halvings < scene.max_halvings:    # line 2 (NaN: no decrease)
            alpha, halvings = alpha / 2, halvings + 1                   # line 3
            E_next = IP_val(scene, lagged, x + alpha * p)
        x_next = x + alpha * p
        yield NewtonIterate(x, p, residual, alpha_ccd, alpha, halvings, x_next, update)
        if not E_next < E:                  # no decrease: E cannot tell x_next from x
            if residual > scene.tol:        # (else x is converged already, e.g. at rest with p = 0)
                _check_round_off_floor(scene, lagged, x, p, E, E_next, residual, step_index)
            break
        x, E = x_next, E_next
        report.alphas.append(alpha)
        p, residual = _direction(scene, lagged, x, step_index)
        if residual <= scene.tol and math.isfinite(E):     # (-inf: once more, to the check above)
            break
    else:
        raise NewtonNotConverged("Newton did not converge", step_index, residual=residual,
                                 iterations=scene.max_newton_iterations, tol=scene.tol, h=scene.h)
    report.residual, report.stalled = residual, residual > scene.tol   # stalled: at E's floor
    return x


def _direction(scene, lagged, x, step_index, bound_shows_convergence=True):
    """(p, ||p||_inf / h) at x (m/s); (None, bound) where ||grad E||_2 / (min m h), a bound on it
    as H >= M, is already <= tol."""
    g = IP_grad(scene, lagged, x)
    if scene.contact is not None:   # coordinates it prescribes are no unknowns (5_mov_dirichlet)
        g = scene.contact.free(g)
    bound = math.sqrt(np.vdot(g, g)) / scene.m.min() / scene.h
    if bound_shows_convergence and bound <= scene.tol:
        return None, bound
    p = search_dir(scene, lagged, x, g)
    residual = float(np.abs(p).max()) / scene.h
    if not math.isfinite(residual):
        raise NonFiniteState("the Newton direction is not finite", step_index)
    return p, residual


def _check_round_off_floor(scene, lagged, x, p, E, E_next, residual, step_index):
    """LineSearchFailed unless E(x + alpha p) = E(x) along a descent direction (grad E . p < 0):
    E's round-off floor (docs/limits.md)."""
    slope = float(np.vdot(IP_grad(scene, lagged, x), p))
    if not (slope < 0.0 and E_next == E):
        raise LineSearchFailed("line search could not decrease the Incremental Potential",
                               step_index, residual=residual, E=E, E_trial=E_next,
                               directional_derivative=slope)


def newton_iterates(scene, x, v, *, step_index=0):
    """The time step of `step`, yielding a NewtonIterate after each line search; returns
    (x^{n+1}, v^{n+1}, StepReport)."""
    x_n = utils.check_points("x", x, scene.x0.shape)
    v_n = utils.check_points("v", v, scene.x0.shape)
    step_index = utils.check_whole("step_index", step_index, minimum=0)
    t = step_time(scene, step_index)        # t^{n+1}: what the scene prescribes
    targets = scene.hand.targets(t) if "hand" in scene.terms else None
    lagged = Lagged(x_n, x_n + scene.h * v_n, None, targets, scene.surface_velocity(t))
    if scene.contact is not None:           # x^n checked above it; the rows it prescribes
        lagged = scene.contact.prescribe(lagged, t)
    report = StepReport()
    try:
        lagged = friction_update(scene, lagged, x_n, v_n)                 # mu*lambda^n
        # Newton from x^n, as the lecture (or the chalk's predicted start)
        x = lagged.x_n if scene.newton_start == "x_n" else predicted_start(scene, lagged)
        x = yield from newton(scene, lagged, x, report, step_index)
        if "friction" in scene.terms and scene.friction_updates > 0:               # Algorithm 5
            for j in range(1, scene.friction_updates + 2):
                lagged = friction_update(scene, lagged, x)                         # lines 2, 5
                p, report.residual = _direction(scene, lagged, x, step_index)      # line 3
                report.friction_converged = report.residual <= scene.tol
                if report.friction_converged or j > scene.friction_updates:
                    break
                x = yield from newton(scene, lagged, x, report, step_index, j, (p, report.residual))
                report.friction_updates = j
    except (ValueError, np.linalg.LinAlgError) as err:  # an energy overflowed, or H did not factor
        raise NonFiniteState(f"the step's numbers broke down ({err})", step_index) from err
    if "friction" in scene.terms:       # -grad P_f(v^{n+1} - v_s), the last mu*lambda; its work
        F_f = -FrictionEnergy.grad_kernel(*dict(potential_terms(scene, lagged, x))[FrictionEnergy])
        report.friction_force, report.friction_work = F_f, float(np.vdot(F_f, x - x_n))
        report.surface_work = float(np.vdot(F_f.sum(axis=0), lagged.v_s)) * scene.h
    if scene.contact is not None:
        report.min_distance = float(scene.contact.distances(x).min())
    return x, (x - x_n) / scene.h, report      # x^{n+1}, v^{n+1}


def run_out(iterates):
    """What newton_iterates (perhaps part-taken) returns, (x^{n+1}, v^{n+1}, StepReport)."""
    while True:
        try:
            next(iterates)
        except StopIteration as done:   # the generator's return value
            return done.value


def step(scene, x, v, *, step_index=0):
    """(x^{n+1}, v^{n+1}, StepReport) from (x^n, v^n) at t^n = step_index h, which errors name."""
    return run_out(newton_iterates(scene, x, v, step_index=step_index))
