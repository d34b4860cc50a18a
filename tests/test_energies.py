"""Every energy's grad against its val, and hess against grad, by central finite differences,
at many random configurations and on both sides of every branch point."""
import numpy as np
import pytest

import BarrierEnergy
import FrictionEnergy
import GravityEnergy
import InertiaEnergy
import MassSpringEnergy
import square_mesh
import utils
from fd import assert_close, dense, fd_gradient, fd_jacobian, roundoff

SEEDS = range(6)
N_SLOPE = np.array([0.1, 1.0]) / np.hypot(0.1, 1.0)
O_SLOPE = np.array([0.0, -1.0])


def check_derivatives(val, grad, hess, x, eps, rtol=1e-6):
    """grad == FD(val) and dense(hess) == FD(grad) at x; also hess is symmetric and 2N x 2N."""
    assert_close(grad(x), fd_gradient(val, x, eps), rtol, "grad vs FD of val", roundoff(val(x), eps))
    ijv = hess(x)
    assert all(a.ndim == 1 for a in ijv) and len({len(a) for a in ijv}) == 1
    H = dense(ijv, x.size)
    assert_close(H, H.T, 1e-12, "hess symmetry")
    assert_close(H, fd_jacobian(grad, x, eps), rtol, "hess vs FD of grad", roundoff(grad(x), eps))


# --- inertia and gravity --------------------------------------------------------------------

@pytest.mark.parametrize("seed", SEEDS)
def test_inertia(seed):
    rng = np.random.default_rng(seed)
    x, x_tilde, m = rng.normal(size=(7, 2)), rng.normal(size=(7, 2)), rng.uniform(0.5, 3, 7)
    check_derivatives(lambda y: InertiaEnergy.val(y, x_tilde, m), lambda y: InertiaEnergy.grad(y, x_tilde, m),
                      lambda y: InertiaEnergy.hess(y, x_tilde, m), x, 1e-5)


@pytest.mark.parametrize("seed", SEEDS)
def test_gravity(seed):
    rng = np.random.default_rng(seed)
    x, m, g = rng.normal(size=(6, 2)), rng.uniform(0.5, 3, 6), rng.normal(size=2)
    check_derivatives(lambda y: GravityEnergy.val(y, m, g), lambda y: GravityEnergy.grad(y, m, g),
                      lambda y: GravityEnergy.hess(y, m, g), x, 1e-5)
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
    check_derivatives(lambda y: MassSpringEnergy.val(y, e, l2, k), lambda y: MassSpringEnergy.grad(y, e, l2, k),
                      lambda y: MassSpringEnergy.hess(y, e, l2, k, project_psd=False), x, 1e-6)


def test_mass_spring_projection_only_changes_compressed_springs():
    x, e, l2, k = spring_setup(0, 1.5)           # every spring stretched: true Hessian is PSD
    diff = x[e[:, 0]] - x[e[:, 1]]
    assert (np.einsum("ij,ij->i", diff, diff) > l2).all()
    n = x.size
    assert_close(dense(MassSpringEnergy.hess(x, e, l2, k), n),
                 dense(MassSpringEnergy.hess(x, e, l2, k, project_psd=False), n), 1e-12, "stretched")
    x, e, l2, k = spring_setup(0, 0.6)           # compressed: the true Hessian is indefinite
    H_true = dense(MassSpringEnergy.hess(x, e, l2, k, project_psd=False), n)
    H_proj = dense(MassSpringEnergy.hess(x, e, l2, k), n)
    assert np.linalg.eigvalsh(H_true).min() < -1e-6 * np.abs(H_true).max()
    assert np.linalg.eigvalsh(H_proj).min() > -1e-9 * np.abs(H_proj).max()


def test_mass_spring_value_at_rest_and_by_hand():
    x0, e = square_mesh.generate(1.0, 2)
    d = x0[e[:, 0]] - x0[e[:, 1]]
    l2 = np.einsum("ij,ij->i", d, d)
    # exact by construction: every coordinate is a multiple of 0.5, so each edge vector, its squared
    # length and the strain ||d||^2 / l^2 - 1 = 0 are exact in float64, whatever order or FMA is used
    assert MassSpringEnergy.val(x0, e, l2, 5.0) == 0.0
    # one spring of rest length 1 stretched to 2: 1/2 k l^2 (4/1 - 1)^2 = 4.5 k
    assert MassSpringEnergy.val([[0.0, 0.0], [2.0, 0.0]], [[0, 1]], [1.0], [3.0]) == pytest.approx(13.5)


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
    check_derivatives(lambda y: BarrierEnergy.val(y, *args), lambda y: BarrierEnergy.grad(y, *args),
                      lambda y: BarrierEnergy.hess(y, *args), x, eps)
    if where == "just_above_dhat":          # empty active set: the sum of nothing, 0.0 exactly
        assert BarrierEnergy.val(x, *args) == 0.0 and len(BarrierEnergy.hess(x, *args)[0]) == 0


def test_barrier_keyword_constants_and_value():
    x = np.array([[0.0, 0.005]])
    # w dhat kappa/2 (s - 1) ln s with s = 1/2
    expect = 0.25 * 0.01 * 1e5 / 2 * (-0.5) * np.log(0.5)
    assert BarrierEnergy.val(x, [0.0, 1.0], [0.0, 0.0], [0.25]) == pytest.approx(expect)
    assert BarrierEnergy.val(x, [0.0, 1.0], [0.0, 0.0], [0.25], kappa=2e5) == pytest.approx(2 * expect)
    assert BarrierEnergy.val(x, [0.0, 1.0], [0.0, 0.0], [0.25], dhat=0.004) == 0.0     # inactive: 0.0 exactly


def test_mu_lambda_is_mu_times_contact_force():
    rng = np.random.default_rng(3)
    d = np.array([0.002, 0.006, 0.02, 0.5])
    x, w = barrier_points(rng, d), np.full(4, 0.25)
    mu_lambda = BarrierEnergy.compute_mu_lambda(x, N_SLOPE, O_SLOPE, w, 0.3)
    force = -BarrierEnergy.grad(x, N_SLOPE, O_SLOPE, w)       # contact force on each node
    assert_close(mu_lambda, 0.3 * np.linalg.norm(force, axis=1), 1e-12, "mu*lambda")
    assert (mu_lambda[:2] > 0).all() and (mu_lambda[2:] == 0).all()     # beyond dhat: no force at all, 0.0 exactly


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
@pytest.mark.parametrize("where", ["static", "just_below_epsv", "just_above_epsv", "sliding", "zero"])
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

    def vel(y):
        return (y - x_n) / hhat

    # a step eps in x moves the tangential speed by eps/hhat: keep it far below the distance of
    # every speed to a branch point (eps_v, and 0 where |vbar| is not smooth)
    # at vbar = 0 exactly, grad contains |vbar| vbar (C1 only), so the FD error is ~ step/eps_v
    gap = min(np.abs(speeds - epsv).min(), speeds.min()) if where != "zero" else 1e-3 * epsv
    eps = 1e-4 * hhat * gap
    check_derivatives(lambda y: FrictionEnergy.val(vel(y), *args), lambda y: FrictionEnergy.grad(vel(y), *args),
                      lambda y: FrictionEnergy.hess(vel(y), *args, project_psd=False), x, eps)
    if where == "zero":
        assert not FrictionEnergy.grad(vel(x), *args).any()
    g = FrictionEnergy.grad(vel(x), *args)
    assert np.abs(g @ N_SLOPE).max() <= 1e-12 * max(np.abs(g).max(), 1.0), "friction acts along the slope only"


@pytest.mark.parametrize("where", ["static", "just_below_epsv", "just_above_epsv", "sliding", "zero"])
def test_val_grad_hess_kernels_are_the_three_kernels(where):
    """What the integrator calls (one pass per term, friction through `mollifier`) gives the numbers
    of the FD-checked kernels, for every term and on both sides of every branch."""
    rng = np.random.default_rng(3)

    def same(fused, val, grad, hess, upper=True):
        """upper: the fused kernel gives each node's 2x2 block as its entries (h00, h01, h11)."""
        assert fused[0] == pytest.approx(val, rel=1e-13, abs=1e-300)
        assert_close(fused[1], grad, 1e-13, "grad", atol=1e-13 * np.abs(grad).max(initial=0.0))
        assert np.array_equal(fused[2][0], hess[0])
        blocks = hess[1][[0, 0, 1], [0, 1, 1]] if upper else hess[1]
        assert fused[2][1].shape == blocks.shape
        assert_close(fused[2][1], blocks, 1e-13, "hess", atol=1e-13 * np.abs(blocks).max(initial=0.0))

    epsv, hhat = 1e-3, 0.01
    speeds = {"static": rng.uniform(0.05, 0.9, 6) * epsv, "just_below_epsv": epsv * (1 - 1e-12) * np.ones(6),
              "just_above_epsv": epsv * (1 + 1e-12) * np.ones(6), "sliding": rng.uniform(2, 500, 6) * epsv,
              "zero": np.zeros(6)}[where]
    x_n, x, mu_lambda = friction_setup(rng, speeds, epsv, hhat)
    args = ((x - x_n) / hhat, mu_lambda, hhat, N_SLOPE, epsv)
    same(FrictionEnergy.val_grad_hess_kernel(*args), FrictionEnergy.val_kernel(*args),
         FrictionEnergy.grad_kernel(*args), FrictionEnergy.hess_kernel(*args))
    stretch = {"static": 0.6, "just_below_epsv": 0.97, "just_above_epsv": 1.03, "sliding": 1.5, "zero": 1.0}[where]
    spring = spring_setup(1, stretch)
    value, (edges, forces), (edges, spring_H) = MassSpringEnergy.val_grad_hess_kernel(*spring)
    gradient = utils.BlockPattern.build(len(spring[0]), edges).sum_spring_forces(forces)
    same((value, gradient, (edges, MassSpringEnergy._edge_blocks(spring_H))), MassSpringEnergy.val_kernel(*spring),
         MassSpringEnergy.grad_kernel(*spring), MassSpringEnergy.hess_kernel(*spring), upper=False)
    dhat = 0.01
    d = rng.uniform(0.05, 3.0, 6) * dhat
    barrier = (barrier_points(rng, d), N_SLOPE, O_SLOPE, rng.uniform(0.1, 0.5, 6), dhat, 1e5)
    same(BarrierEnergy.val_grad_hess_kernel(*barrier), BarrierEnergy.val_kernel(*barrier),
         BarrierEnergy.grad_kernel(*barrier), BarrierEnergy.hess_kernel(*barrier))


def test_friction_energy_is_the_same_number_in_both_kernels():
    """val_kernel and val_grad_hess_kernel sum P_f to the same bits (the line search compares the
    two), in the static branch too, where f0 is a cubic in y/eps_v."""
    rng = np.random.default_rng(5)
    epsv, hhat = 1e-3, 0.01
    for i in range(300):
        speeds = rng.uniform(0, 1.2, 8) * epsv if i % 3 else rng.uniform(1.0, 300.0, 8) * epsv   # or all sliding
        x_n, x, mu_lambda = friction_setup(rng, speeds, epsv, hhat)
        args = ((x - x_n) / hhat, mu_lambda, hhat, N_SLOPE, epsv)
        # bit for bit: one code path (both call mollifier on the same y, then the same ml.dot)
        assert FrictionEnergy.val_grad_hess_kernel(*args)[0] == FrictionEnergy.val_kernel(*args)


def test_mollifier_is_f0_f1_over_y_and_f1_prime():
    epsv, hhat = 2e-3, 0.02
    y = np.concatenate([[0.0, 1e-300, np.nextafter(epsv, 0), epsv], np.linspace(0, 4 * epsv, 101)])
    with np.errstate(divide="raise", invalid="raise"):
        f0_of_y, f1y, f1p = FrictionEnergy.mollifier(y, epsv, hhat)
    assert_close(f0_of_y, FrictionEnergy.f0(y * hhat, epsv, hhat), 1e-14, "f0")
    assert_close(f1y, FrictionEnergy.f1_over_y(y, epsv), 1e-14, "f1/y")
    assert_close(f1p, FrictionEnergy.f1_prime(y, epsv), 1e-14, "f1'", atol=1e-14 / epsv)
    # every contact on one side of eps_v: mollifier computes that branch alone, with the same numbers;
    # bit for bit, as both sides are the same element-wise operations in the same order (y * hhat,
    # 1 / y, (2 - y/eps_v)/eps_v, ...), each rounded once by IEEE on every CPU (no BLAS, no reduction)
    sliding = np.linspace(epsv, 50 * epsv, 7)
    assert [a.tolist() for a in FrictionEnergy.mollifier(sliding, epsv, hhat)] == [
        FrictionEnergy.f0(sliding * hhat, epsv, hhat).tolist(), (1.0 / sliding).tolist(), [0.0] * 7]
    static = np.linspace(0.0, np.nextafter(epsv, 0), 7)
    f0_of_y, f1y, f1p = FrictionEnergy.mollifier(static, epsv, hhat)
    assert_close(f0_of_y, FrictionEnergy.f0(static * hhat, epsv, hhat), 1e-14, "f0 static")
    assert f1y.tolist() == FrictionEnergy.f1_over_y(static, epsv).tolist()
    assert f1p.tolist() == FrictionEnergy.f1_prime(static, epsv).tolist()


def test_tangent_spans_the_tangent_operator():
    """The kernels use T = I - n n^T = t t^T (a half-space in 2-D)."""
    for n in (N_SLOPE, np.array([0.0, 1.0]), np.array([-0.6, 0.8])):
        t = FrictionEnergy.tangent(n)
        assert_close(np.outer(t, t), np.eye(2) - np.outer(n, n), 1e-15, "t t^T")
        # t . n = n_y n_x - n_x n_y is zero in exact arithmetic; numpy's dot may fuse the two products
        # (an FMA kernel on AVX-512 CPUs), which leaves the rounding of one product, at most
        # eps/2 |n_x n_y| <= eps/4 for a unit n.
        assert abs(t @ n) <= 0.25 * np.finfo(float).eps


def test_friction_force_magnitude_is_mu_lambda_when_sliding():
    rng = np.random.default_rng(0)
    x_n, x, mu_lambda = friction_setup(rng, np.full(5, 0.7), 1e-3, 0.01)
    g = FrictionEnergy.grad((x - x_n) / 0.01, mu_lambda, 0.01, N_SLOPE)
    assert_close(np.linalg.norm(g, axis=1), mu_lambda, 1e-12, "|F| = mu lambda")


def test_friction_projection_is_identity_on_psd_bracket():
    """The bracket of Eq. 9.2.4 is PSD for the lecture's f1, so projecting it changes nothing beyond
    round-off of the terms it is made of, mu_lambda/hhat * f1(y)/y (in 2-D the sliding Hessian is
    exactly zero: both sides are then round-off of that size)."""
    rng = np.random.default_rng(1)
    for speeds in (np.zeros(6), np.full(6, 5e-4), np.full(6, 0.2)):
        x_n, x, mu_lambda = friction_setup(rng, speeds, 1e-3, 0.01)
        v = (x - x_n) / 0.01
        natural = mu_lambda.max() / 0.01 * FrictionEnergy.f1_over_y(speeds, 1e-3).max()
        assert_close(dense(FrictionEnergy.hess(v, mu_lambda, 0.01, N_SLOPE), x.size),
                     dense(FrictionEnergy.hess(v, mu_lambda, 0.01, N_SLOPE, project_psd=False), x.size),
                     1e-12, "projection of a PSD bracket", atol=1e-12 * natural)


# --- mollifier --------------------------------------------------------------------------------

def test_f0_derivative_is_f1():
    epsv, hhat = 1e-3, 0.01
    y = np.concatenate([np.linspace(0, 3 * epsv * hhat, 301), [epsv * hhat * (1 - 1e-4), epsv * hhat * (1 + 1e-4)]])
    step = 1e-4 * epsv * hhat
    y = y[np.abs(y - epsv * hhat) > 2 * step]               # the branch point itself: see continuity
    y = y[y > 2 * step]
    numeric = (FrictionEnergy.f0(y + step, epsv, hhat) - FrictionEnergy.f0(y - step, epsv, hhat)) / (2 * step)
    assert_close(numeric, FrictionEnergy.f1(y / hhat, epsv), 1e-7, "f0' = f1(y / hhat)")


def test_mollifier_continuity_at_branch_point():
    epsv, hhat = 2e-3, 0.02
    below, above = np.nextafter(epsv, 0), epsv
    assert FrictionEnergy.f0(below * hhat, epsv, hhat) == pytest.approx(FrictionEnergy.f0(above * hhat, epsv, hhat), rel=1e-12)
    assert FrictionEnergy.f1(below, epsv) == pytest.approx(FrictionEnergy.f1(above, epsv), rel=1e-12)
    assert FrictionEnergy.f1_over_y(below, epsv) == pytest.approx(FrictionEnergy.f1_over_y(above, epsv), rel=1e-12)
    assert FrictionEnergy.f_hess_term(below, epsv) == pytest.approx(FrictionEnergy.f_hess_term(above, epsv), rel=1e-12)
    assert FrictionEnergy.f0(0.0, epsv, hhat) == pytest.approx(epsv * hhat / 3)


def test_f1_prime_is_the_bracket_along_the_tangent():
    """f1'(y) = f_hess_term(y) y + f1(y)/y (Eq. 9.2.6 times y, plus Eq. 9.2.5), and the derivative of f1."""
    epsv = 1e-3
    y = np.linspace(1e-6, 3e-3, 400)
    assert_close(FrictionEnergy.f1_prime(y, epsv),
                 FrictionEnergy.f_hess_term(y, epsv) * y + FrictionEnergy.f1_over_y(y, epsv), 1e-12, "identity",
                 atol=1e-9 / epsv)
    step = 1e-9
    inside = np.abs(y - epsv) > 2 * step
    numeric = (FrictionEnergy.f1(y + step, epsv) - FrictionEnergy.f1(y - step, epsv)) / (2 * step)
    assert_close(FrictionEnergy.f1_prime(y, epsv)[inside], numeric[inside], 1e-6, "f1' = d f1 / dy")


def test_f1_over_y_finite_at_zero():
    with np.errstate(all="raise"):                      # any division by zero would raise here
        value = FrictionEnergy.f1_over_y(np.array([0.0, 1e-300, 1e-3, 5.0]), 1e-3)
        term = FrictionEnergy.f_hess_term(np.array([0.0, 5.0]), 1e-3)
        g = FrictionEnergy.grad(np.zeros((3, 2)), np.ones(3), 0.01, N_SLOPE)
        H = FrictionEnergy.hess(np.zeros((3, 2)), np.ones(3), 0.01, N_SLOPE)
    assert value[0] == pytest.approx(2 / 1e-3) and np.isfinite(value).all() and np.isfinite(term).all()
    assert not g.any() and np.isfinite(H[2]).all()


# --- the FD check itself catches wrong formulas --------------------------------------------------

@pytest.mark.parametrize("break_it", ["sign", "factor_2", "f1_over_y_factor_2", "hess_factor_2"])
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
                              lambda y: MassSpringEnergy.hess(y, e, l2, k, project_psd=False), x, 1e-6)
        return
    if break_it == "f1_over_y_factor_2":
        original = FrictionEnergy.f1_over_y
        monkeypatch.setattr(FrictionEnergy, "f1_over_y", lambda y, epsv: 2.0 * original(y, epsv))
    else:
        original = FrictionEnergy.f1_prime
        monkeypatch.setattr(FrictionEnergy, "f1_prime", lambda y, epsv: 2.0 * original(y, epsv))
    args = (mu_lambda, 0.01, N_SLOPE, 1e-3)
    with pytest.raises(AssertionError):
        check_derivatives(lambda y: FrictionEnergy.val((y - x_n) / 0.01, *args),
                          lambda y: FrictionEnergy.grad((y - x_n) / 0.01, *args),
                          lambda y: FrictionEnergy.hess((y - x_n) / 0.01, *args, project_psd=False), xf, 1e-9)
