"""Gravitational potential: P_g(x) = -sum_i m_i g . x_i (val/grad/hess check their input, the
*_kernel of the same name trusts it)."""
import numpy as np

import utils

GRAVITY = (0.0, -9.81)  # m/s^2, the lecture's g
ARGUMENTS = "x, m and g"        # what a result that overflowed came from (utils.finite_result)


def _check(x, m, g):
    x = utils.check_points("x", x)
    return x, utils.check_per_item("m", m, len(x)), utils.check_vector("g", g)


def val(x, m, g=GRAVITY):
    """P_g = -sum_i m_i g . x_i (checked)."""
    return utils.finite_result("GravityEnergy.val", val_kernel(*_check(x, m, g)), ARGUMENTS)


def grad(x, m, g=GRAVITY):
    """grad P_g = -m_i g at every node (checked)."""
    return utils.finite_result("GravityEnergy.grad", grad_kernel(*_check(x, m, g)), ARGUMENTS)


def hess(x, m, g=GRAVITY):
    """P_g is linear in x: its Hessian is zero, an empty IJV triplet (checked)."""
    return utils.blocks_to_ijv(*hess_kernel(*_check(x, m, g)))


def val_kernel(x, m, g):
    return -float(m @ (x @ g))


def grad_kernel(x, m, g):
    return -m[:, None] * g


def hess_kernel(x, m, g):
    """Zero: no element blocks."""
    return np.zeros((0, 1), dtype=np.int64), np.zeros((0, 2, 2))
