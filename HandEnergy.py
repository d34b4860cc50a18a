"""The hand (the chalk's grip): zero-rest-length springs from the held nodes to moving targets,

    P_hand(x) = sum_{i held} 1/2 k_hand ||x_i - target_i||^2,

the penalty form of a moving boundary condition (the tutorial's 5_mov_dirichlet), targets at
t^{n+1}, k_hand one or one per held node (val/grad/hess check, the *_kernel trusts its input).
"""
from dataclasses import dataclass

import numpy as np

import utils


@dataclass(frozen=True)
class Hand:
    """The grip as scene data: the held nodes, their stiffness, and their targets rest + d(t), d
    linear through the keyframes (key_t, key_d), at the last segment's velocity after key_t[-1]."""
    nodes: np.ndarray       # (H,) held node indices
    rest: np.ndarray        # (H, 2) the targets at d = 0 (the held nodes' start positions), m
    k_hand: float           # spring stiffness per held node, N/m
    key_t: np.ndarray       # (K,) keyframe times, increasing, K >= 2, s
    key_d: np.ndarray       # (K, 2) the targets' displacement at key_t, m

    def displacement(self, t):
        """d(t), constant before key_t[0]."""
        t0, t1 = self.key_t[-2:]
        if t > t1:
            return self.key_d[-1] + (t - t1) / (t1 - t0) * (self.key_d[-1] - self.key_d[-2])
        return np.array([np.interp(t, self.key_t, d) for d in self.key_d.T])

    def targets(self, t):
        """target_i(t) = rest_i + d(t), (H, 2)."""
        return self.rest + self.displacement(t)


def _check(x, nodes, target, k_hand):
    x = utils.check_points("x", x)
    nodes = np.asarray(nodes)
    if nodes.ndim != 1 or (nodes.size and not np.issubdtype(nodes.dtype, np.integer)):
        raise ValueError("nodes must be a 1-D array of integer node indices, "
                         f"got {nodes.dtype} of shape {nodes.shape}")
    if nodes.size and (nodes.min() < 0 or nodes.max() >= len(x)):
        bad = nodes[(nodes < 0) | (nodes >= len(x))][0]
        raise ValueError(f"nodes has node index {bad} outside [0, {len(x)}) for {len(x)} nodes")
    if len(np.unique(nodes)) != len(nodes):
        raise ValueError("nodes must not hold a node twice")
    target = utils.check_points("target", target, (len(nodes), 2))
    k_hand = utils.check_per_item("k_hand", k_hand, len(nodes), what="held node")
    if (k_hand < 0).any():
        i = int(np.argmax(k_hand < 0))
        raise ValueError(f"k_hand must be >= 0, got {k_hand[i]} at held node {i}")
    return x, nodes.astype(np.int64), target, k_hand


def val(x, nodes, target, k_hand):
    """P_hand = sum_i 1/2 k_hand ||x_i - target_i||^2 over the held nodes (checked)."""
    return val_kernel(*_check(x, nodes, target, k_hand))


def grad(x, nodes, target, k_hand):
    """grad_i P_hand = k_hand (x_i - target_i) at the held nodes, zero elsewhere (checked)."""
    return grad_kernel(*_check(x, nodes, target, k_hand))


def hess(x, nodes, target, k_hand):
    """hess_i P_hand = k_hand I at the held nodes, as an IJV triplet (checked)."""
    return utils.blocks_to_ijv(*hess_kernel(*_check(x, nodes, target, k_hand)))


def val_kernel(x, nodes, target, k_hand):
    diff = x.take(nodes, axis=0) - target
    return 0.5 * float((k_hand * np.einsum("ij,ij->i", diff, diff)).sum())


def grad_kernel(x, nodes, target, k_hand):
    g = np.zeros(x.shape)
    g[nodes] = np.asarray(k_hand)[..., None] * (x.take(nodes, axis=0) - target)   # one, or (H,)
    return g


def hess_kernel(x, nodes, target, k_hand):
    """A 2x2 block k_hand I on each held node alone: PSD, constant, within the mesh's band."""
    return nodes[:, None], np.full(len(nodes), k_hand)[:, None, None] * np.eye(2)
