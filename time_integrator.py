"""One implicit Euler time step, written as minimizing the Incremental Potential (IP):

    E(x) = 1/2 ||x - x_tilde||_M^2 + h^2 (sum of the scene's potential terms),  x_tilde = x^n + h v^n,

solved by projected Newton with the filtered backtracking line search of Algorithm 4 (CCD against
the slope, then halving while E increases). Friction uses mu*lambda^n and T^n lagged from x^n
(the lecture's semi-implicit friction); with `scene.friction_updates` > 0 the step runs the
fixed-point iterations of Algorithm 5 for fully implicit friction.

`step(scene, x, v)` returns the next (x, v) and a `StepReport`; it prints nothing and changes
neither the scene nor its inputs. A scene is any object with the attributes `Scene` in
simulator.py has (masses, springs, slope, mu, dhat, kappa, epsv, h, tol, caps, `terms` and the
sparsity `pattern` of its Newton system).
"""
from dataclasses import dataclass, field
import math

import numpy as np

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
    residual: float = math.inf          # final ||p||_inf / h (a velocity, m/s), or an upper bound
                                        # on it where convergence was shown without a factorization
    factorizations: int = 0             # sparse factorizations of H (one per Newton direction)
    alphas: list = field(default_factory=list)  # accepted line-search step sizes, in order
    min_distance: float = math.inf      # smallest node distance to the slope after the step
    friction_iterations: int = 0        # Newton solves with updated mu*lambda (1 = lagged only)
    friction_converged: bool = True     # fixed point reached (always True when lagged)
    friction_work: float = 0.0          # work of the friction forces over the step (J, <= 0)
    # the terms of x alone at x^{n+1}, for the next step to start from (see PositionTerms); the
    # step handed this report takes them and sets this back to None
    end_terms: object = field(default=None, repr=False, compare=False)


@dataclass(frozen=True)
class SceneConstants:
    """What the Incremental Potential needs of a scene that no x changes: M's slot values, the masses
    per DOF, 1 / min m, and the terms' parameters scaled by h^2 (see IncrementalPotential), with
    gravity's gradient (zero without gravity). Read-only, computed once and handed on with the
    position terms."""
    inertia: np.ndarray
    dof_masses: np.ndarray      # (N, 2): m_i twice per row, the masses InertiaEnergy multiplies by
    inv_m_min: float            # H >= M, so ||H^-1||_2 <= 1 / min m
    k_h2: np.ndarray            # h^2 k
    g_h2: np.ndarray            # h^2 g
    kappa_h2: float             # h^2 kappa
    gravity_grad: np.ndarray    # h^2 grad P_g (constant in x)

    @classmethod
    def of(cls, scene):
        unknown = set(scene.terms) - {"inertia", *POTENTIALS}
        if unknown:
            raise ValueError(f"scene.terms has an unknown term {sorted(unknown)[0]!r}")
        x0, h2 = scene.x0, scene.h * scene.h
        inertia = scene.pattern.diagonal(InertiaEnergy.hess_kernel(x0, x0, scene.m))
        dof_masses = np.repeat(scene.m, 2).reshape(-1, 2)
        m_min = float(scene.m.min())
        k_h2, g_h2 = h2 * scene.k, h2 * scene.g
        gravity_grad = (GravityEnergy.grad_kernel(x0, scene.m, g_h2) if "gravity" in scene.terms
                        else np.zeros(x0.shape))
        for a in (inertia, dof_masses, k_h2, g_h2, gravity_grad):
            a.setflags(write=False)
        return cls(inertia, dof_masses, 1.0 / m_min if m_min > 0.0 else math.inf, k_h2, g_h2,
                   h2 * scene.kappa, gravity_grad)


@dataclass(frozen=True)
class PositionTerms:
    """The scene's terms that depend on x alone (springs, gravity, the barrier) at one x: h^2 times
    their sum P, its gradient and the slot values of its Hessian (PSD-projected).
    A step ends with them at x^{n+1}, the next step's x^n; handed that step's report, the next step
    starts from them instead of evaluating the same terms at the same x again (and takes the scene's
    constants from them)."""
    scene: object
    x: np.ndarray               # a copy: the numbers hold for exactly these positions
    P: float
    g: np.ndarray
    H: np.ndarray
    constants: SceneConstants


class IncrementalPotential:
    """E(x) for one Newton solve: the scene's terms with x^n, x_tilde and mu*lambda^n fixed.

    It calls the energies' kernels, which skip the input checks: `build_scene` validated the scene
    once and `step` validates x^n and v^n, and every x it is asked about is x^n plus Newton steps.
    Friction is evaluated on the nodes in contact at x^n only (mu*lambda^n > 0), fixed for the solve.

    Each potential term is linear in one of its parameters (k, g, kappa, mu*lambda), so h^2 P(x) is
    the term itself with that parameter times h^2: the terms are called so (SceneConstants), and no
    value, gradient or Hessian is scaled after the fact.
    """

    def __init__(self, scene, x_n, x_tilde, mu_lambda, start_terms=None):
        self.scene = scene
        self.x_n = x_n
        self.x_tilde = x_tilde
        self.mu_lambda = mu_lambda
        self.h2 = scene.h * scene.h
        self.contacts = np.zeros(0, dtype=np.int64) if mu_lambda is None else (mu_lambda > 0.0).nonzero()[0]
        self.potentials = tuple(t for t in scene.terms if t != "inertia"
                                and (t != "friction" or len(self.contacts)))
        self.contact_x_n = x_n.take(self.contacts, axis=0)
        self.contact_mu_lambda = None if mu_lambda is None else mu_lambda.take(self.contacts)
        self.contact_slots = scene.pattern.node_block_slots(self.contacts)
        self._evaluated = None                # (x, grad E(x), H(x)) of the last evaluate
        self._position_terms = None           # (x, P, grad P, hess P) of h^2 times the terms of x alone
        self._friction_gradient = None        # (x, h^2 grad P_f at the contacts) of the last evaluate
        if start_terms is not None and start_terms.scene is scene:
            self.constants = start_terms.constants
            if start_terms.x.shape == x_n.shape and (start_terms.x == x_n).all():
                self._position_terms = (x_n, start_terms.P, start_terms.g, start_terms.H)
        else:
            self.constants = SceneConstants.of(scene)
        self.inv_m_min = self.constants.inv_m_min
        self.contact_mu_lambda_h2 = None if mu_lambda is None else self.h2 * self.contact_mu_lambda

    def _contact_velocity(self, x):
        """v = (x - x^n) / h at the nodes in contact, the friction term's argument."""
        return (x.take(self.contacts, axis=0) - self.contact_x_n) / self.scene.h

    def val(self, x):
        """E(x) = 1/2 ||x - x_tilde||_M^2 + h^2 sum_terms P(x); +inf where a node is on or below the
        slope (the barrier refuses it), so the line search halves away from it even where round-off
        defeats the CCD bound (the "filter" of the filtered line search)."""
        s, c, P = self.scene, self.constants, 0.0      # P: h^2 times the potentials
        try:
            for term in self.potentials:
                if term == "spring":
                    P += MassSpringEnergy.val_kernel(x, s.e, s.l2, c.k_h2)
                elif term == "gravity":
                    P += GravityEnergy.val_kernel(x, s.m, c.g_h2)
                elif term == "barrier":
                    P += BarrierEnergy.val_kernel(x, s.n, s.o, s.contact_area, s.dhat, c.kappa_h2)
        except BarrierEnergy.NotAboveHalfSpace:
            return math.inf
        if "friction" in self.potentials:       # last, as evaluate adds it
            P += FrictionEnergy.val_kernel(self._contact_velocity(x), self.contact_mu_lambda_h2, s.h, s.n, s.epsv)
        return InertiaEnergy.val_kernel(x, self.x_tilde, c.dof_masses) + P

    def evaluate(self, x):
        """E(x) exactly as val(x) sums it, with grad E(x) = M (x - x_tilde) + h^2 sum_terms grad P(x)
        and the slot values (scene.pattern) of H(x) = M + h^2 sum_terms hess P(x), each term
        PSD-projected (gravity's Hessian is zero), so H >= M: every eigenvalue of H is at least
        min m. Each term's val_grad_hess_kernel shares its geometry (edge vectors, active set,
        contacts) among the three; the terms of x alone are summed apart (_position_terms_at), so
        the step can hand them to the next one. The line search calls it for its first trial, which
        Newton usually accepts and then needs grad E and H at; gradient(x) and hessian(x) reuse them."""
        try:
            return self._evaluate(x)
        except BarrierEnergy.NotAboveHalfSpace:       # the filter, as in val
            return math.inf

    def _evaluate(self, x):
        """evaluate(x) without the filter: NotAboveHalfSpace where the barrier refuses x."""
        s, c = self.scene, self.constants
        P, g, H = self._position_terms_at(x)
        E_inertia, g_inertia = InertiaEnergy.val_grad_kernel(x, self.x_tilde, c.dof_masses)
        g, H = g + g_inertia, H + c.inertia     # new arrays: the terms of x alone stay as they are
        if "friction" in self.potentials:
            P_term, g_term, (_, H_term) = FrictionEnergy.val_grad_hess_kernel(
                self._contact_velocity(x), self.contact_mu_lambda_h2, s.h, s.n, s.epsv)
            g[self.contacts] += g_term          # (every node passed is in contact: mu*lambda > 0)
            s.pattern.add_node_blocks(H, self.contact_slots, H_term)
            P += P_term
            self._friction_gradient = (x, g_term)
        self._evaluated = (x, g, H)
        return E_inertia + P

    def _position_terms_at(self, x):
        """h^2 P, its gradient and its Hessian, P the terms of x alone (all but friction, the last
        term) at x, with each term's val_grad_hess_kernel; kept for the end of the step."""
        known = self._position_terms
        if known is not None and known[0] is x:
            return known[1:]
        s, c, pattern = self.scene, self.constants, self.scene.pattern
        P, g, H = 0.0, c.gravity_grad, None     # g and H are new arrays before any += below
        for term in self.potentials:
            if term == "spring":
                P_term, (_, forces), (_, spring_H) = MassSpringEnergy.val_grad_hess_kernel(x, s.e, s.l2, c.k_h2)
                g = g + pattern.sum_spring_forces(forces)
                H_term = pattern.sum_spring_blocks(spring_H)
                H = H_term if H is None else H + H_term
            elif term == "gravity":
                P_term = GravityEnergy.val_kernel(x, s.m, c.g_h2)
            elif term == "barrier":
                P_term, g_term, (nodes, blocks) = BarrierEnergy.val_grad_hess_kernel(
                    x, s.n, s.o, s.contact_area, s.dhat, c.kappa_h2)
                g = g + g_term
                H = np.zeros(len(pattern.rows)) if H is None else H
                pattern.add_node_blocks(H, pattern.node_block_slots(nodes[:, 0]), blocks)
            else:
                continue                            # friction: depends on x^n too (evaluate)
            P += P_term
        H = np.zeros(len(pattern.rows)) if H is None else H
        self._position_terms = (x, P, g, H)
        return P, g, H

    def friction_gradient(self, x):
        """grad P_f at the contact nodes at x (from the last evaluate's h^2 grad P_f, when it was at x)."""
        known = self._friction_gradient
        if known is not None and known[0] is x:
            return known[1] / self.h2
        s = self.scene
        return FrictionEnergy.grad_kernel(self._contact_velocity(x), self.contact_mu_lambda, s.h, s.n, s.epsv)

    def end_terms(self, x):
        """PositionTerms at x if this solve evaluated them there (else None)."""
        known = self._position_terms
        if known is None or known[0] is not x:
            return None
        x_copy, (P, g, H) = x.copy(), known[1:]
        for a in (x_copy, g, H):
            a.setflags(write=False)                 # evaluate copies them before adding friction
        return PositionTerms(self.scene, x_copy, P, g, H, self.constants)

    def gradient(self, x):
        """grad E(x) (see evaluate)."""
        return self._derivatives(x)[0]

    def hessian(self, x):
        """The slot values of H(x) (see evaluate)."""
        return self._derivatives(x)[1]

    def _derivatives(self, x):
        if self._evaluated is None or self._evaluated[0] is not x:
            self._evaluate(x)           # NotAboveHalfSpace (a ValueError) where x has no derivatives
        return self._evaluated[1:]

    def gradient_and_hessian(self, x):
        """grad E(x) and the slot values of H(x) (see gradient and hessian)."""
        return self.gradient(x), self.hessian(x)

    def search_direction(self, x):
        """Projected Newton direction p = -H^-1 grad E at x (H is PSD-projected, so SPD with M > 0)."""
        pattern = self.scene.pattern
        g, H = self.gradient_and_hessian(x)
        return -pattern.factor_solve(pattern.matrix(H), g.reshape(-1)).reshape(-1, 2)


POTENTIALS = ("spring", "gravity", "barrier", "friction")


def _mu_lambda(scene, x):
    """mu * lambda from the barrier at x, or None when the scene has no friction term."""
    if "friction" not in scene.terms:
        return None
    return BarrierEnergy.compute_mu_lambda_kernel(x, scene.n, scene.o, scene.contact_area, scene.mu,
                                                  scene.dhat, scene.kappa)


def _init_step_size(scene, x, p):
    """Algorithm 4, line 1: CCD against the slope; without a slope the full step is safe."""
    if "barrier" not in scene.terms:
        return 1.0
    return BarrierEnergy.init_step_size_kernel(x, scene.n, scene.o, p)


# Conjugate gradients confirm convergence with the previous iterate's factor when the band is at
# least this wide (or SuperLU solves): a factorization then costs 10 or more triangular solves. Below it
# a factorization costs about as much as the iterations that would try to save it.
CG_MIN_BANDWIDTH = 48
CG_ITERATIONS = 4       # at most this many before giving up and factoring H
# ... and only when the previous direction's residual was at most this many times tol: after a
# larger step H has changed too much for the previous factor to say anything (above all the first
# step out of x^n, where friction's Hessian at v = 0 is the stiff static one)
CG_AFTER_RESIDUAL = 10.0


class NewtonSystem:
    """The Newton directions of one solve, and the lecture's convergence test ||p||_inf / h <= tol.

    The lecture's loop solves H p = -grad E at every iterate, so its last factorization only confirms
    that the loop is done. H = M + h^2 (PSD-projected terms) >= M, so ||H^-1 r||_2 <= ||r||_2 / m_min
    for every r, and convergence can often be confirmed without factoring H:
      1. ||p||_inf <= ||grad E||_2 / m_min, before H is even assembled;
      2. for wide bands, conjugate gradients on H q = -grad E preconditioned by the previous iterate's
         factor: ||p||_inf <= ||q||_inf + ||grad E + H q||_2 / m_min after each iteration.
    Where neither shows ||p||_inf <= tol h, H is factored and p solved for, as in the lecture. Newton
    stops where the lecture's loop stops (up to round-off: the bound covers the exact H^-1 grad E,
    the lecture tests the p it computed); the residual it reports is then the upper bound.
    """

    def __init__(self, scene, ip, step_index):
        self.scene, self.ip, self.step_index = scene, ip, step_index
        self.pattern = scene.pattern
        self.limit = scene.tol * scene.h            # ||p||_inf <= limit <=> converged
        self.use_cg = self.pattern.solver == "superlu" or self.pattern.bandwidth >= CG_MIN_BANDWIDTH
        self.factor = None                          # the factor of the last H solved with
        self.factor_residual = math.inf             # ||p||_inf / h of the direction solved with it
        self.factorizations = 0

    def direction(self, x, iteration):
        """p = -H^-1 grad E at x, by a fresh factorization; and ||p||_inf / h."""
        g = self.ip.gradient(x).reshape(-1)
        return self._solve(self.ip.hessian(x), g, iteration)

    def check(self, x, iteration):
        """(None, bound) when ||p||_inf / h <= bound <= tol is shown without a factorization; else
        (p, ||p||_inf / h) as direction(x) gives them."""
        g = self.ip.gradient(x).reshape(-1)
        residual = math.sqrt(g.dot(g)) * self.ip.inv_m_min / self.scene.h
        if residual <= self.scene.tol:              # the very test _newton makes, on the bound
            return None, residual
        H = self.ip.hessian(x)
        if self.use_cg and self.factor is not None and self.factor_residual <= CG_AFTER_RESIDUAL * self.scene.tol:
            bound = self._cg_bound(H, g)
            if bound is not None and bound / self.scene.h <= self.scene.tol:
                return None, bound / self.scene.h
        return self._solve(H, g, iteration)

    def _solve(self, H, g, iteration):
        self.factor = None                          # no stale factor survives a failed one
        try:
            self.factor = self.pattern.factor(self.pattern.matrix(H))
            p = -self.pattern.solve(self.factor, g)
        except (RuntimeError, np.linalg.LinAlgError) as err:  # SuperLU or LAPACK could not factor H
            raise NonFiniteState(f"the linear solve failed ({err})", self.step_index,
                                 newton_iteration=iteration) from err
        self.factorizations += 1
        residual = float(np.abs(p).max()) / self.scene.h
        if not math.isfinite(residual):
            raise NonFiniteState("the Newton direction is not finite", self.step_index, newton_iteration=iteration)
        self.factor_residual = residual
        return p.reshape(-1, 2), residual

    def _cg_bound(self, H, g):
        """An upper bound on ||H^-1 g||_inf that is <= limit, or None: conjugate gradients on
        H q = g preconditioned by the previous factor, bounded after each iteration by
        ||q||_inf + ||g - H q||_2 / m_min. None as soon as that cannot come out below the limit
        (the previous factor's own answer is over the limit, ||q||_inf - ||g - H q||_2 / m_min is
        over it, or CG_ITERATIONS are done). The first product H z also gives the true residual of
        q = z, the previous factor's own answer: where its bound is below the limit already (the
        usual case), that is the bound, with no second product."""
        pattern, factor, inv_m_min, limit = self.pattern, self.factor, self.ip.inv_m_min, self.limit
        q, r = np.zeros_like(g), g.copy()
        z = pattern.solve(factor, r)
        z_max = np.abs(z).max()
        if not z_max <= limit:
            return None
        A = pattern.to_csc(H)
        d, rz = z, r @ z
        for iteration in range(CG_ITERATIONS):
            Hd = A @ d
            if iteration == 0:                        # q = z: its true residual is g - H z
                r_z = g - Hd
                bound = z_max + math.sqrt(r_z @ r_z) * inv_m_min
                if bound <= limit:
                    return bound
            alpha = rz / (d @ Hd)
            q += alpha * d
            r -= alpha * Hd
            q_max, r_bound = np.abs(q).max(), math.sqrt(r @ r) * inv_m_min
            if not q_max - r_bound <= limit:          # shown not converged (or not finite)
                return None
            if q_max + r_bound <= limit:              # confirm with the true residual g - H q
                r_true = g - A @ q
                bound = q_max + math.sqrt(r_true @ r_true) * inv_m_min
                return bound if bound <= limit else None
            z = pattern.solve(factor, r)
            rz, rz_last = r @ z, rz
            d = z + (rz / rz_last) * d
        return None


def _newton(scene, ip, x, step_index, report, system=None, p=None, residual=None):
    """Minimize `ip` from x by projected Newton with the filtered line search; returns x.

    Stops when ||p||_inf / h <= tol after at least one iteration: the lecture's loop tests before
    iterating, which at small h (h*|g| below tol) would leave a body at rest frozen forever.
    `p`, `residual` (from `system`) are the first direction, when the caller has it already.
    """
    system = system or NewtonSystem(scene, ip, step_index)
    E_last = ip.evaluate(x)
    if p is None:
        p, residual = system.direction(x, 0)
    iterations = 0
    while iterations == 0 or residual > scene.tol:
        if iterations >= scene.max_newton_iterations:
            raise NewtonNotConverged(
                "Newton did not converge", step_index, iterations=iterations, residual=residual,
                tol=scene.tol, h=scene.h)
        alpha = _init_step_size(scene, x, p)
        x_trial = x + alpha * p
        E_new, halvings = ip.evaluate(x_trial), 0   # keeps grad E and H: usually accepted
        while not E_new <= E_last:        # a NaN trial energy is rejected too
            if halvings >= scene.max_halvings:
                if residual <= scene.tol:   # already converged; the rest is round-off in E
                    return _finish(report, system, x, iterations, residual)
                raise LineSearchFailed(
                    "line search could not decrease the Incremental Potential", step_index,
                    newton_iteration=iterations, alpha=alpha, halvings=halvings,
                    residual=residual, E=E_last, E_trial=E_new)
            alpha *= 0.5
            halvings += 1
            x_trial = x + alpha * p
            E_new = ip.val(x_trial)
        x, E_last = x_trial, E_new
        report.alphas.append(alpha)
        iterations += 1
        p, residual = system.check(x, iterations)
    return _finish(report, system, x, iterations, residual)


def _finish(report, system, x, iterations, residual):
    """Add one Newton solve's figures to the step's report; returns its minimizer x."""
    report.residual = residual
    report.newton_iterations += iterations
    report.factorizations += system.factorizations
    system.factorizations = 0
    return x


def step(scene, x, v, step_index=0, previous=None):
    """Advance (x^n, v^n) by one implicit Euler step of scene.h: returns (x^{n+1}, v^{n+1}, StepReport).

    `previous`, the StepReport of the step that ended at this x (optional; `simulator.simulate`
    passes it), lets the step start from the terms of x alone that step already evaluated here
    (its `end_terms`, which this step takes: it sets them to None): the same numbers, one
    evaluation fewer. They are used only for the same scene and exactly the same positions."""
    x_n = utils.check_points("x", x)
    v_n = utils.check_points("v", v)
    if x_n.shape != scene.x0.shape or v_n.shape != scene.x0.shape:
        raise ValueError(f"x and v must have shape {scene.x0.shape}, got {x_n.shape} and {v_n.shape}")
    x_tilde = x_n + scene.h * v_n
    report = StepReport()

    mu_lambda = _mu_lambda(scene, x_n)      # lagged: mu*lambda^n, T^n from x^n (checks x^n is above the slope)
    if mu_lambda is None and "barrier" in scene.terms:
        BarrierEnergy.check_above(x_n, scene.n, scene.o)
    try:
        start_terms = None if previous is None else previous.end_terms
        if start_terms is not None:
            previous.end_terms = None       # handed on once: a kept list of reports holds no copies
        ip = IncrementalPotential(scene, x_n, x_tilde, mu_lambda, start_terms)
        x_next = _newton(scene, ip, x_n, step_index, report)
        report.friction_iterations = 1 if mu_lambda is not None else 0

        if mu_lambda is not None and scene.friction_updates > 0:   # Algorithm 5
            report.friction_converged = False
            for update in range(scene.friction_updates + 1):
                ip = IncrementalPotential(scene, x_n, x_tilde, _mu_lambda(scene, x_next))
                system = NewtonSystem(scene, ip, step_index)
                p, residual = system.check(x_next, 0)
                report.factorizations += system.factorizations
                system.factorizations = 0
                if residual <= scene.tol:       # x_next already minimizes the updated problem
                    report.friction_converged = True
                    report.residual = residual
                    break
                if update == scene.friction_updates:
                    break                       # cap reached, and now known not to be a fixed point
                x_next = _newton(scene, ip, x_next, step_index, report, system, p, residual)
                report.friction_iterations += 1
    except ValueError as err:               # an energy overflowed at the state the solver reached
        raise NonFiniteState(f"an energy became non-finite ({err})", step_index) from err

    v_next = (x_next - x_n) / scene.h
    if len(ip.contacts):            # force -grad P_f at the end of the step, times the displacement
        c = ip.contacts
        report.friction_work = -float((ip.friction_gradient(x_next) * (x_next[c] - x_n[c])).sum())
    if "barrier" in scene.terms:
        report.min_distance = float(BarrierEnergy.distances(x_next, scene.n, scene.o).min())
    report.end_terms = ip.end_terms(x_next)
    return x_next, v_next, report
