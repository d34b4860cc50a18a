"""A grasp's fingers (docs/grasp.md): P(x) = sum_f [P_b(x_block; n_f, o = x_f) - N_f n_f . x_f], x_f
the last F rows of x, P_b BarrierEnergy's; val/grad/hess check, then call the *_kernel."""
import numpy as np

import BarrierEnergy
import utils

ARGUMENTS = "squeeze, contact_area, dhat, kappa and the distances to the fingers"


def _check(x, n, squeeze, contact_area, dhat, kappa):
    x = utils.check_points("x", x)
    n = np.array([utils.check_unit_normal(f"n[{f}]", row) for f, row in enumerate(n)])
    if not 0 < len(n) < len(x):
        raise utils.ParameterError("n", f"n must hold one normal per finger, 1 to {len(x) - 1} "
                                        f"of them, got {len(n)}")
    return (x, n, utils.check_per_item("squeeze", squeeze, len(n), "finger", ">= 0"),
            utils.check_per_item("contact_area", contact_area, len(x)),
            utils.check_positive("dhat", dhat), utils.check_positive("kappa", kappa))


def val(x, n, squeeze, contact_area, dhat=BarrierEnergy.DHAT, kappa=BarrierEnergy.KAPPA):
    """P (checked; see val_kernel)."""
    checked = _check(x, n, squeeze, contact_area, dhat, kappa)
    return utils.finite_result("FingerEnergy.val", val_kernel(*checked), ARGUMENTS)


def grad(x, n, squeeze, contact_area, dhat=BarrierEnergy.DHAT, kappa=BarrierEnergy.KAPPA):
    """grad P, (N, 2) (checked; see grad_kernel)."""
    checked = _check(x, n, squeeze, contact_area, dhat, kappa)
    return utils.finite_result("FingerEnergy.grad", grad_kernel(*checked), ARGUMENTS)


def hess(x, n, squeeze, contact_area, dhat=BarrierEnergy.DHAT, kappa=BarrierEnergy.KAPPA):
    """hess P as an IJV triplet (checked; see hess_kernel)."""
    nodes, blocks = hess_kernel(*_check(x, n, squeeze, contact_area, dhat, kappa))
    return utils.blocks_to_ijv(nodes, utils.finite_result("FingerEnergy.hess", blocks, ARGUMENTS))


def split(x, n):
    """(the block's rows, the fingers' x_f (F, 2), the last len(n) rows)."""
    return x[:len(x) - len(n)], x[len(x) - len(n):]


def each(kernel, x, n, *args):
    """[kernel(x_block, n_f, x_f, *args) for each finger f]: BarrierEnergy's, with o = x_f."""
    block, fingers = split(x, n)
    return [kernel(block, n_f, x_f, *args) for n_f, x_f in zip(n, fingers)]


def val_kernel(x, n, squeeze, contact_area, dhat, kappa):
    """P = sum_f [P_b(x_block; n_f, x_f) - N_f n_f . x_f]."""
    barrier = sum(each(BarrierEnergy.val_kernel, x, n, contact_area, dhat, kappa))
    return barrier - float(squeeze @ np.einsum("fj,fj->f", n, split(x, n)[1]))


def grad_kernel(x, n, squeeze, contact_area, dhat, kappa):
    """grad_i P = sum_f grad_i P_b(n_f, x_f); grad_f P = -sum_i grad_i P_b(n_f, x_f) - N_f n_f."""
    g_b = each(BarrierEnergy.grad_kernel, x, n, contact_area, dhat, kappa)     # (N_block, 2) each
    g_f = [-g.sum(axis=0) - N_f * n_f for g, N_f, n_f in zip(g_b, squeeze, n)]
    return np.vstack([sum(g_b), g_f])


def hess_kernel(x, n, squeeze, contact_area, dhat, kappa):
    """Blocks [[A, -A], [-A, A]] on the pairs (i, f), A = hess_i P_b(n_f, x_f) (PSD as A is)."""
    parts = each(BarrierEnergy.hess_kernel, x, n, contact_area, dhat, kappa)
    pairs = [np.hstack([i, np.full_like(i, len(x) - len(n) + f)]) for f, (i, _) in enumerate(parts)]
    return np.concatenate(pairs), np.concatenate([np.block([[A, -A], [-A, A]]) for _, A in parts])
