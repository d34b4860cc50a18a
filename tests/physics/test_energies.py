"""Every energy's grad against its val, and hess against grad, by central finite differences,
at many random configurations and on both sides of every branch point."""
import numpy as np
import pytest

import BarrierEnergy
import FrictionEnergy
import GravityEnergy
import HandEnergy
import InertiaEnergy
import MassSpringEnergy
import square_mesh
from helpers.fd import assert_close, check_derivatives, check_energy, dense

SEEDS = range(6)
N_SLOPE = np.array([0.1, 1.0]) / np.hypot(0.1, 1.0)
O_SLOPE = np.array([0.0, -1.0])


def check_friction(x, x_n, hhat, args, eps):
    """check_derivatives of P_f as a function of x, v = (x - x_n) / hhat, its true Hessian."""
    def vel(y):
        return (y - x_n) / hhat
    check_derivatives(lambda y: FrictionEnergy.val(vel(y), *args),
                      lambda y: FrictionEnergy.grad(vel(y), *args),
                      lambda y: FrictionEnergy.hess(vel(y), *args, project_psd=False), x, eps)


# --- inertia and gravity --------------------------------------------------------------------

@pytest.mark.parametrize("seed", SEEDS)
def test_inertia(seed):
    rng = np.random.default_rng(seed)
    x, x_tilde, m = rng.normal(size=(7, 2)), rng.normal(size=(7, 2)), rng.uniform(0.5, 3, 7)
    check_energy(InertiaEnergy, x, 1e-5, x_tilde, m)


@pytest.mark.parametrize("seed", SEEDS)
def test_gravity(seed):
    rng = np.random.default_rng(seed)
    x, m, g = rng.normal(size=(6, 2)), rng.uniform(0.5, 3, 6), rng.normal(size=2)
    check_energy(GravityEnergy, x, 1e-5, m, g)
    assert all(len(a) == 0 for a in GravityEnergy.hess(x, m, g))
    assert GravityEnergy.val(np.array([[0.0, 2.0]]), [3.0]) == pytest.approx(3.0 * 9.81 * 2.0)


# --- mass-spring ----------------------------------------------------------------------------

def spring_setup(seed, stretch):
    """The lecture's mesh, its springs scaled by `stretch` on average plus random jitter."""
    rng = np.random.default_rng(seed)
    x0, e = square_mesh.generate(1.0, 3)
    d = x0[e[:, 0]] - x0[e[:, 1]]
    l2 = np.einsum("ij,ij->i", d, d)
    x = stretch * x0 + 0.02 * rng.normal(size=x0.shape)
    k = rng.uniform(1e3, 3e4, len(e))
    return x, e, l2, k


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("stretch", [0.6, 0.97, 1.03, 1.5])
def test_mass_spring_true_hessian(seed, stretch):
    x, e, l2, k = spring_setup(seed, stretch)
    check_energy(MassSpringEnergy, x, 1e-6, e, l2, k, project_psd=False)


def test_mass_spring_projection_only_changes_compressed_springs():
    x, e, l2, k = spring_setup(0, 1.5)           # every spring stretched: true Hessian is PSD
    diff = x[e[:, 0]] - x[e[:, 1]]
    assert (np.einsum("ij,ij->i", diff, diff) > l2).all()
    n = x.size
    H_true = dense(MassSpringEnergy.hess(x, e, l2, k, project_psd=False), n)
    assert_close(dense(MassSpringEnergy.hess(x, e, l2, k), n), H_true, 1e-12, "stretched")
    x, e, l2, k = spring_setup(0, 0.6)           # compressed: the true Hessian is indefinite
    H_true = dense(MassSpringEnergy.hess(x, e, l2, k, project_psd=False), n)
    H_proj = dense(MassSpringEnergy.hess(x, e, l2, k), n)
    assert np.linalg.eigvalsh(H_true).min() < -1e-6 * np.abs(H_true).max()
    assert np.linalg.eigvalsh(H_proj).min() > -1e-9 * np.abs(H_proj).max()


def test_mass_spring_value_at_rest_and_by_hand():
    x0, e = square_mesh.generate(1.0, 2)
    d = x0[e[:, 0]] - x0[e[:, 1]]
    l2 = np.einsum("ij,ij->i", d, d)
    # exact by construction: every coordinate is a multiple of 0.5, so each edge vector, its
    # squared length and the strain ||d||^2 / l^2 - 1 = 0 are exact in float64, with or without FMA
    assert MassSpringEnergy.val(x0, e, l2, 5.0) == 0.0
    # one spring of rest length 1 stretched to 2: 1/2 k l^2 (4/1 - 1)^2 = 4.5 k
    stretched = MassSpringEnergy.val([[0.0, 0.0], [2.0, 0.0]], [[0, 1]], [1.0], [3.0])
    assert stretched == pytest.approx(13.5)


# --- barrier --------------------------------------------------------------------------------

def barrier_points(rng, d):
    """Nodes at the given distances d from the lecture's slope, spread along it."""
    tangent = np.array([N_SLOPE[1], -N_SLOPE[0]])
    return O_SLOPE + np.outer(rng.uniform(-1, 1, len(d)), tangent) + np.outer(d, N_SLOPE)


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("where", ["inside", "just_below_dhat", "just_above_dhat", "mixed"])
def test_barrier(seed, where):
    rng = np.random.default_rng(seed)
    dhat, kappa = 0.01, 1e5
    d = {"inside": rng.uniform(0.1, 0.9, 6) * dhat,
         "just_below_dhat": dhat * (1 - rng.uniform(1e-3, 1e-2, 6)),
         "just_above_dhat": dhat * (1 + rng.uniform(1e-3, 1e-2, 6)),
         "mixed": rng.uniform(0.05, 3.0, 6) * dhat}[where]
    x, w = barrier_points(rng, d), rng.uniform(0.1, 0.5, len(d))
    args = (N_SLOPE, O_SLOPE, w, dhat, kappa)
    eps = 1e-3 * min(d.min(), abs(d - dhat).min())   # never straddles the branch at d = dhat
    check_energy(BarrierEnergy, x, eps, *args)
    if where == "just_above_dhat":          # empty active set: the sum of nothing, 0.0 exactly
        assert BarrierEnergy.val(x, *args) == 0.0 and len(BarrierEnergy.hess(x, *args)[0]) == 0


def test_barrier_keyword_constants_and_value():
    x = np.array([[0.0, 0.005]])
    # w dhat kappa/2 (s - 1) ln s with s = 1/2
    expect = 0.25 * 0.01 * 1e5 / 2 * (-0.5) * np.log(0.5)
    up, origin = [0.0, 1.0], [0.0, 0.0]
    assert BarrierEnergy.val(x, up, origin, [0.25]) == pytest.approx(expect)
    assert BarrierEnergy.val(x, up, origin, [0.25], kappa=2e5) == pytest.approx(2 * expect)
    # inactive: 0.0 exactly
    assert BarrierEnergy.val(x, up, origin, [0.25], dhat=0.004) == 0.0


def test_mu_lambda_is_mu_times_contact_force():
    rng = np.random.default_rng(3)
    d = np.array([0.002, 0.006, 0.02, 0.5])
    x, w = barrier_points(rng, d), np.full(4, 0.25)
    mu_lambda = BarrierEnergy.compute_mu_lambda(x, N_SLOPE, O_SLOPE, w, 0.3)
    force = -BarrierEnergy.grad(x, N_SLOPE, O_SLOPE, w)       # contact force on each node
    assert_close(mu_lambda, 0.3 * np.linalg.norm(force, axis=1), 1e-12, "mu*lambda")
    # beyond dhat: no force at all, 0.0 exactly
    assert (mu_lambda[:2] > 0).all() and (mu_lambda[2:] == 0).all()


def test_init_step_size_is_ccd_scaled_by_0_9():
    x = np.array([[0.0, 1.0], [1.0, 0.5], [2.0, 3.0]])
    n, o = np.array([0.0, 1.0]), np.zeros(2)
    p = np.array([[0.0, -2.0], [0.0, -4.0], [0.0, 1.0]])
    # node 0 reaches the ground at alpha 0.5, node 1 at 0.125: 0.9 * 0.125
    assert BarrierEnergy.init_step_size(x, n, o, p) == pytest.approx(0.1125)
    # no node reaches the ground within alpha <= 1 / 0.9: the full step, the constant 1.0 exactly
    assert BarrierEnergy.init_step_size(x, n, o, -p * 0.01) == 1.0
    assert BarrierEnergy.init_step_size(x, n, o, p * 0.01) == 1.0


# --- friction -------------------------------------------------------------------------------

def friction_setup(rng, speeds, epsv, hhat):
    """Velocities with tangential speed `speeds` (plus any normal part), and positions
    x = x^n + hhat v, so P_f can be differentiated with respect to x. x^n is kept near zero so
    that x - x^n loses no digits at the tiny FD steps near eps_v."""
    tangent = np.array([N_SLOPE[1], -N_SLOPE[0]])
    sign = rng.choice([-1.0, 1.0], len(speeds))
    normal = 0.1 * epsv * rng.normal(size=len(speeds)) if speeds.any() else np.zeros(len(speeds))
    v = np.outer(sign * speeds, tangent) + np.outer(normal, N_SLOPE)     # speeds 0: v = 0 exactly
    x_n = 1e-6 * rng.normal(size=v.shape)
    mu_lambda = rng.uniform(10, 100, len(speeds))
    mu_lambda[0] = 0.0                          # a node out of contact
    return x_n, x_n + hhat * v, mu_lambda


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("where",
                         ["static", "just_below_epsv", "just_above_epsv", "sliding", "zero"])
def test_friction(seed, where):
    rng = np.random.default_rng(seed)
    epsv, hhat = 1e-3, 0.01
    speeds = {"static": rng.uniform(0.05, 0.9, 6) * epsv,
              "just_below_epsv": epsv * (1 - rng.uniform(1e-3, 1e-2, 6)),
              "just_above_epsv": epsv * (1 + rng.uniform(1e-3, 1e-2, 6)),
              "sliding": rng.uniform(2, 500, 6) * epsv,
              "zero": np.zeros(6)}[where]
    x_n, x, mu_lambda = friction_setup(rng, speeds, epsv, hhat)
    args = (mu_lambda, hhat, N_SLOPE, epsv)
    # a step eps in x moves the tangential speed by eps/hhat: keep it far below the distance of
    # every speed to a branch point (eps_v, and 0 where |vbar| is not smooth)
    # at vbar = 0 exactly, grad contains |vbar| vbar (C1 only), so the FD error is ~ step/eps_v
    gap = min(np.abs(speeds - epsv).min(), speeds.min()) if where != "zero" else 1e-3 * epsv
    check_friction(x, x_n, hhat, args, 1e-4 * hhat * gap)
    g = FrictionEnergy.grad((x - x_n) / hhat, *args)
    if where == "zero":
        assert not g.any()
    along_slope_only = np.abs(g @ N_SLOPE).max() <= 1e-12 * max(np.abs(g).max(), 1.0)
    assert along_slope_only, "friction acts along the slope only"


def lecture_f0(vbarnorm, epsv, hhat):
    """The lecture's FrictionEnergy.f0, scalar, as the slide writes it."""
    if vbarnorm >= epsv:
        return vbarnorm * hhat
    vbarnormhhat, epsvhhat = vbarnorm * hhat, epsv * hhat
    return (vbarnormhhat * vbarnormhhat * (-vbarnormhhat / 3.0 + epsvhhat) / (epsvhhat * epsvhhat)
            + epsvhhat / 3.0)


def lecture_f1_div_vbarnorm(vbarnorm, epsv):
    return 1.0 / vbarnorm if vbarnorm >= epsv else (-vbarnorm + 2.0 * epsv) / (epsv * epsv)


def lecture_f_hess_term(vbarnorm, epsv):
    return -1.0 / (vbarnorm * vbarnorm) if vbarnorm >= epsv else -1.0 / (epsv * epsv)


def test_mollifier_functions_are_the_lecture_s():
    """f0, f1_div_vbarnorm and f_hess_term take the lecture's arguments and give its numbers
    (written in ||vbar|| / eps_v, so they agree to round-off, a few ulps)."""
    epsv, hhat = 1e-3, 0.01
    by_hand = 5.0e-6 * 5.0e-6 * (-5.0e-6 / 3 + 1e-5) / 1e-10 + 1e-5 / 3
    assert FrictionEnergy.f0(5e-4, epsv, hhat) == pytest.approx(by_hand, rel=1e-14)
    vbarnorm = np.concatenate([[0.0, 1e-300, np.nextafter(epsv, 0), epsv],
                               np.linspace(0, 4 * epsv, 101)])
    for mine, lecture, args in ((FrictionEnergy.f0, lecture_f0, (epsv, hhat)),
                                (FrictionEnergy.f1_div_vbarnorm, lecture_f1_div_vbarnorm, (epsv,)),
                                (FrictionEnergy.f_hess_term, lecture_f_hess_term, (epsv,))):
        # no division by zero at ||vbar|| = 0
        with np.errstate(divide="raise", invalid="raise"):
            values = mine(vbarnorm, *args)
        assert_close(values, [lecture(v, *args) for v in vbarnorm], 1e-14, mine.__name__)


def test_tangent_spans_the_tangent_operator():
    """The kernels use T = I - n n^T = t t^T (a half-space in 2-D)."""
    for n in (N_SLOPE, np.array([0.0, 1.0]), np.array([-0.6, 0.8])):
        t = FrictionEnergy.tangent(n)
        assert_close(np.outer(t, t), np.eye(2) - np.outer(n, n), 1e-15, "t t^T")
        # t . n = n_y n_x - n_x n_y is zero in exact arithmetic; numpy's dot may fuse the two
        # products (an FMA kernel on AVX-512 CPUs), which leaves the rounding of one product, at
        # most eps/2 |n_x n_y| <= eps/4 for a unit n.
        assert abs(t @ n) <= 0.25 * np.finfo(float).eps


def test_friction_force_magnitude_is_mu_lambda_when_sliding():
    rng = np.random.default_rng(0)
    x_n, x, mu_lambda = friction_setup(rng, np.full(5, 0.7), 1e-3, 0.01)
    g = FrictionEnergy.grad((x - x_n) / 0.01, mu_lambda, 0.01, N_SLOPE)
    assert_close(np.linalg.norm(g, axis=1), mu_lambda, 1e-12, "|F| = mu lambda")


def test_friction_projection_is_identity_on_psd_bracket():
    """The bracket of the lecture's hess_k P_f is PSD for its f1, so projecting it changes nothing
    beyond round-off of the terms it is made of, mu_lambda/hhat * f1(||vbar||)/||vbar|| (in 2-D the
    sliding Hessian is exactly zero: both sides are then round-off of that size)."""
    rng = np.random.default_rng(1)
    for speeds in (np.zeros(6), np.full(6, 5e-4), np.full(6, 0.2)):
        x_n, x, mu_lambda = friction_setup(rng, speeds, 1e-3, 0.01)
        v = (x - x_n) / 0.01
        natural = mu_lambda.max() / 0.01 * FrictionEnergy.f1_div_vbarnorm(speeds, 1e-3).max()
        projected = dense(FrictionEnergy.hess(v, mu_lambda, 0.01, N_SLOPE), x.size)
        true = dense(FrictionEnergy.hess(v, mu_lambda, 0.01, N_SLOPE, project_psd=False), x.size)
        assert_close(projected, true, 1e-12, "projection of a PSD bracket", atol=1e-12 * natural)


# --- mollifier --------------------------------------------------------------------------------

def f1(vbarnorm, epsv):
    """f1(||vbar||) = ||vbar|| f1_div_vbarnorm(||vbar||)."""
    return vbarnorm * FrictionEnergy.f1_div_vbarnorm(vbarnorm, epsv)


def test_f0_derivative_is_f1():
    """d f0(||vbar|| hhat) / d||vbar|| = hhat f1(||vbar||) (the lecture's f0'(y) = f1(y / hhat))."""
    epsv, hhat = 1e-3, 0.01
    vbarnorm = np.concatenate([np.linspace(0, 3 * epsv, 301),
                               [epsv * (1 - 1e-4), epsv * (1 + 1e-4)]])
    step = 1e-4 * epsv
    # off the branch points
    vbarnorm = vbarnorm[(np.abs(vbarnorm - epsv) > 2 * step) & (vbarnorm > 2 * step)]
    numeric = (FrictionEnergy.f0(vbarnorm + step, epsv, hhat)
               - FrictionEnergy.f0(vbarnorm - step, epsv, hhat)) / (2 * step)
    assert_close(numeric, hhat * f1(vbarnorm, epsv), 1e-7, "f0' = hhat f1")


def test_mollifier_continuity_at_branch_point():
    epsv, hhat = 2e-3, 0.02
    below, above = np.nextafter(epsv, 0), epsv
    for f, args in ((FrictionEnergy.f0, (epsv, hhat)), (f1, (epsv,)),
                    (FrictionEnergy.f1_div_vbarnorm, (epsv,)),
                    (FrictionEnergy.f_hess_term, (epsv,))):
        assert f(below, *args) == pytest.approx(f(above, *args), rel=1e-12), f.__name__
    assert FrictionEnergy.f0(0.0, epsv, hhat) == pytest.approx(epsv * hhat / 3)


def test_f_hess_term_is_f1_prime_y_minus_f1_over_y_squared():
    """f_hess_term(y) = (f1'(y) y - f1(y)) / y^2, with f1' by central differences of f1."""
    epsv = 1e-3
    y = np.linspace(1e-5, 3e-3, 400)
    step = 1e-9
    y = y[np.abs(y - epsv) > 2 * step]
    f1_prime = (f1(y + step, epsv) - f1(y - step, epsv)) / (2 * step)
    assert_close(FrictionEnergy.f_hess_term(y, epsv), (f1_prime * y - f1(y, epsv)) / y ** 2, 1e-5,
                 "f_hess_term", atol=1e-5 / epsv ** 2)


def test_f1_div_vbarnorm_finite_at_zero():
    with np.errstate(all="raise"):                      # any division by zero would raise here
        value = FrictionEnergy.f1_div_vbarnorm(np.array([0.0, 1e-300, 1e-3, 5.0]), 1e-3)
        term = FrictionEnergy.f_hess_term(np.array([0.0, 5.0]), 1e-3)
        g = FrictionEnergy.grad(np.zeros((3, 2)), np.ones(3), 0.01, N_SLOPE)
        H = FrictionEnergy.hess(np.zeros((3, 2)), np.ones(3), 0.01, N_SLOPE)
    assert value[0] == pytest.approx(2 / 1e-3)
    assert np.isfinite(value).all() and np.isfinite(term).all()
    assert not g.any() and np.isfinite(H[2]).all()


# --- the FD check itself catches wrong formulas --------------------------------------------------

@pytest.mark.parametrize("break_it",
                         ["sign", "factor_2", "f1_div_vbarnorm_factor_2", "f_hess_term_factor_2"])
def test_fd_check_catches_broken_formula(break_it, monkeypatch):
    """Break a formula on purpose; the same checks as above must fail."""
    x, e, l2, k = spring_setup(0, 1.2)
    rng = np.random.default_rng(0)
    x_n, xf, mu_lambda = friction_setup(rng, np.full(6, 0.5e-3), 1e-3, 0.01)
    if break_it in ("sign", "factor_2"):
        factor = -1.0 if break_it == "sign" else 2.0
        with pytest.raises(AssertionError):
            check_derivatives(lambda y: MassSpringEnergy.val(y, e, l2, k),
                              lambda y: factor * MassSpringEnergy.grad(y, e, l2, k),
                              lambda y: MassSpringEnergy.hess(y, e, l2, k, project_psd=False),
                              x, 1e-6)
        return
    name = "f1_div_vbarnorm" if break_it == "f1_div_vbarnorm_factor_2" else "f_hess_term"
    original = getattr(FrictionEnergy, name)
    monkeypatch.setattr(FrictionEnergy, name, lambda vbarnorm, epsv: 2.0 * original(vbarnorm, epsv))
    with pytest.raises(AssertionError):
        check_friction(xf, x_n, 0.01, (mu_lambda, 0.01, N_SLOPE, 1e-3), 1e-9)


# --- the hand (the chalk's grip): zero-rest-length springs to moving targets ----------------------

@pytest.mark.parametrize("seed", SEEDS)
def test_hand(seed):
    rng = np.random.default_rng(seed)
    x = rng.normal(size=(9, 2))
    nodes = rng.choice(9, size=4, replace=False)
    target = x[nodes] + 0.1 * rng.normal(size=(4, 2))
    # one stiffness, or one per node
    for k_hand in (rng.uniform(500, 8000), rng.uniform(500, 8000, 4)):
        check_energy(HandEnergy, x, 1e-5, nodes, target, k_hand)
    free = np.setdiff1d(np.arange(9), nodes)
    # only the held nodes are pulled
    assert not HandEnergy.grad(x, nodes, target, 1e3)[free].any()


def test_hand_value_by_hand_and_its_blocks_are_node_blocks():
    # one held node 3 m and 4 m from its target: 1/2 k 5^2
    x = [[0.0, 0.0], [1.0, 1.0]]
    assert HandEnergy.val(x, [1], [[4.0, 5.0]], 4.0) == 50.0
    assert HandEnergy.grad(x, [1], [[4.0, 5.0]], 4.0).tolist() == [[0, 0], [-12, -16]]
    nodes, blocks = HandEnergy.hess_kernel(np.zeros((5, 2)), np.array([1, 4]), np.zeros((2, 2)),
                                           7.0)
    # k_hand I on each node alone
    assert nodes.shape == (2, 1) and np.array_equal(blocks, [7.0 * np.eye(2)] * 2)


def test_hand_targets_follow_the_keyframes_and_then_the_last_velocity():
    hand = HandEnergy.Hand(nodes=np.array([0, 1]), rest=np.array([[0.0, 1.0], [1.0, 1.0]]),
                           k_hand=2000.0, key_t=np.array([0.0, 0.1, 0.2, 1.2]),
                           key_d=np.array([[0.0, 0.0], [0.0, -5e-4], [0.0, -5e-4], [0.01, -5e-4]]))
    assert np.array_equal(hand.targets(0.0), hand.rest)
    # halfway down
    assert np.allclose(hand.displacement(0.05), [0.0, -2.5e-4], rtol=0, atol=1e-18)
    # holding
    assert np.allclose(hand.displacement(0.15), [0.0, -5e-4], rtol=0, atol=1e-18)
    # moving at 0.01 m/s
    assert np.allclose(hand.displacement(0.7), [0.005, -5e-4], rtol=0, atol=1e-15)
    # and on, past key_t[-1]
    assert np.allclose(hand.displacement(3.2), [0.03, -5e-4], rtol=0, atol=1e-15)
    assert np.allclose(hand.targets(3.2), hand.rest + [0.03, -5e-4], rtol=0, atol=1e-15)


# --- friction that weakens with slip: mu per node -------------------------------------------------

def test_slip_weakened_mu_from_static_to_kinetic():
    mu, mu_s, v_c = 0.35, 0.5, 1e-3
    vbarnorm = np.array([0.0, v_c, 10 * v_c, 1.0])
    expected = [mu_s, mu + (mu_s - mu) / np.e, mu + (mu_s - mu) * np.exp(-10), mu]
    assert_close(FrictionEnergy.slip_weakened_mu(vbarnorm, mu, mu_s, v_c), expected, 1e-15,
                 "mu(||vbar||)")
    # one coefficient (mu_s = mu) is mu exactly, at every speed: mu + 0 * exp(...)
    assert (FrictionEnergy.slip_weakened_mu(vbarnorm, mu, mu, v_c) == mu).all()


def test_mu_lambda_with_a_mu_per_node_is_each_node_s_mu_times_its_contact_force():
    rng = np.random.default_rng(5)
    d = np.array([0.002, 0.006, 0.02, 0.5, 0.004])
    x, w = barrier_points(rng, d), np.full(5, 0.25)
    mu = rng.uniform(0.1, 0.6, 5)
    force = np.linalg.norm(-BarrierEnergy.grad(x, N_SLOPE, O_SLOPE, w), axis=1)
    mu_lambda = BarrierEnergy.compute_mu_lambda(x, N_SLOPE, O_SLOPE, w, mu)
    assert_close(mu_lambda, mu * force, 1e-12, "mu_k lambda_k")
    # an array of one value is the scalar's result, bit for bit
    assert np.array_equal(BarrierEnergy.compute_mu_lambda(x, N_SLOPE, O_SLOPE, w, np.full(5, 0.3)),
                          BarrierEnergy.compute_mu_lambda(x, N_SLOPE, O_SLOPE, w, 0.3))


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("where", ["static", "sliding", "zero"])
def test_friction_with_a_slip_weakened_mu_per_node(seed, where):
    """The lagged solve's P_f with mu_k = slip_weakened_mu(|t . v^n_k|), mu_lambda = mu_k
    lambda_k(x^n): fixed through the solve, so P_f(x) is still a potential and its grad and hess
    still match FD."""
    rng = np.random.default_rng(seed)
    epsv, hhat, v_c = 1e-3, 0.01, 1e-3
    speeds = {"static": rng.uniform(0.05, 0.9, 6) * epsv, "sliding": rng.uniform(2, 500, 6) * epsv,
              "zero": np.zeros(6)}[where]
    x_n, x, _ = friction_setup(rng, speeds, epsv, hhat)
    tangent = FrictionEnergy.tangent(N_SLOPE)
    along = np.outer(rng.uniform(-1, 1, 6), tangent)
    # some nodes within dhat = 0.01, some beyond
    contact = O_SLOPE + along + np.outer(rng.uniform(0.1, 1.5, 6) * 0.01, N_SLOPE)
    v_n = rng.normal(size=(6, 2)) * rng.uniform(0, 5 * v_c, 6)[:, None]
    mu = FrictionEnergy.slip_weakened_mu(np.abs(v_n @ tangent), 0.35, 0.5, v_c)
    mu_lambda = BarrierEnergy.compute_mu_lambda(contact, N_SLOPE, O_SLOPE, np.full(6, 0.25), mu)
    assert ((mu >= 0.35) & (mu <= 0.5)).all() and (mu_lambda > 0).any()
    gap = min(np.abs(speeds - epsv).min(), speeds.min()) if where != "zero" else 1e-3 * epsv
    check_friction(x, x_n, hhat, (mu_lambda, hhat, N_SLOPE, epsv), 1e-4 * hhat * gap)


def eig_route(H):
    """Reference: numpy's eigen-decomposition, negative eigenvalues clamped, one matrix at a time
    (the lecture's make_PD)."""
    out = []
    for A in H:
        lam, Q = np.linalg.eigh(A)
        out.append(Q @ np.diag(np.maximum(lam, 0)) @ Q.T)
    return np.array(out)


def test_spring_closed_form_equals_4x4_eigen_projection():
    rng = np.random.default_rng(2)
    x, e = square_mesh.generate(1.0, 3)
    d = x[e[:, 0]] - x[e[:, 1]]
    l2 = np.einsum("ij,ij->i", d, d)
    x = x * 0.8 + 0.05 * rng.normal(size=x.shape)                   # mostly compressed springs
    rows, cols, vals = MassSpringEnergy.hess(x, e, l2, 1e4, project_psd=False)
    blocks = vals.reshape(len(e), 4, 4)
    projected = MassSpringEnergy.hess(x, e, l2, 1e4)[2].reshape(len(e), 4, 4)
    assert np.allclose(projected, eig_route(blocks), rtol=1e-10, atol=1e-8)
