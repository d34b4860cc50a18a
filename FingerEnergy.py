"""The fingers of a grasp: half-spaces through nodes of x, each pressed toward the block by a force.

Finger f is the half-space through the node x_f with unit normal n_f (pointing to the block). As the
tutorial's 5_mov_dirichlet makes its ceiling an extra node with the plane through it, the fingers
are the last F rows of x, and a block node i is at distance d_fi = n_f . (x_i - x_f): grad d_fi is
n_f at x_i and -n_f at x_f. A finger is pressed by a set force N_f along n_f, a potential like
gravity's. With P_b the barrier of BarrierEnergy (block nodes only, o = x_f):

    P(x) = sum_f [ P_b(x_block; n_f, x_f) - N_f n_f . x_f ]

so the barrier's derivative in x_f is minus the sum of its derivatives in the block's nodes, and its
Hessian couples x_i and x_f by the 4x4 block [[A, -A], [-A, A]], A = w_i dhat b''(d_fi) n_f n_f^T
(PSD as A is). At rest a finger's barrier force on the block is N_f. The sums run over the fingers
(a few surfaces, never over contacts); each surface's is BarrierEnergy's kernel. val/grad/hess check
their input and call the *_kernel of the same name.
"""
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
    """P = sum_f P_b(x_block; n_f, x_f) - N_f n_f . x_f (checked; see val_kernel)."""
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
    """(the block's rows, the fingers' rows x_f (F, 2)): the fingers are the last len(n) rows."""
    return x[:len(x) - len(n)], x[len(x) - len(n):]


def distances(x, n):
    """d_fi = n_f . (x_i - x_f), (F, N_block)."""
    block, fingers = split(x, n)
    return n @ block.T - np.einsum("fj,fj->f", n, fingers)[:, None]


def check_above(x, n):
    """NotAboveHalfSpace (a ValueError) if a block node is on or behind a finger (d <= 0)."""
    block, fingers = split(x, n)
    for n_f, x_f in zip(n, fingers):
        BarrierEnergy.check_above(block, n_f, x_f)


def val_kernel(x, n, squeeze, contact_area, dhat, kappa):
    """P = sum_f [P_b(x_block; n_f, x_f) - N_f n_f . x_f]."""
    block, fingers = split(x, n)
    w = contact_area[:len(block)]
    barrier = sum(BarrierEnergy.val_kernel(block, n_f, x_f, w, dhat, kappa)
                  for n_f, x_f in zip(n, fingers))
    return barrier - float(squeeze @ np.einsum("fj,fj->f", n, fingers))


def grad_kernel(x, n, squeeze, contact_area, dhat, kappa):
    """grad_i P = sum_f w_i dhat b'(d_fi) n_f at a block node; grad_f P = -(sum_i of finger f's
    terms) - N_f n_f at a finger's node."""
    block, fingers = split(x, n)
    w = contact_area[:len(block)]
    g = np.zeros(x.shape)
    for f, (n_f, x_f) in enumerate(zip(n, fingers)):
        g_f = BarrierEnergy.grad_kernel(block, n_f, x_f, w, dhat, kappa)
        g[:len(block)] += g_f
        g[len(block) + f] = -g_f.sum(axis=0) - squeeze[f] * n_f
    return g


def hess_kernel(x, n, squeeze, contact_area, dhat, kappa):
    """The blocks [[A, -A], [-A, A]] on the pairs (i, f) with d_fi < dhat, A = w_i dhat b''(d_fi)
    n_f n_f^T (the squeeze is linear: no Hessian)."""
    block, fingers = split(x, n)
    w = contact_area[:len(block)]
    nodes, blocks = [np.zeros((0, 2), dtype=np.int64)], [np.zeros((0, 4, 4))]
    for f, (n_f, x_f) in enumerate(zip(n, fingers)):
        i, A = BarrierEnergy.hess_kernel(block, n_f, x_f, w, dhat, kappa)
        nodes.append(np.hstack([i, np.full_like(i, len(block) + f)]))
        blocks.append(np.block([[A, -A], [-A, A]]))
    return np.concatenate(nodes), np.concatenate(blocks)


def compute_mu_lambda_kernel(x, n, contact_area, mu, dhat, kappa):
    """mu * lambda_fi (F, N): finger f's normal force on node i times mu (BarrierEnergy's
    compute_mu_lambda_kernel with o = x_f), zero on the fingers' own rows."""
    block, fingers = split(x, n)
    w = contact_area[:len(block)]
    mu_lambda = np.zeros((len(n), len(x)))
    for f, (n_f, x_f) in enumerate(zip(n, fingers)):
        mu_lambda[f, :len(block)] = BarrierEnergy.compute_mu_lambda_kernel(block, n_f, x_f, w, mu,
                                                                           dhat, kappa)
    return mu_lambda


def init_step_size_kernel(x, n, p):
    """Algorithm 4, line 1, against moving half-spaces: along p, d_fi changes at n_f . (p_i - p_f),
    so alpha = 0.9 / max(max_fi -n_f . (p_i - p_f) / d_fi, 0.9) (BarrierEnergy.approach_rates)."""
    (block, fingers), (p_block, p_fingers) = split(x, n), split(p, n)
    rates = [BarrierEnergy.approach_rates(block, n_f, x_f, p_block - p_f).max(initial=0.0)
             for n_f, x_f, p_f in zip(n, fingers, p_fingers)]
    return 0.9 / max(float(max(rates)), 0.9)
