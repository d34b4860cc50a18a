"""Log-barrier contact against a half-space (the slope), its CCD step bound and the normal force.

Distance to the half-space: d(x) = n . (x - o), with unit normal n and a point o on it, so
grad d = n and hess d = 0. Per node, weighted by its contact area w_i (the lecture's choice):

    P_b(x) = sum_i w_i dhat b(d_i),   b(d) = kappa/2 (d/dhat - 1) ln(d/dhat)   for d < dhat, else 0.

Only the nodes with d < dhat enter. `val`, `grad`, `hess`, `init_step_size` and `compute_mu_lambda`
check their input and call the `*_kernel` of the same name, which holds the formula and trusts its
input. The kernels of P_b and of mu*lambda refuse a node at d <= 0, where the barrier is undefined.
"""
import numpy as np

import utils

DHAT = 0.01     # barrier activation distance (m)
KAPPA = 1e5     # barrier stiffness
# what a result that overflowed came from (utils.finite_result)
ARGUMENTS = "contact_area, dhat, kappa and the distances to the half-space"


class NotAboveHalfSpace(ValueError):
    """A node on or below the half-space (d <= 0), where the barrier is not defined."""


def _check(x, n, o, contact_area, dhat, kappa):
    x = utils.check_points("x", x)
    return (x, utils.check_unit_normal("n", n), utils.check_vector("o", o),
            utils.check_per_item("contact_area", contact_area, len(x)),
            utils.check_positive("dhat", dhat), utils.check_positive("kappa", kappa))


def val(x, n, o, contact_area, dhat=DHAT, kappa=KAPPA):
    """P_b = sum_{d_i < dhat} w_i dhat kappa/2 (s - 1) ln s, s = d_i / dhat (checked: val_kernel)"""
    checked = _check(x, n, o, contact_area, dhat, kappa)
    return utils.finite_result("BarrierEnergy.val", val_kernel(*checked), ARGUMENTS)


def grad(x, n, o, contact_area, dhat=DHAT, kappa=KAPPA):
    """grad_i P_b = w_i dhat b'(d_i) n (checked; see grad_kernel)."""
    checked = _check(x, n, o, contact_area, dhat, kappa)
    return utils.finite_result("BarrierEnergy.grad", grad_kernel(*checked), ARGUMENTS)


def hess(x, n, o, contact_area, dhat=DHAT, kappa=KAPPA):
    """hess_i P_b = w_i dhat b''(d_i) n n^T as an IJV triplet (checked; see hess_kernel)."""
    nodes, blocks = hess_kernel(*_check(x, n, o, contact_area, dhat, kappa))
    return utils.blocks_to_ijv(nodes, utils.finite_result("BarrierEnergy.hess", blocks, ARGUMENTS))


def distances(x, n, o):
    """d_i = n . (x_i - o) for every node."""
    return x.dot(n) - o.dot(n)


def _active(x, n, o, dhat):
    """The nodes with d < dhat and their distances; NotAboveHalfSpace if any node has d <= 0."""
    d = distances(x, n, o)
    if d.min() <= 0.0:
        raise NotAboveHalfSpace(f"x: node {d.argmin()} is at distance {d.min():.6g} <= 0, under it")
    i = (d < dhat).nonzero()[0]
    return i, d.take(i)                         # (take: d[i], faster on small arrays)


def check_above(x, n, o):
    """NotAboveHalfSpace (a ValueError) naming the lowest node if any node has d <= 0."""
    _active(x, n, o, np.inf)


def val_kernel(x, n, o, contact_area, dhat, kappa):
    """P_b = sum_{d_i < dhat} w_i dhat kappa/2 (s - 1) ln s, s = d_i / dhat."""
    i, d = _active(x, n, o, dhat)
    s = d / dhat
    return float(contact_area.take(i) @ ((s - 1.0) * np.log(s))) * dhat * kappa / 2.0


def dP_dd(d, w, dhat, kappa):
    """w dhat b'(d) = w dhat kappa/2 (ln(s)/dhat + (s - 1)/d), s = d / dhat: dP_b/dd_i, < 0 below
    dhat."""
    s = d / dhat
    return w * dhat * kappa / 2.0 * (np.log(s) / dhat + (s - 1.0) / d)


def grad_kernel(x, n, o, contact_area, dhat, kappa):
    """grad_i P_b = w_i dhat b'(d_i) n for the nodes with d_i < dhat, zero elsewhere."""
    i, d = _active(x, n, o, dhat)
    g = np.zeros(x.shape)
    g[i] = dP_dd(d, contact_area.take(i), dhat, kappa)[:, None] * n
    return g


def hess_kernel(x, n, o, contact_area, dhat, kappa):
    """hess_i P_b = w_i dhat b''(d_i) n n^T, b''(d) = kappa (d + dhat) / (2 d^2 dhat) > 0 (PSD as
    it is), for the nodes with d_i < dhat; written (d + dhat) / d / d: d^2 underflows first."""
    i, d = _active(x, n, o, dhat)
    curvature = contact_area.take(i) * kappa / 2.0 * (d + dhat) / d / d
    return i[:, None], curvature[:, None, None] * (n[:, None] * n)      # n n^T


def init_step_size(x, n, o, p):
    """CCD against the half-space, scaled by 0.9 (checked; see init_step_size_kernel)."""
    x, p = utils.check_points("x", x), utils.check_points("p", p)
    if p.shape != x.shape:
        raise ValueError(f"p must have the shape of x {x.shape}, got {p.shape}")
    n, o = utils.check_unit_normal("n", n), utils.check_vector("o", o)
    check_above(x, n, o)
    return init_step_size_kernel(x, n, o, p)


def approach_rates(x, n, o, p):
    """-n . p_i / d_i for every node: the share of its distance to the half-space node i covers per
    unit step along p (> 0 where it approaches); it reaches the half-space at alpha_i = 1 / that."""
    return p @ -n / distances(x, n, o)


def init_step_size_kernel(x, n, o, p):
    """Algorithm 4, line 1: alpha = min(1, 0.9 alpha_max), alpha_max the largest step along p that
    keeps every node above the half-space: a node approaching it (n . p_i < 0) reaches it at
    alpha_i = d_i / (-n . p_i), so alpha = 0.9 / max_i (-n . p_i / d_i) when that max exceeds 0.9,
    else 1."""
    return 0.9 / max(float(approach_rates(x, n, o, p).max(initial=0.0)), 0.9)


def compute_mu_lambda(x, n, o, contact_area, mu, dhat=DHAT, kappa=KAPPA):
    """mu * lambda_k, the friction bound of each node; mu one coefficient, or one per node (checked;
    see compute_mu_lambda_kernel)."""
    x, n, o, contact_area, dhat, kappa = _check(x, n, o, contact_area, dhat, kappa)
    if np.ndim(mu) == 0:
        mu = utils.check_nonnegative("mu", mu)
    else:
        mu = utils.check_per_item("mu", mu, len(x), must_be=">= 0")
    mu_lambda = compute_mu_lambda_kernel(x, n, o, contact_area, mu, dhat, kappa)
    return utils.finite_result("BarrierEnergy.compute_mu_lambda", mu_lambda, ARGUMENTS)


def compute_mu_lambda_kernel(x, n, o, contact_area, mu, dhat, kappa):
    """mu * lambda_k, lambda_k = -w_k dhat b'(d_k) = n . (-grad_k P_b) the contact force magnitude
    (zero beyond dhat). mu is a number, or an array of one mu_k per node (slip-weakened friction,
    FrictionEnergy.slip_weakened_mu). The friction term uses it lagged, from x^n."""
    return -mu * (grad_kernel(x, n, o, contact_area, dhat, kappa) @ n)
