"""The Incremental Potential's inertia term E_I(x) = 1/2 ||x - x_tilde||_M^2, lumped masses
(val/grad/hess check their input, the *_kernel of the same name trusts it)."""
import numpy as np

import utils

ARGUMENTS = "x, x_tilde and m"      # what a result that overflowed came from (utils.finite_result)


def _check(x, x_tilde, m):
    x = utils.check_points("x", x)
    x_tilde = utils.check_points("x_tilde", x_tilde)
    if x_tilde.shape != x.shape:
        raise ValueError(f"x_tilde must have the shape of x {x.shape}, got {x_tilde.shape}")
    return x, x_tilde, utils.check_per_item("m", m, len(x), must_be="> 0")


def val(x, x_tilde, m):
    """E_I = 1/2 sum_i m_i ||x_i - x_tilde_i||^2 (checked)."""
    return utils.finite_result("InertiaEnergy.val", val_kernel(*_check(x, x_tilde, m)), ARGUMENTS)


def grad(x, x_tilde, m):
    """grad E_I = M (x - x_tilde) (checked)."""
    return utils.finite_result("InertiaEnergy.grad", grad_kernel(*_check(x, x_tilde, m)), ARGUMENTS)


def hess(x, x_tilde, m):
    """hess E_I = M as an IJV triplet (checked; finite, as m is)."""
    return utils.blocks_to_ijv(*hess_kernel(*_check(x, x_tilde, m)))


def val_kernel(x, x_tilde, m):
    diff = x - x_tilde
    return 0.5 * float(m @ np.einsum("ij,ij->i", diff, diff))


def grad_kernel(x, x_tilde, m):
    return m[:, None] * (x - x_tilde)


def hess_kernel(x, x_tilde, m):
    """The 2x2 block m_i I at every node, constant in x."""
    return np.arange(len(m))[:, None], m[:, None, None] * np.eye(2)
