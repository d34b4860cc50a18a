"""The grasp's energy: FingerEnergy (the barrier against half-spaces through nodes of x, and the
squeeze), against finite differences on both sides of d = dhat; the fingers' CCD and mu*lambda
(scenes.grasp.Fingers)."""
from types import SimpleNamespace

import numpy as np
import pytest

import BarrierEnergy
import FingerEnergy
from helpers.fd import assert_close, check_energy
from scenes.grasp import Fingers

SEEDS = range(4)
NORMALS = np.array([[1.0, 0.0], [-0.6, 0.8]])       # two fingers, one tilted


def fingers(n):
    """Fingers of normals n (the lift plays no part here)."""
    return Fingers(np.asarray(n), np.ones(len(n)), np.array([0.0, 1.0]), 1.0, 1.0, 0.0, 0.05)


def finger_points(rng, d):
    """Block nodes at distances d (F, K) from fingers through two nodes, then the fingers' nodes
    (the last rows): (F K + F, 2); each block node is near one finger only, in front of both."""
    fingers = np.array([[-1.0, 0.0], [1.0, -1.0]]) + rng.uniform(-0.1, 0.1, (len(NORMALS), 2))
    tangents = NORMALS @ np.array([[0.0, -1.0], [1.0, 0.0]])        # (n_y, -n_x)
    block = [x_f + np.outer(rng.uniform(-0.05, 0.05, len(d_f)), t_f) + np.outer(d_f, n_f)
             for x_f, n_f, t_f, d_f in zip(fingers, NORMALS, tangents, d)]
    return np.vstack(block + [fingers])


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("where", ["inside", "just_below_dhat", "just_above_dhat", "mixed"])
def test_finger_energy(seed, where):
    rng = np.random.default_rng(seed)
    dhat, kappa = 0.01, 1e3
    d = {"inside": rng.uniform(0.1, 0.9, (2, 4)) * dhat,
         "just_below_dhat": dhat * (1 - rng.uniform(1e-3, 1e-2, (2, 4))),
         "just_above_dhat": dhat * (1 + rng.uniform(1e-3, 1e-2, (2, 4))),
         "mixed": rng.uniform(0.05, 3.0, (2, 4)) * dhat}[where]
    x = finger_points(rng, d)
    w = np.append(rng.uniform(0.1, 0.5, d.size), [0.0, 0.0])
    eps = 1e-3 * min(d.min(), abs(d - dhat).min())  # never straddles the branch at d = dhat
    check_energy(FingerEnergy, x, eps, NORMALS, [2.0, 3.0], w, dhat, kappa)


def test_finger_energy_is_the_barrier_through_each_finger_plus_the_squeeze():
    """P = sum_f P_b(x_block; n_f, x_f) - N_f n_f . x_f, and each finger's node takes minus the
    sum of its barrier forces: the total barrier force is zero (action, reaction)."""
    rng = np.random.default_rng(7)
    x = finger_points(rng, rng.uniform(0.2, 0.8, (2, 3)) * 0.01)
    w, squeeze = np.append(np.full(6, 0.3), [0.0, 0.0]), np.array([2.0, 3.0])
    block, fingers = x[:6], x[6:]
    barrier = sum(BarrierEnergy.val(block, n_f, x_f, w[:6], 0.01, 1e3)
                  for n_f, x_f in zip(NORMALS, fingers))
    expect = barrier - squeeze @ np.einsum("fj,fj->f", NORMALS, fingers)
    assert FingerEnergy.val(x, NORMALS, squeeze, w, 0.01, 1e3) == pytest.approx(expect, rel=1e-12)
    g_barrier = FingerEnergy.grad(x, NORMALS, [0.0, 0.0], w, 0.01, 1e3)
    assert_close(g_barrier.sum(axis=0), np.zeros(2), 1e-12, "barrier forces sum to zero",
                 1e-12 * np.abs(g_barrier).max())
    g = FingerEnergy.grad(x, NORMALS, squeeze, w, 0.01, 1e3)
    assert_close(g[6:] - g_barrier[6:], -squeeze[:, None] * NORMALS, 1e-12, "the squeeze")


def test_finger_ccd_is_relative_to_the_moving_finger():
    """A block node 0.01 from a finger: moving it 0.02 toward the finger, or the finger 0.02 toward
    it, is a contact at alpha 0.5 (0.9 of it taken); moving both together is no approach."""
    n = np.array([[1.0, 0.0]])
    x = np.array([[0.01, 0.0], [0.0, 0.0]])
    toward = np.array([[-0.02, 0.0], [0.0, 0.0]])
    assert fingers(n).init_step_size(x, toward) == pytest.approx(0.45)
    assert fingers(n).init_step_size(x, -toward[::-1]) == pytest.approx(0.45)
    assert fingers(n).init_step_size(x, np.tile([5.0, 1.0], (2, 1))) == 1.0


def test_finger_mu_lambda_is_mu_times_each_finger_s_force():
    rng = np.random.default_rng(3)
    x = finger_points(rng, np.array([[0.002, 0.02], [0.006, 0.5]]))
    w = np.append(np.full(4, 0.25), [0.0, 0.0])
    scene = SimpleNamespace(contact_area=w, dhat=0.01, kappa=1e3)
    mu_lambda = fingers(NORMALS).lambdas(scene, x, 0.3)
    for f, rows in enumerate([slice(0, 2), slice(2, 4)]):
        force = -BarrierEnergy.grad(x[:4], NORMALS[f], x[4 + f], w[:4], 0.01, 1e3)
        assert_close(mu_lambda[f, :4], 0.3 * np.linalg.norm(force, axis=1), 1e-12, "mu*lambda")
        assert mu_lambda[f, rows][0] > 0 and mu_lambda[f, rows][1] == 0.0
    assert not mu_lambda[:, 4:].any()           # the fingers' own rows


def test_fingers_need_a_normal_each_and_fewer_than_the_nodes():
    with pytest.raises(ValueError, match="^n must hold one normal per finger"):
        FingerEnergy.val(np.zeros((2, 2)), [[1.0, 0.0], [-1.0, 0.0]], 1.0, [1.0, 1.0])
