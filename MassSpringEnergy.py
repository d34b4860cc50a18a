"""Mass-spring elasticity: E_s(x) = sum_e 1/2 k_e l_e^2 (||x_a - x_b||^2 / l_e^2 - 1)^2.

`l2` holds the squared rest lengths l_e^2, as in the lecture's code. `val`, `grad`, `hess` check
their input, then call the `*_kernel` function of the same name, which holds the formula and trusts
its input (the time integrator calls the kernels on a scene it has validated once).
"""
import numpy as np

import utils

# Entry (2A + i, 2B + j) of a spring's 4x4 block is sign(A, B) H_ij: which of (H00, H01, H11) and
# which sign, for the 16 entries in row-major order.
_BLOCK_ENTRY = np.array([0, 1, 0, 1, 1, 2, 1, 2, 0, 1, 0, 1, 1, 2, 1, 2])
_BLOCK_SIGN = np.array([1.0, 1.0, -1.0, -1.0] * 2 + [-1.0, -1.0, 1.0, 1.0] * 2)[:, None]
_TINY = np.finfo(np.float64).tiny
_BLOCK_ENTRY.setflags(write=False)
_BLOCK_SIGN.setflags(write=False)

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
    """diff_e = x_a - x_b (E, 2) for every edge, its components (dx, dy) and ||diff_e||^2."""
    diff = x.take(e[:, 0], axis=0) - x.take(e[:, 1], axis=0)
    dx, dy = diff[:, 0], diff[:, 1]
    return diff, dx, dy, dx * dx + dy * dy


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
    """E_s = sum_e 1/2 k l2 (||diff||^2 / l2 - 1)^2 (see _val)."""
    return _val(_strain(_edge_vectors(x, e)[3], l2), l2, k)


def grad_kernel(x, e, l2, k):
    """dE/dx_a = -dE/dx_b = 2 k (||diff||^2 / l2 - 1) diff, summed over the edges of each node (see _forces)."""
    diff, _, _, sq = _edge_vectors(x, e)
    forces = _forces(diff, _strain(sq, l2), k)
    return utils.scatter_add_pairs(e, forces[:, 0], forces[:, 1], len(x))


def hess_kernel(x, e, l2, k, project_psd=True):
    """Per edge [[H, -H], [-H, H]], H = 2k/l2 (2 diff diff^T + (||diff||^2 - l2) I) (see _blocks).
    Returns (e, blocks), the blocks entry-major (4, 4, E) (see utils.blocks_to_ijv)."""
    return e, _blocks(*_edge_vectors(x, e)[1:], l2, k, project_psd)


def val_grad_hess_kernel(x, e, l2, k):
    """val_kernel, grad_kernel and the PSD-projected hess_kernel at once, from one set of edge
    vectors (the line search's first trial: Newton usually accepts it and then needs all three),
    spring by spring: the gradient comes as (e, f), f (E, 2) = dE/dx_a = -dE/dx_b of each spring
    (utils.BlockPattern.sum_spring_forces adds them up per node), the Hessian as (e, H), H (3, E)
    the entries (h00, h01, h11) of each spring's projected 2x2 H, whose 4x4 block is
    [[H, -H], [-H, H]] (utils.BlockPattern.sum_spring_blocks adds them)."""
    diff, dx, dy, sq = _edge_vectors(x, e)
    strain = _strain(sq, l2)
    return _val(strain, l2, k), (e, _forces(diff, strain, k)), (e, _spring_hessians(dx, dy, sq, l2, k, True))


def _strain(sq, l2):
    """||diff||^2 / l2 - 1, the strain measure of the lecture's spring energy."""
    return sq / l2 - 1.0


def _val(strain, l2, k):
    """E_s = sum_e 1/2 k l2 strain^2."""
    return 0.5 * float((k * l2).dot(strain * strain))


def _forces(diff, strain, k):
    """dE/dx_a = -dE/dx_b = 2 k strain diff of every spring, (E, 2) (axis by axis: numpy broadcasts a
    column over rows of two slowly)."""
    scale, forces = 2.0 * k * strain, np.empty(diff.shape)
    np.multiply(diff[:, 0], scale, out=forces[:, 0])
    np.multiply(diff[:, 1], scale, out=forces[:, 1])
    return forces


def _blocks(dx, dy, sq, l2, k, project_psd):
    """Per edge the 4x4 block [[H, -H], [-H, H]] with H = 2k/l2 (2 diff diff^T + (||diff||^2 - l2) I).

    H has the eigenvector diff with eigenvalue lam_par = 2k/l2 (3 ||diff||^2 - l2) and the one
    across it with lam_perp = 2k/l2 (||diff||^2 - l2), so with u = diff diff^T / ||diff||^2,
    H = lam_par u + lam_perp (I - u), and its PSD projection H+ clamps both at zero. The 4x4 block
    is [[1, -1], [-1, 1]] (x) H, whose eigenvalues are 2 eig(H) and 0, so its projection is
    [[1, -1], [-1, 1]] (x) H+. Entry-major, (4, 4, E).
    """
    return _edge_blocks(_spring_hessians(dx, dy, sq, l2, k, project_psd))


def _spring_hessians(dx, dy, sq, l2, k, project_psd):
    """The 2x2 H (PSD-projected if asked) of every spring as its entries (h00, h01, h11), (3, E)
    (see _blocks for the closed form)."""
    c = (2.0 * k) / l2
    lam_perp = c * (sq - l2)
    lam_par = (2.0 * c) * sq
    lam_par += lam_perp                     # (in place, here and below: fewer temporaries)
    if project_psd:
        np.maximum(lam_par, 0.0, out=lam_par)
        np.maximum(lam_perp, 0.0, out=lam_perp)
    w = np.subtract(lam_par, lam_perp, out=lam_par)
    w /= np.maximum(sq, _TINY)              # w = (lam_par - lam_perp) / ||diff||^2 (zero length: H = lam_perp I)
    H = np.empty((3, len(sq)))
    w_dx = w * dx
    np.multiply(w_dx, dx, out=H[0])
    H[0] += lam_perp                        # h00 = lam_perp + w dx^2
    np.multiply(w_dx, dy, out=H[1])         # h01 = w dx dy
    np.multiply(w, dy, out=H[2])
    H[2] *= dy
    H[2] += lam_perp                        # h11 = lam_perp + w dy^2
    return H


def _edge_blocks(H):
    """[[1, -1], [-1, 1]] (x) [[h00, h01], [h01, h11]] for every edge, H = (h00, h01, h11) (3, E);
    entry-major (4, 4, E)."""
    return (H.take(_BLOCK_ENTRY, axis=0) * _BLOCK_SIGN).reshape(4, 4, -1)
