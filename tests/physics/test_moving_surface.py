"""Friction against a moving surface (the slide "Tangential Relative Velocity"): P_f of v - v_s, its
derivatives in x, the surface's prescribed motion, and the force that drags a body along."""
import dataclasses

import numpy as np
import pytest

import FrictionEnergy
import simulator
import time_integrator
from helpers.fd import assert_close, dense, fd_gradient, fd_jacobian, roundoff
from scenes.scene import MovingSurface

N = np.array([0.1, 1.0]) / np.hypot(0.1, 1.0)
T = FrictionEnergy.tangent(N)
EPSV, HHAT = 1e-3, 0.01


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("where", ["static", "just_below_epsv", "just_above_epsv", "sliding"])
def test_friction_derivatives_with_a_moving_surface(seed, where):
    """P_f(x) = sum mu lambda f0(||T^T ((x - x^n) / h - v_s)|| h): grad and hess against finite
    differences in x, with v_s = 2 m/s along t: the lab velocity is far from the slip, which alone
    sets the mollifier's branch (static, either side of eps_v, sliding)."""
    rng = np.random.default_rng(seed)
    speeds = {"static": rng.uniform(0.05, 0.9, 6) * EPSV,
              "just_below_epsv": EPSV * (1 - rng.uniform(1e-3, 1e-2, 6)),
              "just_above_epsv": EPSV * (1 + rng.uniform(1e-3, 1e-2, 6)),
              "sliding": rng.uniform(2, 500, 6) * EPSV}[where]
    v_s = 2.0 * T
    normal = 0.1 * EPSV * rng.normal(size=6)
    slip = np.outer(rng.choice([-1.0, 1.0], 6) * speeds, T) + np.outer(normal, N)
    x_n = 1e-6 * rng.normal(size=slip.shape)        # near zero: x - x^n loses no digits
    x = x_n + HHAT * (slip + v_s)
    mu_lambda = rng.uniform(10, 100, 6)
    mu_lambda[0] = 0.0                              # a node out of contact
    args = (mu_lambda, HHAT, N, EPSV)

    def relative(y):
        return (y - x_n) / HHAT - v_s

    def val(y):
        return FrictionEnergy.val(relative(y), *args)

    def grad(y):
        return FrictionEnergy.grad(relative(y), *args)      # in x: dv/dx = I / h is inside

    # a step eps in x moves the slip by eps / h: keep it far below every slip's distance to eps_v
    eps = 1e-4 * HHAT * min(np.abs(speeds - EPSV).min(), speeds.min())
    assert_close(grad(x), fd_gradient(val, x, eps), 1e-6, "grad vs FD of val",
                 roundoff(val(x), eps))
    H = dense(FrictionEnergy.hess(relative(x), *args, project_psd=False), x.size)
    assert_close(H, H.T, 1e-12, "hess symmetry")
    assert_close(H, fd_jacobian(grad, x, eps), 1e-6, "hess vs FD of grad", roundoff(grad(x), eps))


def test_the_integrator_s_friction_is_that_of_v_minus_v_s():
    """The Incremental Potential's gradient against finite differences of its value with a moving
    surface, and its friction part is FrictionEnergy's at (x - x^n) / h - v_s, not at the lab v."""
    scene = simulator.build_tablecloth_scene()
    x_n = scene.x0
    v_s = scene.surface.velocity(0.1, scene.h)                      # in the pull: U along +x
    lagged = time_integrator.Lagged(x_n, x_n, None, None, v_s)
    lagged = time_integrator.friction_update(scene, lagged, x_n)
    assert (lagged.mu_lambda > 0).sum() == scene.params["nx"] + 1    # the bottom row carries it
    y = x_n + 1e-6 * np.random.default_rng(0).normal(size=x_n.shape)

    def E(z):
        return time_integrator.IP_val(scene, lagged, z)

    assert_close(time_integrator.IP_grad(scene, lagged, y), fd_gradient(E, y, 1e-9), 1e-5, "grad E")
    frictionless = dataclasses.replace(lagged, mu_lambda=np.zeros(len(y)))
    friction_part = (time_integrator.IP_grad(scene, lagged, y)
                     - time_integrator.IP_grad(scene, frictionless, y))
    args = (lagged.mu_lambda, scene.h, scene.n, scene.epsv)
    relative = FrictionEnergy.grad((y - x_n) / scene.h - lagged.v_s, *args)
    assert_close(friction_part, scene.h ** 2 * relative, 1e-9, "the IP's friction part")
    lab = FrictionEnergy.grad((y - x_n) / scene.h, *args)
    assert np.abs(relative - lab).max() > 0.5 * np.abs(relative).max()     # v_s does enter

def test_the_cloth_moves_its_length_at_its_speed_for_any_h():
    """v_s of a step is the cloth's displacement over it, over h: U inside the pull, 0 outside,
    and the steps' displacements add up to L even where the pull's ends fall inside a step."""
    surface = MovingSurface(pull_speed=8.0, pull_length=1.0, t_pull=0.05,
                            tangent=np.array([1.0, 0.0]))
    for h in (5e-3, 3e-3, 7e-3):
        velocities = np.array([surface.velocity((n + 1) * h, h) for n in range(int(0.5 / h))])
        assert abs(velocities[:, 0].sum() * h - 1.0) < 1e-12 and not velocities[:, 1].any()
        assert (velocities[:, 0] >= 0.0).all() and (velocities[:, 0] <= 8.0 * (1 + 1e-12)).all()
    aligned = [surface.velocity((n + 1) * 5e-3, 5e-3)[0] for n in range(100)]   # 10 + 25 steps
    assert np.allclose(aligned, [0.0] * 10 + [8.0] * 25 + [0.0] * 65, rtol=1e-12, atol=1e-9)
    assert surface.offset(0.0) == 0.0 and surface.offset(1.0) == 1.0


def test_friction_drags_a_dish_at_rest_toward_the_cloth_s_velocity():
    """The pull's first step: the dish at rest, the cloth at U >> eps_v. Friction speeds the dish up
    (positive lab-frame work) with the whole bound mu M g along the pull, and the surface's work is
    that force times U h; heat = surface work - friction work >= 0."""
    scene = simulator.build_tablecloth_scene(pull_speed=4.0)
    p = scene.params
    first = int(round(p["t_pull"] / scene.h))          # the step that ends at t_pull + h
    for record in simulator.simulate(scene, first + 1):
        assert record.index == first or record.report.surface_work == 0.0
    report = record.report
    weight = p["mass"] * -p["gravity"][1]
    force = report.friction_force.sum(axis=0)
    assert force[0] == pytest.approx(p["mu"] * weight, rel=1e-3) and abs(force[1]) < 1e-9 * weight
    assert report.friction_work > 0.0
    assert report.surface_work == pytest.approx(force[0] * p["pull_speed"] * scene.h, rel=1e-12)
    assert report.surface_work - report.friction_work > 0.0
    assert (record.v[:, 0] > 0.0).all()


def test_a_still_surface_does_no_work():
    """Without a moving surface, v_s is zero: the default scene's reports carry no surface work."""
    scene = simulator.build_scene()
    assert scene.surface is None and not time_integrator.Lagged(scene.x0, scene.x0, None).v_s.any()
    assert all(record.report.surface_work == 0.0 for record in simulator.simulate(scene, 40))
