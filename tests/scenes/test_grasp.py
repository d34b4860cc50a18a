"""The grasp: a settled start, the prescribed lift, and the slip against the closed forms (held,
it creeps at u*; dropped, it slips at (g + a) - 2 mu N / m; in between, it is held before the
lift, creeping at u* (IPC's friction has no static friction), but slips while the lift
accelerates)."""
import math
import warnings

import numpy as np
import pytest

import FrictionEnergy
import closed_forms
from helpers.runs import replaying
from scenes import grasp

G = 9.81


def squeeze_for(ratio, p=grasp.GRASP):
    """N with m g / (2 mu N) = ratio."""
    return p["mass"] * G / (2 * p["mu"] * ratio)


def finger_forces(scene, x):
    """Each finger's normal force on the block (N), the sum of its lambda_i."""
    return scene.contact.lambdas(scene, x).sum(axis=1)


def test_the_block_starts_settled_at_the_gap_where_each_finger_carries_n():
    """Round-off: brentq to xtol 1e-15 m on a force of slope ~1e4 N/m per node: 1e-10 N."""
    scene = grasp.build_grasp_scene()
    assert finger_forces(scene, scene.x0) == pytest.approx([2.616, 2.616], abs=1e-9)
    gap = scene.contact.distances(scene.x0).min()
    assert 0.6 * scene.dhat < gap < 0.8 * scene.dhat    # kappa 100: about 0.7 dhat (the issue)


def test_the_lift_is_prescribed_and_the_fingers_press_with_n(shared_runs):
    """The fingers' rows rise by Fingers.offset(t) exactly (a Dirichlet condition: Newton never
    moves them along the lift), and each finger's force stays N; a held block, creeping in the
    lift's frame at u* (0.29 to 0.30 mm/s), sees N to 1e-5 relative (the fingers' own inertia,
    m_f a, is normal to the lift, so nothing else enters). The steps are the session's shared run
    (helpers/runs.py: simulate's, bit for bit), the grasp's pictures' too."""
    scene = grasp.build_grasp_scene(squeeze=4.0)
    for rec in shared_runs.simulate(scene, 60):  # 0.3 s: still, then accelerating
        assert (rec.x[-2:, 1] == scene.contact.offset(rec.t)).all()
    assert finger_forces(scene, rec.x) == pytest.approx([4.0, 4.0], rel=1e-5)


def test_a_held_grasp_creeps_at_u_star_in_the_steady_lift(monkeypatch, shared_runs):
    """m g / (2 mu N) = 0.75: u* = eps_v (1 - sqrt(0.25)) = 0.50 mm/s, measured over the steady
    lift (from 0.5 s) at the scene's tol 1e-5 = u* / 50, which reads it about 0.5 tol / u* = 1 %
    low (measured: 0.497 mm/s); 10 % as the issue asks. The steps are the session's shared run of
    this grasp (helpers/runs.py: simulate's, bit for bit), the window's tests' too."""
    monkeypatch.setattr(closed_forms, "simulator", replaying(shared_runs))
    scene = grasp.build_grasp_scene(squeeze=squeeze_for(0.75))
    u_star = grasp.creep_speed(scene)
    assert u_star == pytest.approx(5e-4, rel=1e-9) and grasp.holds(scene)
    t, slip = closed_forms.measured(scene, 0.9, grasp.slip)
    assert grasp.fitted_rate(t, slip, 0.6, 0.9) == pytest.approx(u_star, rel=0.1)
    assert slip.max() < 1e-3                            # held: under a mm in all


def test_a_dropped_grasp_slips_at_the_closed_form_s_acceleration():
    """m g / (2 mu N) = 1.25: (g + a) - 2 mu N / m = 2.462 m/s^2 while the lift accelerates, then
    g - 2 mu N / m = 1.962 (measured to 1e-8: friction is mu N exactly above eps_v); 5 %."""
    scene = grasp.build_grasp_scene(squeeze=squeeze_for(1.25))
    a = scene.contact.lift_accel
    assert not grasp.holds(scene)
    t, slip = closed_forms.measured(scene, 0.7, grasp.slip)
    during = grasp.fitted_rate(t, slip, 0.15, 0.45, order=2)
    after = grasp.fitted_rate(t, slip, 0.55, 0.7, order=2)
    assert during == pytest.approx(grasp.slip_acceleration(scene, a), rel=0.05)
    assert after == pytest.approx(grasp.slip_acceleration(scene), rel=0.05)
    assert grasp.slip_acceleration(scene, a) == pytest.approx(2.462, abs=1e-9)


def test_a_grasp_held_creeping_before_the_lift_slips_while_it_accelerates(monkeypatch,
                                                                          shared_runs):
    """2 mu N = 2.0 N between m g = 1.962 and m (g + a) = 2.062: held before the lift (creeping
    at u* = 0.86 mm/s), slipping at (g + a) - 2 mu N / m = 0.31 m/s^2 while it accelerates (5 %),
    as far as the rigid block's Coulomb slip says by then (the creep before it: 0.09 mm; 5 %).
    The steps are the session's shared run (helpers/runs.py), the grasp's pictures' too."""
    monkeypatch.setattr(closed_forms, "simulator", replaying(shared_runs))
    scene = grasp.build_grasp_scene(squeeze=2.0)
    a = scene.contact.lift_accel
    assert grasp.load_ratio(scene) < 1.0 < grasp.load_ratio(scene, a)
    t, slip = closed_forms.measured(scene, 0.5, grasp.slip)
    before = grasp.fitted_rate(t, slip, 0.05, 0.1)
    assert before == pytest.approx(grasp.creep_speed(scene), rel=0.1)
    during = grasp.fitted_rate(t, slip, 0.2, 0.5, order=2)
    assert during == pytest.approx(grasp.slip_acceleration(scene, a), rel=0.05)
    assert slip[-1] == pytest.approx(grasp.coulomb_slip(scene, 0.5), rel=0.05)


def test_the_coulomb_slip_through_the_lift_s_phases():
    """By hand, a 0.5, V 0.2 (accelerating 0.1 s to 0.5 s): 2 mu N / m = 10 m/s^2 grips until the
    lift, slips at 0.31 m/s^2 for 0.4 s (0.0248 m, at 0.124 m/s), then sticks again at -0.19 m/s^2
    after 0.124 / 0.19 s more (0.124^2 / 0.38 m further)."""
    scene = grasp.build_grasp_scene(squeeze=2.0)
    assert grasp.coulomb_slip(scene, 0.1) == 0.0
    assert grasp.coulomb_slip(scene, 0.5) == pytest.approx(0.31 * 0.4 ** 2 / 2)
    total = 0.31 * 0.4 ** 2 / 2 + 0.124 ** 2 / 0.38
    assert grasp.coulomb_slip(scene, 10.0) == pytest.approx(total)
    assert grasp.coulomb_slip(scene, math.inf) == pytest.approx(total)
    held = grasp.build_grasp_scene(squeeze=4.0)
    assert grasp.coulomb_slip(held, 10.0) == 0.0


def test_the_coulomb_block_drops_when_its_slip_reaches_the_pads():
    """By hand, as above (squeeze 2): 0.0248 m at 0.124 m/s as the steady lift begins, then
    0.0252 m more at -0.19 m/s^2: T = 0.0504 / (0.124 + sqrt(0.124^2 - 0.38 * 0.0252)) = 0.2518 s.
    Squeeze 1.5696 (2 mu N / m = 7.848): slips from t = 0 at 1.962 m/s^2 (0.00981 m at 0.1962 m/s
    by the lift), then at 2.462: T = 0.08038 / (0.1962 + sqrt(0.1962^2 + 4.924 * 0.04019))."""
    slows, slips = grasp.build_grasp_scene(squeeze=2.0), grasp.build_grasp_scene(squeeze=1.5696)
    assert grasp.drop_slip(slows) == pytest.approx(0.05)
    for scene, exact in [(slows, 0.5 + 0.0504 / (0.124 + math.sqrt(0.124 ** 2 - 0.38 * 0.0252))),
                         (slips, 0.1 + 0.08038 / (0.1962 + math.sqrt(0.1962 ** 2
                                                                      + 4.924 * 0.04019)))]:
        t_drop = grasp.coulomb_drop(scene)
        assert t_drop == pytest.approx(exact, rel=1e-9)
        assert grasp.coulomb_slip(scene, t_drop) == pytest.approx(0.05, rel=1e-12)
    assert grasp.coulomb_drop(grasp.build_grasp_scene(squeeze=4.0)) == math.inf


def test_a_coulomb_block_balanced_exactly_slips_on_without_a_warning():
    """2 mu N / m = 8 m/s^2 = g exactly: no slip before the lift, 0.5 m/s^2 in it (0.04 m at
    0.2 m/s by t = 0.5 s), then on at 0.2 m/s: past the pads' 0.05 m at 0.55 s, 1.94 m by 10 s.
    The steady lift's end, inf * 0, warns nowhere (on main: numpy's RuntimeWarning)."""
    scene = grasp.build_grasp_scene(squeeze=2.0, mass=0.25, gravity=(0.0, -8.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert grasp.slip_acceleration(scene) == 0.0
        assert grasp.coulomb_drop(scene) == pytest.approx(0.55, rel=1e-12)
        assert grasp.coulomb_slip(scene, 10.0) == pytest.approx(1.94, rel=1e-12)


@pytest.mark.parametrize("name, value, words", [
    ("squeeze", 0.0, "squeeze must be a finite number > 0"),
    ("lift_accel", -1.0, "lift_accel must be a finite number > 0"),
    ("mu", math.nan, "mu must be a finite number >= 0"),
    ("gravity", (1.0, -9.81), "gravity must point down the fingers"),
])
def test_a_bad_parameter_is_refused_by_name(name, value, words):
    with pytest.raises(ValueError, match=f"^{words}"):
        grasp.build_grasp_scene(**{name: value})


def test_friction_off_leaves_no_friction_term():
    scene = grasp.build_grasp_scene(mu=0.0)
    assert "friction" not in scene.terms and np.isnan(grasp.creep_speed(scene))


def test_friction_against_the_fingers_is_the_sum_of_each_finger_s():
    """The fingers share one tangent (the lift's), so friction against them is P_f with mu*lambda
    summed over them (as friction_update sums Fingers.lambdas) and either's normal: the sum of
    each finger's own P_f, value and gradient, to round-off (one addition of a zero per node)."""
    scene = grasp.build_grasp_scene()
    rng = np.random.default_rng(5)
    v = rng.uniform(-2e-3, 2e-3, scene.x0.shape)        # both sides of eps_v = 1e-3
    each = scene.contact.lambdas(scene, scene.x0, scene.mu)
    assert (np.count_nonzero(each, axis=0) <= 1).all() and each.any()   # one finger a node
    summed = each.sum(axis=0)
    for energy in (FrictionEnergy.val, FrictionEnergy.grad):
        together = energy(v, summed, scene.h, scene.friction_n, scene.epsv)
        apart = sum(energy(v, row, scene.h, n_f, scene.epsv)
                    for row, n_f in zip(each, scene.contact.n))
        assert np.allclose(together, apart, rtol=1e-12, atol=0.0)
