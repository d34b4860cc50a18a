"""Semi-implicit dry friction against a half-space with a mollified static-dynamic transition.

With lagged normal force magnitudes mu*lambda^n and tangent operator T^n = I - n n^T (constant
for a half-space), and the tangential velocity vbar_k = (T^n)^T v_k:
    P_f(x) = sum_k mu lambda_k^n f0(||vbar_k|| hhat)                                  (Eq. 9.2.1)
where v = (x - x^n) / hhat, so dv/dx = I / hhat. val/grad/hess below take v and return
P_f and its derivatives with respect to x. Only nodes with mu_lambda > 0 (in contact) enter.
"""
import numpy as np

import utils

EPSV = 1e-3     # eps_v: tangential speed (m/s) below which friction is static-like


def f0(y, epsv, hhat):
    """Eq. 9.2.2, y = ||vbar|| hhat: -y^3/(3 eps_v^2 hhat^2) + y^2/(eps_v hhat) + eps_v hhat/3 for
    y < eps_v hhat, else y. C^1 at y = eps_v hhat, with f0'(y) = f1(y / hhat)."""
    y = np.asarray(y, dtype=np.float64)
    eh = epsv * hhat
    r = y / eh                          # written in r = y/(eps_v hhat): no eps_v^2 to underflow
    return np.where(y < eh, eh * (-r ** 3 / 3.0 + r * r + 1.0 / 3.0), y)


def f1(y, epsv):
    """Mollified magnitude of the friction force direction: -y^2/eps_v^2 + 2y/eps_v for y < eps_v, else 1."""
    y = np.asarray(y, dtype=np.float64)
    r = y / epsv
    return np.where(y < epsv, r * (2.0 - r), 1.0)


def f1_over_y(y, epsv):
    """Eq. 9.2.5, f1(y)/y: (-y + 2 eps_v)/eps_v^2 for y < eps_v, else 1/y. Finite (2/eps_v) at y = 0,
    and never divides by zero there."""
    y = np.asarray(y, dtype=np.float64)
    safe_y = np.where(y < epsv, 1.0, y)
    return np.where(y < epsv, (2.0 - y / epsv) / epsv, 1.0 / safe_y)


def f_hess_term(y, epsv):
    """Eq. 9.2.6, (f1'(y) y - f1(y)) / y^2: -1/eps_v^2 for y < eps_v, else -1/y^2."""
    y = np.asarray(y, dtype=np.float64)
    safe_y = np.where(y < epsv, 1.0, y)
    inv_epsv = 1.0 / np.float64(epsv)      # numpy scalars overflow to inf (caught), never raise
    return np.where(y < epsv, -inv_epsv * inv_epsv, -(1.0 / safe_y) ** 2)


def tangent_operator(n):
    """T = I - n n^T: projects a velocity onto the half-space's tangent line."""
    return np.eye(2) - np.outer(n, n)


def _check(v, mu_lambda, hhat, n, epsv):
    v = utils.check_points("v", v)
    mu_lambda = utils.check_per_item("mu_lambda", mu_lambda, len(v))
    if (mu_lambda < 0).any():
        i = int(np.argmax(mu_lambda < 0))
        raise ValueError(f"mu_lambda must be >= 0, got {mu_lambda[i]} at node {i}")
    utils.check_positive("hhat", hhat)
    utils.check_positive("epsv", epsv)
    n = utils.check_unit_normal("n", n)
    return v, mu_lambda, n


def _contacts(v, mu_lambda, n):
    """Indices of the nodes in contact, their mu*lambda, T, vbar = T^T v and ||vbar||."""
    idx = np.flatnonzero(mu_lambda > 0.0)
    T = tangent_operator(n)
    vbar = v[idx] @ T           # row k is (T^T v_k)^T; T is symmetric
    return idx, mu_lambda[idx], T, vbar, np.sqrt(np.einsum("ij,ij->i", vbar, vbar))


def val(v, mu_lambda, hhat, n, epsv=EPSV):
    """P_f = sum_k mu lambda_k f0(||vbar_k|| hhat) (Eq. 9.2.1)."""
    v, mu_lambda, n = _check(v, mu_lambda, hhat, n, epsv)
    _, ml, _, _, vbarnorm = _contacts(v, mu_lambda, n)
    return utils.finite_result("FrictionEnergy.val", float(np.sum(ml * f0(vbarnorm * hhat, epsv, hhat))))


def grad(v, mu_lambda, hhat, n, epsv=EPSV):
    """grad_k P_f = mu lambda_k T (f1(||vbar_k||)/||vbar_k||) vbar_k (Eq. 9.2.3); zero at vbar = 0."""
    v, mu_lambda, n = _check(v, mu_lambda, hhat, n, epsv)
    idx, ml, T, vbar, vbarnorm = _contacts(v, mu_lambda, n)
    g = np.zeros_like(v)
    g[idx] = (ml * f1_over_y(vbarnorm, epsv))[:, None] * (vbar @ T)
    return utils.finite_result("FrictionEnergy.grad", g)


def hess(v, mu_lambda, hhat, n, epsv=EPSV, project_psd=True):
    """hess_k P_f = mu lambda_k T [ (f1'y - f1)/y^3 vbar vbar^T + f1/y I ] T^T / hhat   (Eq. 9.2.4),
    y = ||vbar_k||; at y = 0 only the f1/y I part remains. The bracket is PSD for the lecture's f1;
    `project_psd` clamps the round-off (as the lecture's make_PD does)."""
    v, mu_lambda, n = _check(v, mu_lambda, hhat, n, epsv)
    idx, ml, T, vbar, y = _contacts(v, mu_lambda, n)
    outer = vbar[:, :, None] * vbar[:, None, :] / np.where(y > 0.0, y, 1.0)[:, None, None]
    inner = (f_hess_term(y, epsv)[:, None, None] * outer
             + f1_over_y(y, epsv)[:, None, None] * np.eye(2))
    if project_psd:
        inner = utils.project_psd_2x2(inner)
    blocks = T @ inner @ T.T
    blocks = (ml / hhat)[:, None, None] * 0.5 * (blocks + np.swapaxes(blocks, 1, 2))  # exact symmetry
    return utils.blocks_to_ijv(idx[:, None], utils.finite_result("FrictionEnergy.hess", blocks))
