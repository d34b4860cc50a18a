"""Semi-implicit dry friction against a half-space, with the lecture's mollified static-dynamic
transition.

With the normal force magnitudes mu*lambda^n and the tangent operator T^n lagged from x^n, and
vbar_k = (T^n)^T v_k the tangential relative velocity of node k, v = (x - x^n) / hhat - v_s:

    P_f(x) = sum_k mu lambda_k^n f0(||vbar_k|| hhat)                 (the lecture's P_f)

`val`, `grad`, `hess` take v and return P_f and its derivatives in x (dv/dx = I / hhat).
Only the nodes with mu_lambda > 0 (in contact at x^n) enter. mu_lambda is per node, so a coefficient
per node (`slip_weakened_mu`, static above kinetic: the chalk's stick-slip) needs nothing new here.

For a half-space in 2-D the tangent line has one unit direction t = (n_y, -n_x), so T = I - n n^T =
t t^T and vbar_k = u_k t with u_k = t . v_k: ||vbar_k|| = |u_k|. The code computes in that form.
The slide's T_k = [I - n n^T; n n^T - I] acts on [v_p; v_s]; a surface's v_s is prescribed (zero
for a still one), so the caller passes v = v_p - v_s (time_integrator.potential_terms) and T_k
reduces to T = t t^T (`tangent`).

`val`, `grad`, `hess` check their input and call the `*_kernel` of the same name, which holds the
formula and trusts its input (the time integrator calls the kernels on a scene validated once).
"""
import math

import numpy as np

import utils

EPSV = 1e-3     # eps_v (m/s): tangential speed below which friction is static-like
ARGUMENTS = "v, mu_lambda, hhat and epsv"   # what an overflowed result came from (finite_result)


# --- the mollifier (the lecture's three functions; written in r = ||vbar|| / eps_v) ---------------

def f0(vbarnorm, epsv, hhat):
    """f0(||vbar|| hhat): with y = ||vbar|| hhat,
    -y^3/(3 eps_v^2 hhat^2) + y^2/(eps_v hhat) + eps_v hhat/3 for ||vbar|| < eps_v, else y.
    C^1, with f0'(y) = f1(y / hhat)."""
    r = vbarnorm / epsv
    return np.where(vbarnorm < epsv, epsv * hhat * (r * r * (1 - r / 3) + 1 / 3), vbarnorm * hhat)


def f1_div_vbarnorm(vbarnorm, epsv):
    """f1(||vbar||) / ||vbar||: (-||vbar|| + 2 eps_v) / eps_v^2 for ||vbar|| < eps_v, else
    1 / ||vbar||. Finite (2 / eps_v) at ||vbar|| = 0."""
    return np.where(vbarnorm < epsv, (2 - vbarnorm / epsv) / epsv, 1 / np.maximum(vbarnorm, epsv))


def f_hess_term(vbarnorm, epsv):
    """(f1'(||vbar||) ||vbar|| - f1(||vbar||)) / ||vbar||^2: -1 / eps_v^2 for ||vbar|| < eps_v, else
    -1 / ||vbar||^2."""
    return -1.0 / np.maximum(vbarnorm, epsv) ** 2


def f1_inverse(f, epsv):
    """The speed v where the mollifier reaches f <= 1: f1(v) = 2v/eps_v - v^2/eps_v^2 = f,
    v = eps_v (1 - sqrt(1 - f)); a held body creeps there, f its load over mu N."""
    return epsv * (1.0 - math.sqrt(1.0 - f))


# --- friction that weakens with slip (not in the lecture: its chalk remark, mu_s > mu_k) ----------

def slip_weakened_mu(vbarnorm, mu, mu_s, v_c):
    """mu(||vbar||) = mu + (mu_s - mu) exp(-||vbar|| / v_c): the static coefficient mu_s at rest,
    falling to the kinetic mu once the node slips much faster than v_c. The time integrator
    evaluates it in FrictionUpdate only, at the velocity of x^n (or of Algorithm 5's iterate), and
    holds it fixed through the Newton solve like lambda and T, so P_f stays a potential there."""
    return mu + (mu_s - mu) * np.exp(-vbarnorm / v_c)


# --- P_f, its gradient and Hessian ---------------------------------------------------------------

def _check(v, mu_lambda, hhat, n, epsv):
    v = utils.check_points("v", v)
    return (v, utils.check_per_item("mu_lambda", mu_lambda, len(v), must_be=">= 0"),
            utils.check_positive("hhat", hhat), utils.check_unit_normal("n", n),
            utils.check_epsv(epsv))


def val(v, mu_lambda, hhat, n, epsv=EPSV):
    """P_f = sum_k mu lambda_k f0(||vbar_k|| hhat) (checked; see val_kernel)."""
    checked = _check(v, mu_lambda, hhat, n, epsv)
    return utils.finite_result("FrictionEnergy.val", val_kernel(*checked), ARGUMENTS)


def grad(v, mu_lambda, hhat, n, epsv=EPSV):
    """grad_k P_f = mu lambda_k T (f1(||vbar_k||) / ||vbar_k||) vbar_k (checked; grad_kernel)."""
    checked = _check(v, mu_lambda, hhat, n, epsv)
    return utils.finite_result("FrictionEnergy.grad", grad_kernel(*checked), ARGUMENTS)


def hess(v, mu_lambda, hhat, n, epsv=EPSV, project_psd=True):
    """hess_k P_f as an IJV triplet (checked; see hess_kernel)."""
    nodes, blocks = hess_kernel(*_check(v, mu_lambda, hhat, n, epsv), project_psd=project_psd)
    return utils.blocks_to_ijv(nodes, utils.finite_result("FrictionEnergy.hess", blocks, ARGUMENTS))


def tangent(n):
    """t = (n_y, -n_x), the unit tangent of the half-space of normal n: T = I - n n^T = t t^T."""
    return np.array([n[1], -n[0]])


def _contacts(v, mu_lambda, n):
    """The nodes in contact (mu_lambda > 0), their mu lambda, t, and u = t . v (vbar = u t,
    ||vbar|| = |u|)."""
    k = (mu_lambda > 0.0).nonzero()[0]
    t = tangent(n)
    return k, mu_lambda.take(k), t, v.take(k, axis=0).dot(t)        # (take: [k], faster when small)


def val_kernel(v, mu_lambda, hhat, n, epsv):
    """P_f = sum_k mu lambda_k f0(||vbar_k|| hhat)."""
    k, mu_lambda, t, u = _contacts(v, mu_lambda, n)
    return float(mu_lambda @ f0(np.abs(u), epsv, hhat))


def grad_kernel(v, mu_lambda, hhat, n, epsv):
    """grad_k P_f = mu lambda_k T (f1(||vbar_k||) / ||vbar_k||) vbar_k
    = mu lambda_k f1/||vbar|| u_k t (T vbar = vbar = u t); zero at vbar = 0 and out of contact."""
    k, mu_lambda, t, u = _contacts(v, mu_lambda, n)
    g = np.zeros(v.shape)
    g[k] = (mu_lambda * f1_div_vbarnorm(np.abs(u), epsv) * u)[:, None] * t
    return g


def hess_kernel(v, mu_lambda, hhat, n, epsv, project_psd=True):
    """hess_k P_f = mu lambda_k T [f_hess_term / ||vbar|| vbar vbar^T + f1 / ||vbar|| I] T^T / hhat.

    With T = t t^T and vbar = u t the bracket between T and T^T acts on t alone:
    T [...] T^T = (f_hess_term ||vbar|| + f1 / ||vbar||) t t^T  (at vbar = 0 only f1 / ||vbar||
    remains, as in the lecture). PSD projection (the lecture's make_PD) clamps it at zero."""
    k, mu_lambda, t, u = _contacts(v, mu_lambda, n)
    vbarnorm = np.abs(u)
    along_t = f_hess_term(vbarnorm, epsv) * vbarnorm + f1_div_vbarnorm(vbarnorm, epsv)
    if project_psd:
        along_t = np.maximum(along_t, 0.0)
    return k[:, None], (mu_lambda * along_t / hhat)[:, None, None] * (t[:, None] * t)      # t t^T
