"""Log-barrier contact against a half-space (the slope), its CCD step bound and the normal force.

Distance to the half-space: d(x) = n . (x - o) with unit normal n and a point o on its boundary,
so grad d = n and hess d = 0. Per node, weighted by its contact area w_i (the lecture's choice):
    P_b(x) = sum_i w_i dhat b(d_i),   b(d) = kappa/2 (d/dhat - 1) ln(d/dhat)   for d < dhat, else 0.
Only the nodes with d < dhat enter the sums.
"""
import numpy as np

import utils

DHAT = 0.01     # barrier activation distance (m)
KAPPA = 1e5     # barrier stiffness


def _check(x, n, o, contact_area, dhat, kappa):
    x = utils.check_points("x", x)
    n = utils.check_unit_normal("n", n)
    o = utils.check_vector("o", o)
    contact_area = utils.check_per_item("contact_area", contact_area, len(x))
    utils.check_positive("dhat", dhat)
    utils.check_positive("kappa", kappa)
    return x, n, o, contact_area


def distances(x, n, o):
    """d_i = n . (x_i - o) for every node (the unchecked kernel, shared with the integrator)."""
    return (x - o) @ n


def _positive_distances(x, n, o):
    """d for every node; ValueError if any node is on or below the half-space (d <= 0)."""
    d = distances(x, n, o)
    if (d <= 0.0).any():
        i = int(np.argmin(d))
        raise ValueError(f"x: node {i} is at distance {d[i]:.6g} <= 0 from the half-space; "
                         "the barrier is only defined for d > 0")
    return d


def _active(x, n, o, dhat):
    """Indices and distances of the nodes with d < dhat; ValueError if any node has d <= 0."""
    d = _positive_distances(x, n, o)
    idx = np.flatnonzero(d < dhat)
    return idx, d[idx]


def val(x, n, o, contact_area, dhat=DHAT, kappa=KAPPA):
    """P_b = sum_{d_i < dhat} w_i dhat kappa/2 (s - 1) ln s, s = d_i / dhat."""
    x, n, o, contact_area = _check(x, n, o, contact_area, dhat, kappa)
    idx, d = _active(x, n, o, dhat)
    s = d / dhat
    return utils.finite_result("BarrierEnergy.val",
                               float(np.sum(contact_area[idx] * dhat * kappa / 2.0 * (s - 1.0) * np.log(s))))


def dP_dd(d, w, dhat=DHAT, kappa=KAPPA):
    """w dhat b'(d) = w dhat kappa/2 (ln(s)/dhat + (s - 1)/d), s = d/dhat (negative for d < dhat)."""
    s = d / dhat
    return w * dhat * kappa / 2.0 * (np.log(s) / dhat + (s - 1.0) / d)


def grad(x, n, o, contact_area, dhat=DHAT, kappa=KAPPA):
    """grad_i P_b = w_i dhat b'(d_i) n for the active nodes, zero elsewhere."""
    x, n, o, contact_area = _check(x, n, o, contact_area, dhat, kappa)
    idx, d = _active(x, n, o, dhat)
    g = np.zeros_like(x)
    g[idx] = dP_dd(d, contact_area[idx], dhat, kappa)[:, None] * n
    return utils.finite_result("BarrierEnergy.grad", g)


def hess(x, n, o, contact_area, dhat=DHAT, kappa=KAPPA):
    """hess_i P_b = w_i dhat b''(d_i) n n^T, b''(d) = kappa (d + dhat) / (2 d^2 dhat) > 0 (PSD)."""
    x, n, o, contact_area = _check(x, n, o, contact_area, dhat, kappa)
    idx, d = _active(x, n, o, dhat)
    curvature = contact_area[idx] * kappa / 2.0 * (d + dhat) / d / d     # w dhat b''(d), no d^2 underflow
    blocks = curvature[:, None, None] * np.outer(n, n)[None]
    return utils.blocks_to_ijv(idx[:, None], utils.finite_result("BarrierEnergy.hess", blocks))


def init_step_size(x, n, o, p):
    """CCD against the half-space (Algorithm 4, line 1): the largest alpha <= 1 that keeps every
    node on the positive side along x + alpha p, scaled by 0.9 so no node lands on the boundary."""
    x = utils.check_points("x", x)
    p = utils.check_points("p", p)
    if p.shape != x.shape:
        raise ValueError(f"p must have the shape of x {x.shape}, got {p.shape}")
    n = utils.check_unit_normal("n", n)
    o = utils.check_vector("o", o)
    d = _positive_distances(x, n, o)            # every node must start strictly above the slope
    p_n = p @ n
    approaching = p_n < 0.0
    if not approaching.any():
        return 1.0
    return float(min(1.0, np.min(0.9 * d[approaching] / -p_n[approaching])))


def compute_mu_lambda(x, n, o, contact_area, mu, dhat=DHAT, kappa=KAPPA):
    """mu * lambda_k with lambda_k = -dP_k/dd_k = -w_k dhat b'(d_k), the contact force magnitude, for d_k < dhat.

    Zero at the nodes out of contact. Used lagged, from x^n, by the friction term.
    """
    x, n, o, contact_area = _check(x, n, o, contact_area, dhat, kappa)
    mu = float(mu)
    if not np.isfinite(mu) or mu < 0.0:
        raise ValueError(f"mu must be a finite number >= 0, got {mu}")
    idx, d = _active(x, n, o, dhat)
    mu_lambda = np.zeros(len(x))
    mu_lambda[idx] = -mu * dP_dd(d, contact_area[idx], dhat, kappa)
    return mu_lambda
