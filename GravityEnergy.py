"""Gravitational potential: E_g(x) = -sum_i m_i g . x_i."""
import numpy as np

import utils

GRAVITY = (0.0, -9.81)  # m/s^2, the lecture's g


def _check(x, m, g):
    x = utils.check_points("x", x)
    m = utils.check_per_item("m", m, len(x))
    g = utils.check_vector("g", g)
    return x, m, g


def val(x, m, g=GRAVITY):
    """E_g = -sum_i m_i g . x_i."""
    x, m, g = _check(x, m, g)
    return -float(np.sum(m * (x @ g)))


def grad(x, m, g=GRAVITY):
    """grad E_g = -m_i g at every node (constant in x)."""
    x, m, g = _check(x, m, g)
    return -m[:, None] * g[None, :]


def hess(x, m, g=GRAVITY):
    """E_g is linear in x: its Hessian is zero, returned as an empty IJV triplet."""
    _check(x, m, g)
    return utils.empty_ijv()
