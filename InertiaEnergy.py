"""Inertia term of the Incremental Potential: E_I(x) = 1/2 ||x - x_tilde||_M^2 (lumped masses).

`val`, `grad`, `hess` check their input and call the `*_kernel` of the same name, which holds the
formula and trusts its input (the time integrator calls the kernels on a scene validated once).
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
    """hess E_I = M as an IJV triplet (checked; see hess_kernel)."""
    return utils.blocks_to_ijv(*hess_kernel(*_check(x, x_tilde, m)))


def val_kernel(x, x_tilde, m):
    """E_I = 1/2 sum_i m_i ||x_i - x_tilde_i||^2."""
    diff = x - x_tilde
    return 0.5 * float(m @ np.einsum("ij,ij->i", diff, diff))


def grad_kernel(x, x_tilde, m):
    """grad E_I = M (x - x_tilde)."""
    return m[:, None] * (x - x_tilde)


def hess_kernel(x, x_tilde, m):
    """hess E_I = M: the 2x2 block m_i I at every node, constant in x."""
    return np.arange(len(m))[:, None], m[:, None, None] * np.eye(2)
