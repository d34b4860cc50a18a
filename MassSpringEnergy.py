"""Mass-spring elasticity: P_e(x) = sum_e 1/2 k_e l_e^2 (||x_a - x_b||^2 / l_e^2 - 1)^2, `l2` the
squared rest lengths (val/grad/hess check their input, the *_kernel of the same name trusts it)."""
import numpy as np

import utils

ARGUMENTS = "x, l2 and k"       # what a result that overflowed came from (utils.finite_result)


def _check(x, e, l2, k):
    x = utils.check_points("x", x)
    e = utils.check_edges("e", e, len(x))
    return (x, e, utils.check_per_item("l2", l2, len(e), what="edge", must_be="> 0"),
            utils.check_per_item("k", k, len(e), what="edge"))


def val(x, e, l2, k):
    """P_e = sum_e 1/2 k l2 (||diff||^2 / l2 - 1)^2 (checked)."""
    return utils.finite_result("MassSpringEnergy.val", val_kernel(*_check(x, e, l2, k)), ARGUMENTS)


def grad(x, e, l2, k):
    """dP_e/dx_a = -dP_e/dx_b = 2 k (||diff||^2 / l2 - 1) diff (checked)."""
    g = grad_kernel(*_check(x, e, l2, k))
    return utils.finite_result("MassSpringEnergy.grad", g, ARGUMENTS)


def hess(x, e, l2, k, project_psd=True):
    """Per edge [[H, -H], [-H, H]] as an IJV triplet (checked); `project_psd=False` gives the true,
    possibly indefinite, Hessian."""
    nodes, blocks = hess_kernel(*_check(x, e, l2, k), project_psd=project_psd)
    blocks = utils.finite_result("MassSpringEnergy.hess", blocks, ARGUMENTS)
    return utils.blocks_to_ijv(nodes, blocks)


def _edges(x, e):
    """diff = x_a - x_b (E, 2) of every edge, and ||diff||^2 (E,)."""
    diff = x.take(e[:, 0], axis=0) - x.take(e[:, 1], axis=0)   # take: x[e[:, 0]], faster
    return diff, diff[:, 0] ** 2 + diff[:, 1] ** 2


def squared_lengths(x, e):
    """||x_a - x_b||^2 of every edge: a scene's rest lengths l2, measured as P_e measures them, so a
    spring at rest has strain 0.0 exactly."""
    return _edges(np.asarray(x, dtype=float), np.asarray(e))[1]


def val_kernel(x, e, l2, k):
    strain = _edges(x, e)[1] / l2 - 1.0
    return 0.5 * float((k * l2) @ (strain * strain))


def grad_kernel(x, e, l2, k):
    diff, sq = _edges(x, e)
    return utils.add_to_pairs(e, (2.0 * k * (sq / l2 - 1.0))[:, None] * diff, len(x))


def hess_kernel(x, e, l2, k, project_psd=True, out=None):
    """Per edge [[H, -H], [-H, H]], H = 2k/l2 (2 diff diff^T + (||diff||^2 - l2) I)
    = lam_perp I + (lam_par - lam_perp) diff diff^T / ||diff||^2; its PSD projection (make_PD)
    clamps lam_par = 2k/l2 (3 ||diff||^2 - l2) and lam_perp = 2k/l2 (||diff||^2 - l2) at zero.
    Written into `out` (E, 4, 4) where given: the solver's, kept across Newton iterations."""
    diff, sq = _edges(x, e)
    c = 2.0 * k / l2
    lam_perp = c * (sq - l2)
    lam_par = lam_perp + 2.0 * c * sq
    if project_psd:
        lam_par, lam_perp = np.maximum(lam_par, 0.0), np.maximum(lam_perp, 0.0)
    w = (lam_par - lam_perp) / np.maximum(sq, np.finfo(float).tiny)
    H = (w[:, None] * diff)[:, :, None] * diff[:, None, :]
    H[:, 0, 0] += lam_perp          # + lam_perp I, in place: faster than adding an (E, 2, 2) eye
    H[:, 1, 1] += lam_perp
    blocks = np.empty((len(e), 4, 4)) if out is None else out
    blocks[:, :2, :2] = blocks[:, 2:, 2:] = H
    blocks[:, :2, 2:] = blocks[:, 2:, :2] = np.negative(H, out=H)
    return e, blocks
