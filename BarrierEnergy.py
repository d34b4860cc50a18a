"""Log-barrier contact against a half-space (the slope), its CCD step bound and the normal force.

Distance to the half-space: d(x) = n . (x - o) with unit normal n and a point o on its boundary,
so grad d = n and hess d = 0. Per node, weighted by its contact area w_i (the lecture's choice):
    P_b(x) = sum_i w_i dhat b(d_i),   b(d) = kappa/2 (d/dhat - 1) ln(d/dhat)   for d < dhat, else 0.
Only the nodes with d < dhat enter the sums.

`val`, `grad`, `hess`, `init_step_size` and `compute_mu_lambda` check their input, then call the
`*_kernel` function of the same name, which holds the formula and trusts its input (the time
integrator calls the kernels on a scene it has validated once). Every kernel still refuses a node
at d <= 0, where the barrier is not defined.
"""
import numpy as np

import utils

DHAT = 0.01     # barrier activation distance (m)
KAPPA = 1e5     # barrier stiffness


class NotAboveHalfSpace(ValueError):
    """A node on or below the half-space (d <= 0), where the barrier is not defined."""


def _check(x, n, o, contact_area, dhat, kappa):
    x = utils.check_points("x", x)
    n = utils.check_unit_normal("n", n)
    o = utils.check_vector("o", o)
    contact_area = utils.check_per_item("contact_area", contact_area, len(x))
    utils.check_positive("dhat", dhat)
    utils.check_positive("kappa", kappa)
    return x, n, o, contact_area, dhat, kappa


def distances(x, n, o):
    """d_i = n . (x_i - o) = n . x_i - n . o for every node (the unchecked kernel, shared with the
    integrator; in the second form, as x - o would broadcast o over rows of two, which is slow)."""
    return x.dot(n) - float(o.dot(n))


def check_above(x, n, o):
    """NotAboveHalfSpace (a ValueError) naming the first node at d <= 0; the unchecked kernel."""
    _active(x, n, o, np.inf)


def _active(x, n, o, dhat):
    """Indices and distances of the nodes with d < dhat; NotAboveHalfSpace (a ValueError) if any
    node has d <= 0 (every such node has d < dhat)."""
    d = distances(x, n, o)
    idx = (d < dhat).nonzero()[0]
    d_active = d.take(idx)
    if d_active.size and d_active.min() <= 0.0:
        i = int(idx[np.argmin(d_active)])
        raise NotAboveHalfSpace(f"x: node {i} is at distance {d[i]:.6g} <= 0 from the half-space; "
                                "the barrier is only defined for d > 0")
    return idx, d_active


def val(x, n, o, contact_area, dhat=DHAT, kappa=KAPPA):
    """P_b = sum_{d_i < dhat} w_i dhat kappa/2 (s - 1) ln s, s = d_i / dhat (checked; see val_kernel)."""
    return utils.finite_result("BarrierEnergy.val", val_kernel(*_check(x, n, o, contact_area, dhat, kappa)))


def grad(x, n, o, contact_area, dhat=DHAT, kappa=KAPPA):
    """grad_i P_b = w_i dhat b'(d_i) n for the active nodes (checked; see grad_kernel)."""
    return utils.finite_result("BarrierEnergy.grad", grad_kernel(*_check(x, n, o, contact_area, dhat, kappa)))


def hess(x, n, o, contact_area, dhat=DHAT, kappa=KAPPA):
    """hess_i P_b = w_i dhat b''(d_i) n n^T as an IJV triplet (checked; see hess_kernel)."""
    nodes, blocks = hess_kernel(*_check(x, n, o, contact_area, dhat, kappa))
    return utils.blocks_to_ijv(nodes, utils.finite_result("BarrierEnergy.hess", blocks))


def dP_dd(d, w, dhat=DHAT, kappa=KAPPA):
    """w dhat b'(d) = w dhat kappa/2 (ln(s)/dhat + (s - 1)/d), s = d/dhat (negative for d < dhat)."""
    s = d / dhat
    return _dP_dd(d, w, s, np.log(s), dhat, kappa)


def _dP_dd(d, w, s, log_s, dhat, kappa):
    """dP_dd from s = d/dhat and ln s."""
    return (w * (dhat * kappa / 2.0)) * (log_s / dhat + (s - 1.0) / d)


def val_kernel(x, n, o, contact_area, dhat, kappa):
    """P_b = sum_{d_i < dhat} w_i dhat kappa/2 (s - 1) ln s, s = d_i / dhat (see _val)."""
    idx, d = _active(x, n, o, dhat)
    s = d / dhat
    return _val(contact_area.take(idx), s, np.log(s), dhat, kappa)


def grad_kernel(x, n, o, contact_area, dhat, kappa):
    """grad_i P_b = w_i dhat b'(d_i) n for the active nodes, zero elsewhere (see _grad)."""
    idx, d = _active(x, n, o, dhat)
    return _grad(x.shape, idx, dP_dd(d, contact_area.take(idx), dhat, kappa), n)


def hess_kernel(x, n, o, contact_area, dhat, kappa):
    """hess_i P_b = w_i dhat b''(d_i) n n^T (see _blocks). Returns (nodes, blocks): the active nodes
    as (k, 1) element lists and their blocks, entry-major (2, 2, k) (see utils.blocks_to_ijv)."""
    idx, d = _active(x, n, o, dhat)
    return idx[:, None], _blocks(d, contact_area.take(idx), n, dhat, kappa)


def val_grad_hess_kernel(x, n, o, contact_area, dhat, kappa):
    """val_kernel, grad_kernel and hess_kernel at once, from one active set, its weights and one ln s.
    The Hessian comes as (nodes, H), H (3, k) the entries (h00, h01, h11) of each node's 2x2 block
    (what utils.BlockPattern.add_node_blocks adds)."""
    idx, d = _active(x, n, o, dhat)
    w = contact_area.take(idx)
    s = d / dhat
    log_s = np.log(s)
    return (_val(w, s, log_s, dhat, kappa), _grad(x.shape, idx, _dP_dd(d, w, s, log_s, dhat, kappa), n),
            (idx[:, None], utils.outer_entries(n, _curvature(d, w, dhat, kappa))))


def _val(w, s, log_s, dhat, kappa):
    """P_b = sum_{d_i < dhat} w_i dhat kappa/2 (s - 1) ln s over the active nodes, with their
    weights w, s = d_i / dhat and ln s."""
    return dhat * kappa / 2.0 * float(w.dot((s - 1.0) * log_s))


def _grad(shape, idx, dP, n):
    """grad_i P_b = w_i dhat b'(d_i) n for the active nodes idx (dP = w_i dhat b'(d_i)), zero elsewhere."""
    g = np.zeros(shape)
    g[idx] = dP[:, None] * n
    return g


def _blocks(d, w, n, dhat, kappa):
    """hess_i P_b = w_i dhat b''(d_i) n n^T, b''(d) = kappa (d + dhat) / (2 d^2 dhat) > 0 (PSD),
    for the active nodes at distances d with weights w; entry-major (2, 2, k)."""
    return utils.outer_blocks(n, _curvature(d, w, dhat, kappa))


def _curvature(d, w, dhat, kappa):
    """w dhat b''(d) = w kappa (d + dhat) / (2 d^2), without forming d^2 (which underflows)."""
    return w * kappa / 2.0 * (d + dhat) / d / d


def init_step_size(x, n, o, p):
    """CCD against the half-space, scaled by 0.9 (checked; see init_step_size_kernel)."""
    x = utils.check_points("x", x)
    p = utils.check_points("p", p)
    if p.shape != x.shape:
        raise ValueError(f"p must have the shape of x {x.shape}, got {p.shape}")
    n, o = utils.check_unit_normal("n", n), utils.check_vector("o", o)
    _active(x, n, o, np.inf)                    # every node must start strictly above the half-space
    return init_step_size_kernel(x, n, o, p)


def init_step_size_kernel(x, n, o, p):
    """CCD against the half-space (Algorithm 4, line 1): the largest alpha <= 1 that keeps every
    node on the positive side along x + alpha p, scaled by 0.9 so no node lands on the boundary.
    Node i reaches the boundary at alpha_i = d_i / (-n . p_i) if it approaches it (n . p_i < 0), so
    the bound is 0.9 / max_i (-n . p_i / d_i), every d_i > 0."""
    fastest = float((p.dot(-n) / distances(x, n, o)).max(initial=0.0))
    return 1.0 if fastest <= 0.9 else 0.9 / fastest


def compute_mu_lambda(x, n, o, contact_area, mu, dhat=DHAT, kappa=KAPPA):
    """mu * lambda_k, the friction bound of each node (checked; see compute_mu_lambda_kernel)."""
    x, n, o, contact_area, dhat, kappa = _check(x, n, o, contact_area, dhat, kappa)
    mu = float(mu)
    if not np.isfinite(mu) or mu < 0.0:
        raise ValueError(f"mu must be a finite number >= 0, got {mu}")
    return compute_mu_lambda_kernel(x, n, o, contact_area, mu, dhat, kappa)


def compute_mu_lambda_kernel(x, n, o, contact_area, mu, dhat, kappa):
    """mu * lambda_k with lambda_k = -dP_k/dd_k = -w_k dhat b'(d_k), the contact force magnitude, for d_k < dhat.

    Zero at the nodes out of contact. Used lagged, from x^n, by the friction term.
    """
    idx, d = _active(x, n, o, dhat)
    mu_lambda = np.zeros(len(x))
    mu_lambda[idx] = -mu * dP_dd(d, contact_area.take(idx), dhat, kappa)
    return mu_lambda
