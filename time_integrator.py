"""One implicit Euler time step, written as minimizing the Incremental Potential (IP):

    E(x) = 1/2 ||x - x_tilde||_M^2 + h^2 (sum of the scene's potential terms),  x_tilde = x^n + h v^n,

solved by projected Newton with the filtered backtracking line search of Algorithm 4 (CCD against
the slope, then halving while E increases). Friction uses mu*lambda^n and T^n lagged from x^n
(the lecture's semi-implicit friction); with `scene.friction_updates` > 0 the step runs the
fixed-point iterations of Algorithm 5 for fully implicit friction.

`step(scene, x, v)` returns the next (x, v) and a `StepReport`; it prints nothing and changes
neither the scene nor its inputs. A scene is any object with the attributes `Scene` in
simulator.py has (masses, springs, slope, mu, dhat, kappa, epsv, h, tol, caps and `terms`).
"""
from dataclasses import dataclass, field
import math

import numpy as np
import scipy.sparse.linalg

import BarrierEnergy
import FrictionEnergy
import GravityEnergy
import InertiaEnergy
import MassSpringEnergy
import utils


class SimulationError(RuntimeError):
    """A time step that could not be completed; carries the step index and what went wrong."""

    def __init__(self, message, step, **figures):
        self.step = step
        self.figures = figures
        details = ", ".join(f"{k}={_fmt(v)}" for k, v in figures.items())
        super().__init__(f"step {step}: {message} ({details})")


class NewtonNotConverged(SimulationError):
    """Newton hit `scene.max_newton_iterations` with the residual still above `scene.tol`."""


class LineSearchFailed(SimulationError):
    """The backtracking line search halved `scene.max_halvings` times without decreasing E."""


class NonFiniteState(SimulationError):
    """The Newton direction came out non-finite, or the linear solve broke down (never stepped on)."""


def _fmt(value):
    return f"{value:.6g}" if isinstance(value, float) else str(value)


@dataclass
class StepReport:
    """The figures of one time step."""
    newton_iterations: int = 0          # Newton iterations, summed over friction updates
    residual: float = math.inf          # final ||p||_inf / h (a velocity, m/s)
    alphas: list = field(default_factory=list)  # accepted line-search step sizes, in order
    min_distance: float = math.inf      # smallest node distance to the slope after the step
    friction_iterations: int = 0        # Newton solves with updated mu*lambda (1 = lagged only)
    friction_converged: bool = True     # fixed point reached (always True when lagged)
    friction_work: float = 0.0          # work of the friction forces over the step (J, <= 0)


class IncrementalPotential:
    """E(x) for one Newton solve: the scene's terms with x^n, x_tilde and mu*lambda^n fixed."""

    def __init__(self, scene, x_n, x_tilde, mu_lambda):
        self.scene = scene
        self.x_n = x_n
        self.x_tilde = x_tilde
        self.mu_lambda = mu_lambda
        self.h2 = scene.h * scene.h

    def _terms(self):
        s = self.scene
        return s.terms if self.mu_lambda is not None else tuple(t for t in s.terms if t != "friction")

    def _call(self, kind, x):
        """Evaluate val, grad or hess of every term of the scene, as a list (inertia first)."""
        s, out = self.scene, []
        for term in self._terms():
            if term == "inertia":
                out.append(getattr(InertiaEnergy, kind)(x, self.x_tilde, s.m))
                continue
            if term == "spring":
                r = getattr(MassSpringEnergy, kind)(x, s.e, s.l2, s.k)
            elif term == "gravity":
                r = getattr(GravityEnergy, kind)(x, s.m, s.g)
            elif term == "barrier":
                r = getattr(BarrierEnergy, kind)(x, s.n, s.o, s.contact_area, s.dhat, s.kappa)
            elif term == "friction":
                vel = (x - self.x_n) / s.h
                r = getattr(FrictionEnergy, kind)(vel, self.mu_lambda, s.h, s.n, s.epsv)
            else:
                raise ValueError(f"scene.terms has an unknown term {term!r}")
            out.append(utils.scale_ijv(r, self.h2) if kind == "hess" else self.h2 * r)
        return out

    def val(self, x):
        """E(x); +inf where a node is on or below the slope, so the line search halves away from it
        even where round-off defeats the CCD bound (the "filter" of the filtered line search)."""
        s = self.scene
        if "barrier" in s.terms and BarrierEnergy.distances(x, s.n, s.o).min() <= 0.0:
            return math.inf
        return sum(self._call("val", x))

    def grad(self, x):
        return sum(self._call("grad", x))

    def search_direction(self, x):
        """Projected Newton direction p = -H^-1 grad E at x (H is PSD-projected, so SPD with M > 0)."""
        H = utils.ijv_to_csr(utils.concat_ijv(self._call("hess", x)), 2 * len(x))
        g = self.grad(x).ravel()
        # H = M + h^2 (PSD terms) is symmetric positive definite: SuperLU in symmetric mode with
        # a fill-reducing minimum-degree ordering of the symmetric pattern A^T + A, and no
        # off-diagonal pivoting (diag_pivot_thresh=0) because an SPD matrix needs none; this keeps
        # the factor as sparse as a Cholesky factor instead of the larger unsymmetric LU.
        lu = scipy.sparse.linalg.splu(H.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                      options={"SymmetricMode": True})
        return -lu.solve(g).reshape(-1, 2)


def _mu_lambda(scene, x):
    """mu * lambda from the barrier at x, or None when the scene has no friction term."""
    if "friction" not in scene.terms:
        return None
    return BarrierEnergy.compute_mu_lambda(x, scene.n, scene.o, scene.contact_area, scene.mu,
                                           scene.dhat, scene.kappa)


def _init_step_size(scene, x, p):
    """Algorithm 4, line 1: CCD against the slope; without a slope the full step is safe."""
    if "barrier" not in scene.terms:
        return 1.0
    return BarrierEnergy.init_step_size(x, scene.n, scene.o, p)


def _direction(ip, x, step_index, iteration):
    """ip.search_direction(x), with a breakdown of the sparse solver turned into NonFiniteState."""
    try:
        return ip.search_direction(x)
    except RuntimeError as err:             # SuperLU: "Factor is exactly singular" and the like
        raise NonFiniteState(f"the linear solve failed ({err})", step_index, newton_iteration=iteration) from err


def _residual(scene, p, step_index, iteration):
    """||p||_inf / h, the lecture's convergence measure (a velocity); NonFiniteState if p is not finite."""
    residual = float(np.abs(p).max()) / scene.h
    if not math.isfinite(residual):
        raise NonFiniteState("the Newton direction is not finite", step_index, newton_iteration=iteration)
    return residual


def _newton(scene, ip, x, step_index, report, p=None):
    """Minimize `ip` from x by projected Newton with the filtered line search; returns x.

    Stops when ||p||_inf / h < tol after at least one iteration: the lecture's loop tests before
    iterating, which at small h (h*|g| below tol) would leave a body at rest frozen forever.
    """
    E_last = ip.val(x)
    if p is None:
        p = _direction(ip, x, step_index, 0)
    residual = _residual(scene, p, step_index, 0)
    iterations = 0
    while iterations == 0 or residual > scene.tol:
        if iterations >= scene.max_newton_iterations:
            raise NewtonNotConverged(
                "Newton did not converge", step_index, iterations=iterations, residual=residual,
                tol=scene.tol, h=scene.h)
        alpha = _init_step_size(scene, x, p)
        E_new, halvings = ip.val(x + alpha * p), 0
        while not E_new <= E_last:        # a NaN trial energy is rejected too
            if halvings >= scene.max_halvings:
                if residual <= scene.tol:   # already converged; the rest is round-off in E
                    report.residual = residual
                    report.newton_iterations += iterations
                    return x
                raise LineSearchFailed(
                    "line search could not decrease the Incremental Potential", step_index,
                    newton_iteration=iterations, alpha=alpha, halvings=halvings,
                    residual=residual, E=E_last, E_trial=E_new)
            alpha *= 0.5
            halvings += 1
            E_new = ip.val(x + alpha * p)
        x = x + alpha * p
        E_last = E_new
        report.alphas.append(alpha)
        iterations += 1
        p = _direction(ip, x, step_index, iterations)
        residual = _residual(scene, p, step_index, iterations)
    report.residual = residual
    report.newton_iterations += iterations
    return x


def step(scene, x, v, step_index=0):
    """Advance (x^n, v^n) by one implicit Euler step of scene.h: returns (x^{n+1}, v^{n+1}, StepReport)."""
    x_n = utils.check_points("x", x)
    v_n = utils.check_points("v", v)
    if x_n.shape != scene.x0.shape or v_n.shape != scene.x0.shape:
        raise ValueError(f"x and v must have shape {scene.x0.shape}, got {x_n.shape} and {v_n.shape}")
    x_tilde = x_n + scene.h * v_n
    report = StepReport()

    mu_lambda = _mu_lambda(scene, x_n)      # lagged: mu*lambda^n, T^n from x^n (checks x^n is above the slope)
    try:
        ip = IncrementalPotential(scene, x_n, x_tilde, mu_lambda)
        x_next = _newton(scene, ip, x_n, step_index, report)
        report.friction_iterations = 1 if mu_lambda is not None else 0

        if mu_lambda is not None and scene.friction_updates > 0:   # Algorithm 5
            report.friction_converged = False
            for update in range(scene.friction_updates + 1):
                ip = IncrementalPotential(scene, x_n, x_tilde, _mu_lambda(scene, x_next))
                p = _direction(ip, x_next, step_index, 0)
                residual = _residual(scene, p, step_index, 0)
                if residual <= scene.tol:       # x_next already minimizes the updated problem
                    report.friction_converged = True
                    report.residual = residual
                    break
                if update == scene.friction_updates:
                    break                       # cap reached, and now known not to be a fixed point
                x_next = _newton(scene, ip, x_next, step_index, report, p=p)
                report.friction_iterations += 1
    except ValueError as err:               # an energy overflowed at the state the solver reached
        raise NonFiniteState(f"an energy became non-finite ({err})", step_index) from err

    v_next = (x_next - x_n) / scene.h
    if ip.mu_lambda is not None:    # force -grad P_f at the end of the step, times the displacement
        force = -FrictionEnergy.grad(v_next, ip.mu_lambda, scene.h, scene.n, scene.epsv)
        report.friction_work = float(np.sum(force * (x_next - x_n)))
    if "barrier" in scene.terms:
        report.min_distance = float(np.min(BarrierEnergy.distances(x_next, scene.n, scene.o)))
    return x_next, v_next, report
