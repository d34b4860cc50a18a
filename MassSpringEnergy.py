"""Mass-spring elasticity: E_s(x) = sum_e 1/2 k_e l_e^2 (||x_a - x_b||^2 / l_e^2 - 1)^2.

`l2` holds the squared rest lengths l_e^2, as in the lecture's code. `val`, `grad`, `hess` check
their input, then call the `*_kernel` function of the same name, which holds the formula and trusts
its input (the time integrator calls the kernels on a scene it has validated once).
"""
import numpy as np

import utils

# [[1, -1], [-1, 1]] laid out to multiply a spring's 2x2 block H into its 4x4 block (see hess_kernel)
_EDGE_SIGNS = np.array([[1.0, -1.0], [-1.0, 1.0]])[None, :, None, :, None]
_EDGE_SIGNS.setflags(write=False)


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
    """E_s = sum_e 1/2 k l2 (||diff||^2 / l2 - 1)^2 (checked; see val_kernel)."""
    return val_kernel(*_check(x, e, l2, k))


def grad(x, e, l2, k):
    """dE/dx_a = -dE/dx_b = 2 k (||diff||^2 / l2 - 1) diff (checked; see grad_kernel)."""
    return grad_kernel(*_check(x, e, l2, k))


def hess(x, e, l2, k, project_psd=True):
    """Per edge [[H, -H], [-H, H]], H = 2k/l2 (2 diff diff^T + (||diff||^2 - l2) I), as an IJV
    triplet (checked; see hess_kernel). `project_psd=False` gives the true, possibly indefinite one."""
    return utils.blocks_to_ijv(*hess_kernel(*_check(x, e, l2, k), project_psd=project_psd))


def val_kernel(x, e, l2, k):
    """E_s = sum_e 1/2 k l2 (||diff||^2 / l2 - 1)^2."""
    _, sq = _edge_vectors(x, e)
    return float(np.sum(0.5 * k * l2 * (sq / l2 - 1.0) ** 2))


def grad_kernel(x, e, l2, k):
    """dE/dx_a = -dE/dx_b = 2 k (||diff||^2 / l2 - 1) diff, summed over the edges of each node."""
    diff, sq = _edge_vectors(x, e)
    g_diff = (2.0 * k * (sq / l2 - 1.0))[:, None] * diff
    return utils.scatter_add_pairs(e, g_diff, len(x))


def hess_kernel(x, e, l2, k, project_psd=True):
    """Per edge the 4x4 block [[H, -H], [-H, H]] with H = 2k/l2 (2 diff diff^T + (||diff||^2 - l2) I).

    The 4x4 block is [[1, -1], [-1, 1]] (x) H, whose eigenvalues are 2 eig(H) and 0, so its PSD
    projection is [[1, -1], [-1, 1]] (x) H+ with H+ the closed-form 2x2 projection of H.
    Returns (e, blocks): the element node lists and their (E, 4, 4) blocks.
    """
    diff, sq = _edge_vectors(x, e)
    H = (2.0 * k / l2)[:, None, None] * (
        2.0 * diff[:, :, None] * diff[:, None, :] + (sq - l2)[:, None, None] * np.eye(2))
    if project_psd:
        H = utils.project_psd_2x2(H)
    return e, (_EDGE_SIGNS * H[:, None, :, None, :]).reshape(len(e), 4, 4)
