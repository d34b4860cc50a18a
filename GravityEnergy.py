"""Gravitational potential: E_g(x) = -sum_i m_i g . x_i.

`val` and `grad` check their input, then call the `*_kernel` function of the same name, which holds
the formula and trusts its input (the time integrator calls the kernels on a scene it has validated
once). The Hessian is zero, so the integrator never asks for it.
"""
import numpy as np

import utils

GRAVITY = (0.0, -9.81)  # m/s^2, the lecture's g


def _check(x, m, g):
    x = utils.check_points("x", x)
    m = utils.check_per_item("m", m, len(x))
    g = utils.check_vector("g", g)
    return x, m, g


def val(x, m, g=GRAVITY):
    """E_g = -sum_i m_i g . x_i (checked; see val_kernel)."""
    return val_kernel(*_check(x, m, g))


def grad(x, m, g=GRAVITY):
    """grad E_g = -m_i g at every node (checked; see grad_kernel)."""
    return grad_kernel(*_check(x, m, g))


def hess(x, m, g=GRAVITY):
    """E_g is linear in x: its Hessian is zero, returned as an empty IJV triplet."""
    _check(x, m, g)
    return utils.empty_ijv()


def val_kernel(x, m, g):
    """E_g = -sum_i m_i g . x_i."""
    return -float(m.dot(x.dot(g)))


def grad_kernel(x, m, g):
    """grad E_g = -m_i g at every node (constant in x)."""
    return -m[:, None] * g[None, :]
