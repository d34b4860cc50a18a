"""Semi-implicit dry friction against a half-space with a mollified static-dynamic transition.

With lagged normal force magnitudes mu*lambda^n and tangent operator T^n = I - n n^T (constant
for a half-space), and the tangential velocity vbar_k = (T^n)^T v_k:
    P_f(x) = sum_k mu lambda_k^n f0(||vbar_k|| hhat)                                  (Eq. 9.2.1)
where v = (x - x^n) / hhat, so dv/dx = I / hhat. val/grad/hess below take v and return
P_f and its derivatives with respect to x. Only nodes with mu_lambda > 0 (in contact) enter.

In 2-D the tangent line has one unit direction t = (n_y, -n_x), so T = I - n n^T = t t^T and
vbar_k = u_k t with u_k = t . v_k, the signed tangential speed: ||vbar_k|| = |u_k|. The kernels
compute in that form, which needs no 2x2 matrix per node (each formula says how it follows).

`val`, `grad`, `hess` check their input, then call the `*_kernel` function of the same name, which
holds the formula and trusts its input (the time integrator calls the kernels on a scene it has
validated once).
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
    slow = y < epsv
    return np.where(slow, (2.0 - y / epsv) / epsv, 1.0 / np.where(slow, 1.0, y))   # 1/y only where y >= eps_v


def f_hess_term(y, epsv):
    """Eq. 9.2.6, (f1'(y) y - f1(y)) / y^2: -1/eps_v^2 for y < eps_v, else -1/y^2."""
    y = np.asarray(y, dtype=np.float64)
    safe_y = np.where(y < epsv, 1.0, y)
    inv_epsv = 1.0 / np.float64(epsv)      # numpy scalars overflow to inf (caught), never raise
    return np.where(y < epsv, -inv_epsv * inv_epsv, -(1.0 / safe_y) ** 2)


def f1_prime(y, epsv):
    """f1'(y) = f_hess_term(y) y + f1(y)/y, the bracket of Eq. 9.2.4 along the tangent in 2-D:
    2 (1 - y/eps_v)/eps_v for y < eps_v, else 0. Written so, it never forms 1/eps_v^2, which
    overflows for tiny eps_v (and a PSD clamp would then turn -inf into a silent 0)."""
    y = np.asarray(y, dtype=np.float64)
    return np.where(y < epsv, 2.0 * (1.0 - y / epsv) / epsv, 0.0)


def mollifier(y, epsv, hhat):
    """f0(y hhat), f1(y)/y and f1'(y) at once, for the kernels that need all three: the formulas of
    f0 (Eq. 9.2.2), f1_over_y (Eq. 9.2.5) and f1_prime, branch by branch (y < eps_v or not; for
    y = ||vbar||, f0's y hhat < eps_v hhat is the same branch). A branch no y is on is not computed:
    all contacts sliding or all sticking, the usual cases, cost one branch; the numbers are the same."""
    slow = y < epsv
    if not slow.any():
        return _sliding_branch(y, hhat)
    static = _static_branch(y / epsv, epsv, hhat)
    if slow.all():
        return static
    sliding = _sliding_branch(np.where(slow, 1.0, y), hhat)     # 1/y only where y >= eps_v > 0
    return tuple(np.where(slow, a, b) for a, b in zip(static, sliding))


def _static_branch(r, epsv, hhat):
    """f0(y hhat), f1(y)/y, f1'(y) for y < eps_v, from r = y/eps_v: eps_v hhat (-r^3/3 + r^2 + 1/3),
    (2 - r)/eps_v, 2 (1 - r)/eps_v."""
    return (epsv * hhat) * (-r ** 3 / 3.0 + r * r + 1.0 / 3.0), (2.0 - r) / epsv, 2.0 * (1.0 - r) / epsv


def _sliding_branch(y, hhat):
    """f0(y hhat), f1(y)/y, f1'(y) for y >= eps_v: y hhat, 1/y, 0."""
    return y * hhat, 1.0 / y, np.zeros(len(y))


def tangent(n):
    """t = (n_y, -n_x), the unit tangent of the half-space with unit normal n: T = I - n n^T = t t^T."""
    return np.array([n[1], -n[0]])


def _check(v, mu_lambda, hhat, n, epsv):
    v = utils.check_points("v", v)
    mu_lambda = utils.check_per_item("mu_lambda", mu_lambda, len(v))
    if (mu_lambda < 0).any():
        i = int(np.argmax(mu_lambda < 0))
        raise ValueError(f"mu_lambda must be >= 0, got {mu_lambda[i]} at node {i}")
    hhat = utils.check_positive("hhat", hhat)
    epsv = utils.check_positive("epsv", epsv)
    n = utils.check_unit_normal("n", n)
    return v, mu_lambda, hhat, n, epsv


def _contacts(v, mu_lambda, n):
    """Indices of the nodes in contact, their mu*lambda, the tangent t, and vbar = T^T v = u t given
    by u = t . v, with ||vbar|| = |u|."""
    idx = (mu_lambda > 0.0).nonzero()[0]
    if len(idx) < len(mu_lambda):          # (the integrator passes the nodes in contact only)
        v, mu_lambda = v.take(idx, axis=0), mu_lambda.take(idx)
    t = tangent(n)
    u = v.dot(t)
    return idx, mu_lambda, t, u, np.abs(u)


def val(v, mu_lambda, hhat, n, epsv=EPSV):
    """P_f = sum_k mu lambda_k f0(||vbar_k|| hhat) (Eq. 9.2.1) (checked; see val_kernel)."""
    return utils.finite_result("FrictionEnergy.val", val_kernel(*_check(v, mu_lambda, hhat, n, epsv)))


def grad(v, mu_lambda, hhat, n, epsv=EPSV):
    """grad_k P_f = mu lambda_k T (f1(||vbar_k||)/||vbar_k||) vbar_k (Eq. 9.2.3) (checked; see grad_kernel)."""
    return utils.finite_result("FrictionEnergy.grad", grad_kernel(*_check(v, mu_lambda, hhat, n, epsv)))


def hess(v, mu_lambda, hhat, n, epsv=EPSV, project_psd=True):
    """hess_k P_f (Eq. 9.2.4) as an IJV triplet (checked; see hess_kernel)."""
    nodes, blocks = hess_kernel(*_check(v, mu_lambda, hhat, n, epsv), project_psd=project_psd)
    return utils.blocks_to_ijv(nodes, utils.finite_result("FrictionEnergy.hess", blocks))


def val_kernel(v, mu_lambda, hhat, n, epsv):
    """P_f = sum_k mu lambda_k f0(||vbar_k|| hhat) (Eq. 9.2.1) (see _val)."""
    return _val(*_contacts(v, mu_lambda, n), hhat, epsv)


def grad_kernel(v, mu_lambda, hhat, n, epsv):
    """grad_k P_f = mu lambda_k T (f1(||vbar_k||)/||vbar_k||) vbar_k (Eq. 9.2.3) (see _grad)."""
    contacts = _contacts(v, mu_lambda, n)
    return _grad(v.shape, *contacts, f1_over_y(contacts[4], epsv))


def hess_kernel(v, mu_lambda, hhat, n, epsv, project_psd=True):
    """hess_k P_f (Eq. 9.2.4) (see _blocks). Returns (nodes, blocks): the contact nodes as (k, 1)
    element lists and their blocks, entry-major (2, 2, k) (see utils.blocks_to_ijv)."""
    contacts = _contacts(v, mu_lambda, n)
    return contacts[0][:, None], _blocks(*contacts, hhat, epsv, project_psd)


def val_grad_hess_kernel(v, mu_lambda, hhat, n, epsv):
    """val_kernel, grad_kernel and the PSD-projected hess_kernel at once, from one set of contacts
    and one pass of the mollifier (see mollifier). The Hessian comes as (nodes, H), H (3, k) the
    entries (h00, h01, h11) of each node's 2x2 block (what utils.BlockPattern.add_node_blocks adds)."""
    idx, ml, t, u, y = _contacts(v, mu_lambda, n)
    f0_of_y, f1y, f1p = mollifier(y, epsv, hhat)
    return (float(ml.dot(f0_of_y)), _grad(v.shape, idx, ml, t, u, y, f1y),
            (idx[:, None], utils.outer_entries(t, _tangent_coefficient(ml, f1p, hhat, True))))


def _val(idx, ml, t, u, y, hhat, epsv):
    """P_f = sum_k mu lambda_k f0(y_k hhat) (Eq. 9.2.1), y_k = ||vbar_k||, with f0 from mollifier: the
    same bits as val_grad_hess_kernel's P_f (the line search compares the two)."""
    return float(ml.dot(mollifier(y, epsv, hhat)[0]))


def _grad(shape, idx, ml, t, u, y, f1y):
    """grad_k P_f = mu lambda_k T (f1(y)/y) vbar_k (Eq. 9.2.3), y = ||vbar_k||, f1y = f1(y)/y.
    T vbar = vbar = u t, so it is mu lambda_k f1y u_k t: zero at vbar = 0 and out of contact."""
    forces = (ml * f1y * u)[:, None] * t
    if len(idx) == shape[0]:                # every node in contact (as the integrator passes them)
        return forces
    g = np.zeros(shape)
    g[idx] = forces
    return g


def _blocks(idx, ml, t, u, y, hhat, epsv, project_psd):
    """hess_k P_f = mu lambda_k T [ (f1'y - f1)/y^3 vbar vbar^T + f1/y I ] T^T / hhat  (Eq. 9.2.4),
    y = ||vbar_k||. With T = t t^T and vbar = u t, the bracket between T and T^T is
    (f_hess_term(y) y + f1y) t t^T = f1'(y) t t^T (at y = 0 only f1/y remains, as in the lecture).
    The bracket's eigenvalues are f1'(y) >= 0 along t and f1/y > 0 along n, so it is PSD for the
    lecture's f1; `project_psd` clamps the round-off (as the lecture's make_PD does).
    Entry-major, (2, 2, k)."""
    return _tangent_blocks(ml, t, f1_prime(y, epsv), hhat, project_psd)


def _tangent_blocks(ml, t, along_t, hhat, project_psd):
    """mu lambda_k / hhat f1'(y_k) t t^T (see _blocks), along_t = f1'(y_k), entry-major (2, 2, k)."""
    return utils.outer_blocks(t, _tangent_coefficient(ml, along_t, hhat, project_psd))


def _tangent_coefficient(ml, along_t, hhat, project_psd):
    """mu lambda_k / hhat f1'(y_k), the factor of t t^T in hess_k P_f (clamped at 0 if project_psd)."""
    if project_psd:
        along_t = np.maximum(along_t, 0.0)
    return (ml / hhat) * along_t
