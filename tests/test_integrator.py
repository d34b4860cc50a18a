"""The time step: golden trajectories, the lecture's friction behaviour, terms left out, failures."""
import dataclasses
import os

import numpy as np
import pytest

import BarrierEnergy
import FrictionEnergy
import simulator
import time_integrator
import utils

DATA = os.path.join(os.path.dirname(__file__), "data")


def golden_scene(name):
    """The scene a golden file was made with, built from the parameters stored in it."""
    g = np.load(os.path.join(DATA, f"{name}.npz"))
    scene = simulator.build_scene(
        n_seg=int(g["n_seg"]), mu=float(g["mu"]), k=float(g["k"]), h=float(g["h"]), v0=tuple(g["v0"]),
        slope=tuple(g["slope"]), tol=float(g["tol"]), side_len=float(g["side_len"]), rho=float(g["rho"]),
        slope_point=tuple(g["ground_o"]), dhat=float(g["dhat"]), kappa=float(g["kappa"]), epsv=float(g["epsv"]))
    return scene, g


@pytest.mark.parametrize("name", ["slope_mu0.11", "slope_mu0"])
def test_golden_trajectory(name):
    """Same discretization, same tolerance (1e-6): every node of every frame within 1e-4 m."""
    scene, g = golden_scene(name)
    assert np.array_equal(scene.x0, g["x"][0])
    errors = [np.abs(rec.x - g["x"][rec.index + 1]).max() for rec in simulator.simulate(scene, len(g["x"]) - 1)]
    assert max(errors) < 1e-4, f"worst frame {int(np.argmax(errors)) + 1}: {max(errors):.3e} m"


def contact_slip_speed(scene, x, v):
    """Largest tangential speed of the nodes in contact (d < dhat), or None without contact."""
    d = BarrierEnergy.distances(x, scene.n, scene.o)
    tangent = np.array([scene.n[1], -scene.n[0]])
    touching = d < scene.dhat
    return float(np.abs(v[touching] @ tangent).max()) if touching.any() else None


def stop_step(scene, steps):
    """First step from which the square never slips again: every later step has contact and every
    contact node's tangential speed below eps_v, the mollifier's static regime. None if it never stops.
    (The centre of mass is no good here: a stuck, soft square keeps shearing elastically.)"""
    slipping = [s is None or s >= scene.epsv
                for s in (contact_slip_speed(scene, r.x, r.v) for r in simulator.simulate(scene, steps))]
    last = max((i for i, slip in enumerate(slipping) if slip), default=-1)
    return None if last == len(slipping) - 1 else last + 1


@pytest.mark.slow
def test_figure_10_2_1_stick_and_slide():
    """Lecture: mu = 0.1 keeps sliding, mu = 0.11 slides a while then stops, mu = 0.2 stops earlier.
    Measured at the lecture's tolerance, mu = 0.11 stops at about 5.5 s (the rigid-block estimate:
    0.43 m/s after the impact, decelerating at g (mu cos - sin) = 0.098 m/s^2, stops near 5.4 s),
    so 7 s are simulated instead of 5."""
    steps = 700
    stops = {mu: stop_step(simulator.build_scene(mu=mu), steps) for mu in (0.1, 0.11, 0.2)}
    assert stops[0.1] is None
    assert stops[0.11] is not None and stops[0.11] > 100      # it slid for a while first
    assert stops[0.2] is not None and stops[0.2] < stops[0.11]


class CallCounter:
    """Replaces every public function of a module by a counting wrapper (undone by monkeypatch)."""

    def __init__(self, monkeypatch, module, names):
        self.calls = {}
        for name in names:
            original = getattr(module, name)

            def wrapper(*args, _name=name, _f=original, **kw):
                self.calls[_name] = self.calls.get(_name, 0) + 1
                return _f(*args, **kw)
            monkeypatch.setattr(module, name, wrapper)


def run_steps(scene, steps):
    for rec in simulator.simulate(scene, steps):
        pass
    return rec


KERNELS = ["val_kernel", "grad_kernel", "hess_kernel", "val_grad_hess_kernel"]
# what the integrator calls: val with grad and hess at a line search's first trial, val alone at
# halved ones (rare, so a short run may have none)
USED_KERNELS = {"val_kernel", "val_grad_hess_kernel"}
ALWAYS_USED = {"val_grad_hess_kernel"}


def test_mu_zero_calls_no_friction(monkeypatch):
    counter = CallCounter(monkeypatch, FrictionEnergy,
                          ["val", "grad", "hess", "f0", "f1_over_y", "f_hess_term"] + KERNELS)
    barrier = CallCounter(monkeypatch, BarrierEnergy, ["compute_mu_lambda", "compute_mu_lambda_kernel"])
    scene = simulator.build_scene(mu=0.0)
    assert "friction" not in scene.terms
    closest = min(rec.report.min_distance for rec in simulator.simulate(scene, 60))
    assert closest < scene.dhat                                 # contact happened (impact ~ step 30)
    assert counter.calls == {} and barrier.calls == {}
    # the control: with mu the integrator calls the kernels (the checked public functions are for
    # notebooks; the scene was validated once when it was built)
    counter = CallCounter(monkeypatch, FrictionEnergy, ["val", "grad", "hess"] + KERNELS)
    barrier = CallCounter(monkeypatch, BarrierEnergy, ["compute_mu_lambda", "compute_mu_lambda_kernel"])
    run_steps(simulator.build_scene(mu=0.11), 60)
    # (grad_kernel: the friction work of the step, reported in StepReport.friction_work, should the
    # last evaluation not be at x^{n+1}; it always is here)
    assert ALWAYS_USED <= set(counter.calls) <= USED_KERNELS | {"grad_kernel"}
    assert set(barrier.calls) == {"compute_mu_lambda_kernel"}


BARRIER_API = ["val", "grad", "hess", "init_step_size", "compute_mu_lambda", "distances",
               "init_step_size_kernel", "compute_mu_lambda_kernel"] + KERNELS


def test_no_slope_calls_no_barrier_or_ccd(monkeypatch):
    counter = CallCounter(monkeypatch, BarrierEnergy, BARRIER_API)
    friction = CallCounter(monkeypatch, FrictionEnergy, ["val", "grad", "hess"] + KERNELS)
    scene = simulator.build_scene(slope=None, mu=0.5)
    assert scene.terms == ("inertia", "spring", "gravity")
    run_steps(scene, 20)
    assert counter.calls == {} and friction.calls == {}
    no_gravity = simulator.build_scene(slope=None, gravity=(0.0, 0.0))
    assert no_gravity.terms == ("inertia", "spring")
    # the control: with a slope the barrier's kernels and the CCD are called
    counter = CallCounter(monkeypatch, BarrierEnergy, BARRIER_API)
    run_steps(simulator.build_scene(mu=0.0), 40)
    assert ALWAYS_USED | {"init_step_size_kernel", "distances"} <= set(counter.calls)
    assert set(counter.calls) <= USED_KERNELS | {"init_step_size_kernel", "distances"}


def test_barrier_and_friction_see_only_nodes_within_dhat(monkeypatch):
    """Every barrier evaluation touches exactly the nodes with d < dhat at the x it is given, and every
    friction evaluation exactly the nodes with d < dhat at x^n (where mu*lambda^n > 0): the integrator
    hands the friction kernels those nodes only, and every one of them is in contact."""
    barrier_sets, friction_sets = [], []
    active, contacts = BarrierEnergy._active, FrictionEnergy._contacts

    def spy_active(x, n, o, dhat):
        out = active(x, n, o, dhat)
        barrier_sets.append((set(out[0].tolist()), set(np.flatnonzero(BarrierEnergy.distances(x, n, o) < dhat).tolist())))
        return out

    def spy_contacts(v, mu_lambda, n):
        out = contacts(v, mu_lambda, n)
        assert len(out[0]) == len(v)                # nothing passed in that is out of contact
        friction_sets.append(len(v))
        return out
    monkeypatch.setattr(BarrierEnergy, "_active", spy_active)
    monkeypatch.setattr(FrictionEnergy, "_contacts", spy_contacts)
    scene = simulator.build_scene()
    x = scene.x0
    for rec in simulator.simulate(scene, 60):
        within = set(np.flatnonzero(BarrierEnergy.distances(x, scene.n, scene.o) < scene.dhat).tolist())
        assert all(seen == len(within) for seen in friction_sets), f"step {rec.index}"
        friction_sets.clear()
        x = rec.x
    assert all(seen == expected for seen, expected in barrier_sets)
    assert max(len(seen) for seen, _ in barrier_sets) == scene.n_seg + 1      # the bottom row, not all 25


def free_fall_scene(h, **kw):
    return simulator.build_scene(slope=None, h=h, **kw)


@pytest.mark.parametrize("h", [1e-4, 1e-3, 1e-2])
def test_free_fall_matches_implicit_euler_at_any_h(h):
    """A free square is rigid, so implicit Euler gives v_n = n h g and y_n = y0 + g h^2 n(n+1)/2
    exactly, whatever h is. At h = 1e-4, h |g| = 1e-3 is below the default tol of 1e-2 m/s: the
    lecture's loop, which tests before it iterates, would leave the square hanging in the air."""
    scene = free_fall_scene(h)
    steps = int(round(0.05 / h))
    rec = run_steps(scene, steps)
    expected_y = scene.x0[:, 1] - 9.81 * h * h * steps * (steps + 1) / 2
    assert np.allclose(rec.x[:, 1], expected_y, atol=1e-9) and np.allclose(rec.x[:, 0], scene.x0[:, 0], atol=1e-12)
    assert np.allclose(rec.v[:, 1], -9.81 * h * steps, rtol=1e-9)


@pytest.mark.slow
def test_small_time_step_slides_like_large_one():
    """h = 1e-4 on the slope (mu = 0.05 < tan theta): the square drops 5 cm, lands and slides down
    the slope as it does at h = 1e-3: same centre of mass within 1 cm after 0.3 s."""
    coms = {}
    for h in (1e-3, 1e-4):
        scene = simulator.build_scene(h=h, mu=0.05, center=(0.0, -0.45))
        rec = run_steps(scene, int(round(0.3 / h)))
        coms[h] = np.average(rec.x, axis=0, weights=scene.m)
    assert np.abs(coms[1e-3] - coms[1e-4]).max() < 1e-2
    assert coms[1e-4][1] < -0.45 - 0.04 and coms[1e-4][0] > 0.01     # it fell, then slid downhill


def test_step_changes_nothing_it_is_given():
    scene = simulator.build_scene()
    x, v = scene.x0.copy(), scene.v0.copy()
    x_before, v_before = x.copy(), v.copy()
    x1, v1, report = time_integrator.step(scene, x, v)
    assert np.array_equal(x, x_before) and np.array_equal(v, v_before)
    assert not scene.x0.flags.writeable and not scene.m.flags.writeable
    assert report.newton_iterations == 1 and report.residual < scene.tol and report.alphas == [1.0]
    expected = np.min(BarrierEnergy.distances(x1, scene.n, scene.o))
    assert report.min_distance == expected and 0.4 < expected < 0.5


def test_line_search_and_ccd_keep_nodes_off_the_slope():
    """At 30 m/s into the slope the full Newton step would cross it: CCD cuts the step (alpha < 1)
    and every node stays above the slope."""
    scene = simulator.build_scene(v0=(0.0, -30.0), center=(0.0, 0.0))
    alphas = []
    for rec in simulator.simulate(scene, 30):
        assert rec.report.min_distance > 0.0
        alphas += rec.report.alphas
    assert min(alphas) < 0.5


def test_newton_cap_raises_specific_error():
    scene = simulator.build_scene(max_newton_iterations=1, tol=1e-9)
    with pytest.raises(time_integrator.NewtonNotConverged) as info:
        run_steps(scene, 80)
    assert info.value.step >= 1 and info.value.figures["iterations"] == 1
    assert "step" in str(info.value) and "residual" in str(info.value)


def test_line_search_cap_raises_specific_error(monkeypatch):
    scene = simulator.build_scene(max_halvings=3)
    # a search direction pointing uphill can never decrease E: the search must give up, not spin
    original = time_integrator.NewtonSystem._solve

    def uphill(self, H, g, iteration):
        p, residual = original(self, H, g, iteration)
        return -p, residual
    monkeypatch.setattr(time_integrator.NewtonSystem, "_solve", uphill)
    with pytest.raises(time_integrator.LineSearchFailed) as info:
        time_integrator.step(scene, scene.x0, scene.v0, step_index=7)
    assert info.value.step == 7 and info.value.figures["halvings"] == 3
    assert "step 7" in str(info.value)


def test_fully_implicit_friction_updates_and_converges():
    lagged = simulator.build_scene(mu=0.11, tol=1e-6)
    implicit = simulator.build_scene(mu=0.11, tol=1e-6, friction_updates=20)
    x, v = lagged.x0, lagged.v0
    for rec in simulator.simulate(lagged, 45):          # into the sliding contact
        x, v = rec.x, rec.v
    _, _, r_lag = time_integrator.step(lagged, x, v)
    x_imp, _, r_imp = time_integrator.step(implicit, x, v)
    assert r_lag.friction_iterations == 1 and r_lag.friction_converged
    assert r_imp.friction_iterations > 1 and r_imp.friction_converged
    # at the fixed point the friction force uses mu*lambda of the end of the step
    ip = time_integrator.IncrementalPotential(
        implicit, x, x + implicit.h * v, BarrierEnergy.compute_mu_lambda(
            x_imp, implicit.n, implicit.o, implicit.contact_area, implicit.mu))
    assert np.abs(ip.search_direction(x_imp)).max() / implicit.h <= implicit.tol


@pytest.mark.parametrize("kwargs", [dict(), dict(mu=0.5), dict(k=1e6, mu=0.2)])
def test_energy_budget_friction_work(kwargs):
    """Implicit Euler with convex potentials: E^{n+1} - E^n <= W_f^n, the work of friction over the
    step (from the step's optimality condition and convexity; the rest is numerical dissipation). So
    the mechanical energy lost since the start is at least what friction took out, and W_f <= 0.
    Compressed springs are not convex, so for this scene the bound is an empirical one that the
    argument makes plausible; allowed slack: one step's Newton error, M tol (|v| + |dv| + tol)."""
    scene = simulator.build_scene(**kwargs)
    E_prev = simulator.energies(scene, scene.x0, scene.v0)["total"]
    v_prev = scene.v0
    total_work = 0.0
    for rec in simulator.simulate(scene, 150):
        work = rec.report.friction_work
        assert work <= 0.0
        total_work += work
        E = simulator.energies(scene, rec.x, rec.v)["total"]
        slack = scene.m.sum() * scene.tol * (np.abs(rec.v).max() + np.abs(rec.v - v_prev).max() + scene.tol)
        assert E - E_prev <= work + slack, f"step {rec.index}"
        E_prev, v_prev = E, rec.v
    assert total_work < -1.0                       # friction did take energy out while sliding


def test_fixed_point_checks_its_last_solve():
    """Algorithm 5 with a cap of one update: the result of that update is checked against the
    mu*lambda it implies before the step reports (non-)convergence, and the report agrees with an
    independent check of the fixed point. At tol = 1e-6 one update is sometimes enough, sometimes not."""
    scene = simulator.build_scene(mu=0.11, friction_updates=1, tol=1e-6)
    x, v = scene.x0, scene.v0
    outcomes = []
    for rec in simulator.simulate(scene, 45):
        r = rec.report
        ip = time_integrator.IncrementalPotential(scene, x, x + scene.h * v, BarrierEnergy.compute_mu_lambda(
            rec.x, scene.n, scene.o, scene.contact_area, scene.mu))
        at_fixed_point = np.abs(ip.search_direction(rec.x)).max() / scene.h <= scene.tol
        assert r.friction_converged == at_fixed_point, f"step {rec.index}"
        assert r.friction_iterations in (1, 2)
        outcomes.append(r.friction_converged)
        x, v = rec.x, rec.v
    assert True in outcomes and False in outcomes


def test_banded_and_superlu_give_the_same_newton_direction():
    """The integrator picks banded Cholesky for the lecture's mesh; SuperLU must agree with it."""
    banded = simulator.build_scene(mu=0.2)
    assert banded.pattern.solver == "banded"
    superlu = dataclasses.replace(banded, pattern=utils.BlockPattern.build(len(banded.x0), banded.e, "superlu"))
    for rec in simulator.simulate(banded, 40):            # into the sliding contact
        x, v = rec.x, rec.v
    directions = []
    for scene in (banded, superlu):
        mu_lambda = BarrierEnergy.compute_mu_lambda(x, scene.n, scene.o, scene.contact_area, scene.mu)
        assert (mu_lambda > 0).any()
        ip = time_integrator.IncrementalPotential(scene, x, x + scene.h * v, mu_lambda)
        directions.append(ip.search_direction(x + 1e-4))
    assert np.allclose(directions[0], directions[1], rtol=0, atol=1e-10 * np.abs(directions[1]).max())
    x_b, _, _ = time_integrator.step(banded, x, v)
    x_s, _, _ = time_integrator.step(superlu, x, v)
    assert np.abs(x_b - x_s).max() < 1e-9



def run_positions(scene, steps):
    """Positions after every step, and the reports."""
    x, v, xs, reports = scene.x0, scene.v0, [], []
    for i in range(steps):
        x, v, report = time_integrator.step(scene, x, v, i)
        xs.append(x)
        reports.append(report)
    return np.array(xs), reports


def test_convergence_shown_without_a_factorization_is_the_lecture_s_convergence(monkeypatch):
    """NewtonSystem.check stops Newton without factoring H only where ||H^-1 grad E||_inf / h <= tol
    holds for the direction the lecture would solve for, and the bound it reports is above that
    residual: so the trajectory is the one a factorization at every check gives, to the bit."""
    monkeypatch.setattr(time_integrator, "CG_MIN_BANDWIDTH", 0)     # the CG proofs at every size
    scene = simulator.build_scene(n_seg=8, max_newton_iterations=1000)
    shown, original_check, original_cg = [], time_integrator.NewtonSystem.check, time_integrator.NewtonSystem._cg_bound
    by_cg = []

    def spy_check(self, x, iteration):
        p, residual = original_check(self, x, iteration)
        if p is None:
            shown.append((np.abs(self.ip.search_direction(x)).max() / scene.h, residual))
        return p, residual

    def spy_cg(self, H, g):
        products.clear()
        bound = original_cg(self, H, g)
        by_cg.append(bound is not None)
        if bound is not None:
            products_to_success.append(len(products))
        return bound

    class CountedProducts:                  # H's CSC form, counting the CG proof's products with it
        def __init__(self, A):
            self.A = A

        def __matmul__(self, d):
            products.append(1)
            return self.A @ d
    products, products_to_success, original_to_csc = [], [], utils.BlockPattern.to_csc
    monkeypatch.setattr(utils.BlockPattern, "to_csc", lambda self, upper: CountedProducts(original_to_csc(self, upper)))
    monkeypatch.setattr(time_integrator.NewtonSystem, "check", spy_check)
    monkeypatch.setattr(time_integrator.NewtonSystem, "_cg_bound", spy_cg)
    xs, reports = run_positions(scene, 120)                 # the fall, the impact (~ step 30), sliding
    direct, bound = np.array(shown).T
    assert len(shown) > 60 and sum(by_cg) > 10 and len(by_cg) - sum(by_cg) > 10   # both ways, and CG failing too
    assert 1 in products_to_success and max(products_to_success) > 1    # shown by q = z, and after iterating
    assert (direct <= bound * (1 + 1e-12)).all() and (bound <= scene.tol).all()
    factorizations = sum(r.factorizations for r in reports)
    assert factorizations < sum(r.newton_iterations for r in reports) + len(reports)

    # the control: a factorization at every check (as the lecture does) gives the same positions
    monkeypatch.setattr(time_integrator.NewtonSystem, "check", time_integrator.NewtonSystem.direction)
    xs_direct, reports_direct = run_positions(scene, 120)
    assert np.array_equal(xs, xs_direct)
    assert [r.newton_iterations for r in reports] == [r.newton_iterations for r in reports_direct]
    assert sum(r.factorizations for r in reports_direct) == factorizations + len(shown)


def test_a_step_started_from_the_previous_report_is_the_same_step():
    """simulate hands each step the previous report, whose end_terms (the terms of x alone at x^n)
    spare one evaluation: the positions are bit for bit those of steps started from scratch, and
    terms from another scene or other positions are not used."""
    scene = simulator.build_scene(n_seg=6)
    handed = np.array([rec.x for rec in simulator.simulate(scene, 80)])    # impact at ~ step 30
    alone, _ = run_positions(scene, 80)
    assert np.array_equal(handed, alone)

    x, v, report = scene.x0, scene.v0, None
    for i in range(40):
        x, v, report = time_integrator.step(scene, x, v, i, report)
    assert report.end_terms is not None and np.array_equal(report.end_terms.x, x)
    x_fresh, _, _ = time_integrator.step(scene, x, v, 40)
    moved = x.copy()
    moved[0, 0] += 1e-3                                         # other positions: evaluated anew
    assert np.array_equal(time_integrator.step(scene, moved, v, 40, report)[0],
                          time_integrator.step(scene, moved, v, 40)[0])
    other = simulator.build_scene(n_seg=6, k=3e4)               # another scene: not used either
    assert np.array_equal(time_integrator.step(other, x, v, 40, report)[0],
                          time_integrator.step(other, x, v, 40)[0])
    assert np.array_equal(time_integrator.step(scene, x, v, 40, report)[0], x_fresh)


def test_a_node_below_the_slope_is_refused_with_or_without_friction():
    """x^n under the slope is bad input: a ValueError naming the node, with mu = 0 (no friction to
    check it) as with friction; and the IP has no derivatives there (it never answers with another
    point's)."""
    for mu in (0.0, 0.11):
        scene = simulator.build_scene(mu=mu)
        with pytest.raises(ValueError, match="node .* distance"):
            time_integrator.step(scene, scene.x0 + [0.0, -0.6], scene.v0)
    scene = simulator.build_scene(mu=0.0)
    ip = time_integrator.IncrementalPotential(scene, scene.x0, scene.x0, None)
    ip.search_direction(scene.x0)
    below = scene.x0 + [0.0, -0.6]
    assert ip.evaluate(below) == np.inf and ip.val(below) == np.inf      # the line-search filter
    with pytest.raises(ValueError, match="distance"):
        ip.search_direction(below)


def test_evaluate_sums_exactly_what_val_sums():
    """The line search compares evaluate (first trials) with val (halved ones): the same numbers to
    the bit, also in friction's static branch (speeds below eps_v) and at the barrier."""
    scene = simulator.build_scene(mu=0.5, n_seg=4)
    x, v = scene.x0, scene.v0
    for i in range(45):                                         # on the slope, in contact
        x, v, _ = time_integrator.step(scene, x, v, i)
    mu_lambda = time_integrator._mu_lambda(scene, x)
    assert (mu_lambda > 0).sum() >= 3
    ip = time_integrator.IncrementalPotential(scene, x, x + scene.h * v, mu_lambda)
    rng = np.random.default_rng(0)
    for scale in (1e-9, 1e-7, 1e-6, 1e-5, 1e-3):               # contact speeds ~ scale/h vs eps_v
        for _ in range(400):
            y = x + scale * rng.normal(size=x.shape)
            assert ip.evaluate(y) == ip.val(y)


def test_handed_on_terms_are_taken_once():
    scene = simulator.build_scene(n_seg=4)
    _, _, first = time_integrator.step(scene, scene.x0, scene.v0, 0)
    assert first.end_terms is not None
    x, v, _ = time_integrator.step(scene, scene.x0, scene.v0, 0)
    time_integrator.step(scene, x, v, 1, first)
    assert first.end_terms is None            # a list of kept reports holds no copies of H
