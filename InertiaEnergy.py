"""Inertia term of the Incremental Potential: E_I(x) = 1/2 ||x - x_tilde||_M^2 (lumped masses).

`val`, `grad`, `hess` check their input, then call the `*_kernel` function of the same name, which
holds the formula and trusts its input (the time integrator calls the kernels on a scene it has
validated once).
"""
import numpy as np

import utils


def _check(x, x_tilde, m):
    x = utils.check_points("x", x)
    x_tilde = utils.check_points("x_tilde", x_tilde)
    if x_tilde.shape != x.shape:
        raise ValueError(f"x_tilde must have the shape of x {x.shape}, got {x_tilde.shape}")
    m = utils.check_per_item("m", m, len(x))
    if (m <= 0).any():
        i = int(np.argmax(m <= 0))
        raise ValueError(f"m must be > 0 at every node, got {m[i]} at node {i}")
    return x, x_tilde, m


def val(x, x_tilde, m):
    """E_I = 1/2 sum_i m_i ||x_i - x_tilde_i||^2 (checked; see val_kernel)."""
    return val_kernel(*_check(x, x_tilde, m))


def grad(x, x_tilde, m):
    """grad E_I = M (x - x_tilde) (checked; see grad_kernel)."""
    return grad_kernel(*_check(x, x_tilde, m))


def hess(x, x_tilde, m):
    """hess E_I = M: one diagonal entry m_i per DOF (2i, 2i + 1), as an IJV triplet (checked)."""
    x, x_tilde, m = _check(x, x_tilde, m)
    dofs = np.arange(2 * len(x), dtype=np.int64)
    return dofs, dofs.copy(), hess_kernel(x, x_tilde, m)


def val_kernel(x, x_tilde, m):
    """E_I = 1/2 sum_i m_i ||x_i - x_tilde_i||^2 = 1/2 (x - x_tilde) . M (x - x_tilde)."""
    return val_grad_kernel(x, x_tilde, m)[0]


def grad_kernel(x, x_tilde, m):
    """grad E_I = M (x - x_tilde)."""
    return m[:, None] * (x - x_tilde)


def val_grad_kernel(x, x_tilde, m):
    """val_kernel and grad_kernel at once, from one x - x_tilde: E_I = 1/2 diff . (M diff), M diff.
    m may also be given per DOF, (N, 2) (m_i twice per row), which multiplies faster (the integrator's)."""
    diff = x - x_tilde
    M_diff = (m[:, None] if m.ndim == 1 else m) * diff
    return 0.5 * float(np.vdot(diff, M_diff)), M_diff


def hess_kernel(x, x_tilde, m):
    """The diagonal of M, DOF by DOF: (m_0, m_0, m_1, m_1, ...). Constant in x."""
    return np.repeat(m, 2)
