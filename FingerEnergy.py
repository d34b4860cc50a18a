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


def val_kernel(x, n, squeeze, contact_area, dhat, kappa):
    """P = sum_f [P_b(x_block; n_f, x_f) - N_f n_f . x_f]."""
    block, fingers = split(x, n)
    barrier = sum(BarrierEnergy.val_kernel(block, n_f, x_f, contact_area, dhat, kappa)
                  for n_f, x_f in zip(n, fingers))
    return barrier - float(squeeze @ np.einsum("fj,fj->f", n, fingers))


def grad_kernel(x, n, squeeze, contact_area, dhat, kappa):
    """grad_i P = sum_f grad_i P_b(n_f, x_f); grad_f P = -sum_i grad_i P_b(n_f, x_f) - N_f n_f."""
    block, fingers = split(x, n)
    g = np.zeros(x.shape)
    for f, (n_f, x_f) in enumerate(zip(n, fingers)):
        g_f = BarrierEnergy.grad_kernel(block, n_f, x_f, contact_area, dhat, kappa)
        g[:len(block)] += g_f
        g[len(block) + f] = -g_f.sum(axis=0) - squeeze[f] * n_f
    return g


def hess_kernel(x, n, squeeze, contact_area, dhat, kappa):
    """Blocks [[A, -A], [-A, A]] on the pairs (i, f), A = hess_i P_b(n_f, x_f) (PSD as A is)."""
    block, fingers = split(x, n)
    nodes, blocks = [np.zeros((0, 2), dtype=np.int64)], [np.zeros((0, 4, 4))]
    for f, (n_f, x_f) in enumerate(zip(n, fingers)):
        i, A = BarrierEnergy.hess_kernel(block, n_f, x_f, contact_area, dhat, kappa)
        nodes.append(np.hstack([i, np.full_like(i, len(block) + f)]))
        blocks.append(np.block([[A, -A], [-A, A]]))
    return np.concatenate(nodes), np.concatenate(blocks)
