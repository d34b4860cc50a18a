"""Mass-spring elasticity: E_s(x) = sum_e 1/2 k_e l_e^2 (||x_a - x_b||^2 / l_e^2 - 1)^2.

`l2` holds the squared rest lengths l_e^2, as in the lecture's code.
"""
import numpy as np

import utils


def _check(x, e, l2, k):
    x = utils.check_points("x", x)
    e = utils.check_edges("e", e, len(x))
    l2 = utils.check_per_item("l2", l2, len(e), what="edge")
    k = utils.check_per_item("k", k, len(e), what="edge")
    if (l2 <= 0).any():
        i = int(np.argmax(l2 <= 0))
        raise ValueError(f"l2 (squared rest length) must be > 0, got {l2[i]} at edge {i}")
    return x, e, l2, k


def _edge_vectors(x, e):
    """diff_e = x_a - x_b and its squared length for every edge."""
    diff = x[e[:, 0]] - x[e[:, 1]]
    return diff, np.einsum("ij,ij->i", diff, diff)


def val(x, e, l2, k):
    """E_s = sum_e 1/2 k l2 (||diff||^2 / l2 - 1)^2."""
    x, e, l2, k = _check(x, e, l2, k)
    _, sq = _edge_vectors(x, e)
    return float(np.sum(0.5 * k * l2 * (sq / l2 - 1.0) ** 2))


def grad(x, e, l2, k):
    """dE/dx_a = -dE/dx_b = 2 k (||diff||^2 / l2 - 1) diff, summed over the edges of each node."""
    x, e, l2, k = _check(x, e, l2, k)
    diff, sq = _edge_vectors(x, e)
    g_diff = (2.0 * k * (sq / l2 - 1.0))[:, None] * diff
    return utils.scatter_add(e[:, 0], g_diff, len(x)) - utils.scatter_add(e[:, 1], g_diff, len(x))


def hess(x, e, l2, k, project_psd=True):
    """Per edge [[H, -H], [-H, H]] with H = 2k/l2 (2 diff diff^T + (||diff||^2 - l2) I).

    The 4x4 block is [[1, -1], [-1, 1]] (x) H, whose eigenvalues are 2 eig(H) and 0, so its PSD
    projection is [[1, -1], [-1, 1]] (x) H+ with H+ the closed-form 2x2 projection of H.
    `project_psd=False` returns the true (possibly indefinite) Hessian, for checking.
    """
    x, e, l2, k = _check(x, e, l2, k)
    diff, sq = _edge_vectors(x, e)
    H = (2.0 * k / l2)[:, None, None] * (
        2.0 * diff[:, :, None] * diff[:, None, :] + (sq - l2)[:, None, None] * np.eye(2))
    if project_psd:
        H = utils.project_psd_2x2(H)
    blocks = np.kron(np.array([[1.0, -1.0], [-1.0, 1.0]]), np.ones((2, 2)))[None] * np.tile(H, (1, 2, 2))
    return utils.blocks_to_ijv(e, blocks)
