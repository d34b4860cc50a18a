"""The time step: golden trajectories, the lecture's friction behaviour, terms left out,
failures."""
import dataclasses
import os

import numpy as np
import pytest

import BarrierEnergy
import FrictionEnergy
import simulator
import time_integrator
import utils
from analysis import diagnostics
from helpers import ROOT
from helpers.fd import assert_close, dense, fd_gradient

DATA = os.path.join(ROOT, "tests", "data")


def golden_scene(name):
    """The scene a golden file was made with, built from the parameters stored in it."""
    g = np.load(os.path.join(DATA, f"{name}.npz"))
    numbers = ("mu", "k", "h", "tol", "side_len", "rho", "dhat", "kappa", "epsv")
    params = {name: float(g[name]) for name in numbers}
    scene = simulator.build_scene(n_seg=int(g["n_seg"]), v0=tuple(g["v0"]), slope=tuple(g["slope"]),
                                  slope_point=tuple(g["ground_o"]), **params)
    return scene, g


@pytest.mark.parametrize("name", ["slope_mu0.11", "slope_mu0"])
def test_golden_trajectory(name):
    """Same discretization, same tolerance (1e-6): every node of every frame within 1e-4 m."""
    scene, g = golden_scene(name)
    assert np.array_equal(scene.x0, g["x"][0])
    records = simulator.simulate(scene, len(g["x"]) - 1)
    errors = [np.abs(rec.x - g["x"][rec.index + 1]).max() for rec in records]
    assert max(errors) < 1e-4, f"worst frame {int(np.argmax(errors)) + 1}: {max(errors):.3e} m"


def contact_slip_speed(scene, x, v):
    """Largest tangential speed of the nodes in contact (d < dhat), or None without contact."""
    d = BarrierEnergy.distances(x, scene.n, scene.o)
    tangent = np.array([scene.n[1], -scene.n[0]])
    touching = d < scene.dhat
    return float(np.abs(v[touching] @ tangent).max()) if touching.any() else None


def stop_step(scene, records):
    """First of the `records` (scene's StepRecords) from which the square never slips again: every
    later step has contact and every contact node's tangential speed below eps_v, the mollifier's
    static regime. None if it never stops. (Not the centre of mass: a stuck square still shears.)"""
    speeds = (contact_slip_speed(scene, r.x, r.v) for r in records)
    slipping = [s is None or s >= scene.epsv for s in speeds]
    last = max((i for i, slip in enumerate(slipping) if slip), default=-1)
    return None if last == len(slipping) - 1 else last + 1


@pytest.mark.slow
def test_figure_10_2_1_stick_and_slide(shared_runs):
    """Lecture: mu = 0.1 keeps sliding, mu = 0.11 slides a while then stops, mu = 0.2 stops earlier.
    Measured at the lecture's tolerance, mu = 0.11 stops at about 5.5 s, where its contact nodes
    stick while the centre of mass still moves at about 4 cm/s (Newton's tolerance, docs/limits.md;
    converged, at about 6.7 s); the centre of mass itself, decelerating at 0.093 m/s^2, stops near
    6.0 s. So 7 s are simulated instead of 5 (simulate's steps, kept: helpers/runs.py)."""
    scenes = [simulator.build_scene(mu=mu) for mu in (0.1, 0.11, 0.2)]
    stops = {scene.mu: stop_step(scene, shared_runs.simulate(scene, 700)) for scene in scenes}
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


KERNELS = ["val_kernel", "grad_kernel", "hess_kernel"]
MU_LAMBDA = ["compute_mu_lambda", "compute_mu_lambda_kernel"]


def test_mu_zero_calls_no_friction(monkeypatch):
    counter = CallCounter(monkeypatch, FrictionEnergy,
                          ["val", "grad", "hess", "f0", "f1_div_vbarnorm", "f_hess_term"] + KERNELS)
    barrier = CallCounter(monkeypatch, BarrierEnergy, MU_LAMBDA)
    scene = simulator.build_scene(mu=0.0)
    assert "friction" not in scene.terms
    closest = min(rec.report.min_distance for rec in simulator.simulate(scene, 60))
    # contact happened (impact ~ step 30)
    assert closest < scene.dhat
    assert counter.calls == {} and barrier.calls == {}
    # the control: with mu the integrator calls the kernels (the checked public functions are for
    # notebooks; the scene was validated once when it was built)
    counter = CallCounter(monkeypatch, FrictionEnergy, ["val", "grad", "hess"] + KERNELS)
    barrier = CallCounter(monkeypatch, BarrierEnergy, MU_LAMBDA)
    run_steps(simulator.build_scene(mu=0.11), 60)
    assert set(counter.calls) == set(KERNELS)
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
    assert set(counter.calls) == set(KERNELS) | {"init_step_size_kernel", "distances"}


def test_barrier_and_friction_see_only_nodes_within_dhat(monkeypatch):
    """Every barrier evaluation touches exactly the nodes with d < dhat at the x it is given, and
    every friction evaluation exactly the nodes with d < dhat at x^n (where mu*lambda^n > 0)."""
    barrier_sets, friction_sets = [], []
    active, contacts = BarrierEnergy._active, FrictionEnergy._contacts

    def spy_active(x, n, o, dhat):
        out = active(x, n, o, dhat)
        # check_above: x^n above the slope, no barrier sum
        if dhat == np.inf:
            return out
        within = np.flatnonzero(BarrierEnergy.distances(x, n, o) < dhat)
        barrier_sets.append((set(out[0].tolist()), set(within.tolist())))
        return out

    def spy_contacts(v, mu_lambda, n):
        out = contacts(v, mu_lambda, n)
        friction_sets.append(set(out[0].tolist()))
        return out
    monkeypatch.setattr(BarrierEnergy, "_active", spy_active)
    monkeypatch.setattr(FrictionEnergy, "_contacts", spy_contacts)
    scene = simulator.build_scene()
    x = scene.x0
    for rec in simulator.simulate(scene, 60):
        d = BarrierEnergy.distances(x, scene.n, scene.o)
        within = set(np.flatnonzero(d < scene.dhat).tolist())
        assert friction_sets and all(seen == within for seen in friction_sets), f"step {rec.index}"
        friction_sets.clear()
        x = rec.x
    assert all(seen == expected for seen, expected in barrier_sets)
    # the bottom row, not all 25
    assert max(len(seen) for seen, _ in barrier_sets) == scene.params["n_seg"] + 1


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
    assert np.allclose(rec.x[:, 1], expected_y, atol=1e-9)
    assert np.allclose(rec.x[:, 0], scene.x0[:, 0], atol=1e-12)
    assert np.allclose(rec.v[:, 1], -9.81 * h * steps, rtol=1e-9)


@pytest.mark.slow
def test_small_time_step_slides_like_large_one():
    """h = 1e-4 on the slope (mu = 0.05 < tan theta): the square drops 5 cm, lands and slides down
    the slope as it does at h = 1e-3: same centre of mass within 1 cm after 0.25 s (measured: 3 mm;
    it has slid 1.7 cm downhill, landing at 0.1 s)."""
    coms = {}
    for h in (1e-3, 1e-4):
        scene = simulator.build_scene(h=h, mu=0.05, center=(0.0, -0.40))
        rec = run_steps(scene, int(round(0.25 / h)))
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


def test_an_uphill_direction_fails_the_line_search(monkeypatch):
    """An uphill direction (grad E . p > 0, not the round-off floor) never decreases E: the search
    gives up after max_halvings instead of spinning, and says so."""
    scene = simulator.build_scene(max_halvings=3)
    original = time_integrator.search_dir
    monkeypatch.setattr(time_integrator, "search_dir", lambda *args: -original(*args))
    with pytest.raises(time_integrator.LineSearchFailed) as info:
        time_integrator.step(scene, scene.x0, scene.v0, step_index=7)
    # log.csv's step 8
    assert info.value.step == 8 and info.value.figures["directional_derivative"] > 0
    assert "step 8:" in str(info.value)


def test_a_tolerance_below_round_off_stops_at_the_floor_and_says_so():
    """tol = 1e-10 m/s asks more than float64 can resolve in E: Newton stops where the line search
    can no longer decrease E along a descent direction, flags the step as stalled and reports the
    residual it reached; the run goes on (issue 13: it used to spin to its cap and fail)."""
    scene = simulator.build_scene(tol=1e-10)
    # through the impact (~ step 30)
    reports = [rec.report for rec in simulator.simulate(scene, 60)]
    stalled = [r for r in reports if r.stalled]
    assert stalled and all(r.residual > scene.tol for r in stalled)
    assert max(r.newton_iterations for r in reports) < 100
    assert all(r.residual <= scene.tol for r in reports if not r.stalled)
    # the floor is near float64's resolution of x: far below the lecture's tol
    assert max(r.residual for r in stalled) * scene.h < 1e-8


def test_newton_iterates_are_the_step_one_iteration_at_a_time():
    """newton_iterates yields a NewtonIterate per line search, in order; returns what step does."""
    scene = simulator.build_scene(friction_updates=2, tol=1e-4)
    rec = run_steps(scene, 35)                   # just after the impact
    x, v = rec.x, rec.v
    iterates = time_integrator.newton_iterates(scene, x, v, step_index=35)
    seen = []
    while True:
        try:
            seen.append(next(iterates))
        except StopIteration as done:
            x_next, v_next, report = done.value
            break
    x_step, v_step, report_step = time_integrator.step(scene, x, v, step_index=35)
    assert np.array_equal(x_next, x_step) and np.array_equal(v_next, v_step)
    assert len(seen) == report.newton_iterations == report_step.newton_iterations
    assert [it.alpha for it in seen] == report.alphas
    assert np.array_equal(seen[0].x, x) and np.array_equal(seen[-1].x_next, x_next)
    for a, b in zip(seen, seen[1:]):
        # each iterate starts where the last ended
        assert np.array_equal(a.x_next, b.x)
    for it in seen:
        assert it.alpha == it.alpha_ccd / 2 ** it.halvings and 0 < it.alpha_ccd <= 1
        assert np.array_equal(it.x_next, it.x + it.alpha * it.p)
        assert it.residual == np.abs(it.p).max() / scene.h
    assert {it.friction_update for it in seen} <= {0, 1, 2}


def test_step_index_is_keyword_only():
    scene = simulator.build_scene()
    with pytest.raises(TypeError):
        time_integrator.step(scene, scene.x0, scene.v0, 0.01)


def lagged_at(scene, x_n, v_n, x):
    """The step from (x_n, v_n) with its friction's mu*lambda taken at x (Algorithm 5, line 3)."""
    return time_integrator.friction_update(
        scene, time_integrator.Lagged(x_n, x_n + scene.h * v_n, None), x)


def fixed_point_residual(scene, x_n, v_n, x):
    """||p||_inf / h at x for the IP whose friction uses mu*lambda at x (Algorithm 5, line 3)."""
    lagged = lagged_at(scene, x_n, v_n, x)
    p = time_integrator.search_dir(scene, lagged, x, time_integrator.IP_grad(scene, lagged, x))
    return np.abs(p).max() / scene.h


def test_fully_implicit_friction_updates_and_converges():
    lagged = simulator.build_scene(mu=0.11, tol=1e-6)
    implicit = simulator.build_scene(mu=0.11, tol=1e-6, friction_updates=20)
    rec = run_steps(lagged, 45)                  # into the sliding contact
    x, v = rec.x, rec.v
    _, _, r_lag = time_integrator.step(lagged, x, v)
    x_imp, _, r_imp = time_integrator.step(implicit, x, v)
    assert r_lag.friction_updates == 0 and r_lag.friction_converged
    assert r_imp.friction_updates >= 1 and r_imp.friction_converged
    # at the fixed point the friction force uses mu*lambda of the end of the step
    assert fixed_point_residual(implicit, x, v, x_imp) <= implicit.tol


@pytest.mark.parametrize("kwargs", [dict(), dict(mu=0.5), dict(k=1e6, mu=0.2)])
def test_energy_budget_friction_work(kwargs, shared_runs):
    """Implicit Euler with convex potentials: E^{n+1} - E^n <= W_f^n, the work of friction over the
    step (from the step's optimality condition and convexity; the rest is numerical dissipation). So
    the mechanical energy lost since the start is at least what friction took out, and W_f <= 0.
    Compressed springs are not convex, so for this scene the bound is an empirical one that the
    argument makes plausible; allowed slack: one step's Newton error, M tol (|v| + |dv| + tol)."""
    scene = simulator.build_scene(**kwargs)
    E_prev = diagnostics.energies(scene, scene.x0, scene.v0)["total"]
    v_prev = scene.v0
    total_work = 0.0
    for rec in shared_runs.simulate(scene, 150):      # simulate's, kept: helpers/runs.py
        work = rec.report.friction_work
        assert work <= 0.0
        total_work += work
        E = diagnostics.energies(scene, rec.x, rec.v)["total"]
        speeds = np.abs(rec.v).max() + np.abs(rec.v - v_prev).max()
        slack = scene.m.sum() * scene.tol * (speeds + scene.tol)
        assert E - E_prev <= work + slack, f"step {rec.index}"
        E_prev, v_prev = E, rec.v
    assert total_work < -1.0                       # friction did take energy out while sliding


def test_fixed_point_checks_its_last_solve():
    """Algorithm 5 with a cap of one update: the result of that update is checked against the
    mu*lambda it implies before the step reports (non-)convergence, and the report agrees with an
    independent check of the fixed point. At tol = 1e-6 one update is sometimes enough, sometimes
    not."""
    scene = simulator.build_scene(mu=0.11, friction_updates=1, tol=1e-6)
    x, v = scene.x0, scene.v0
    outcomes = []
    for rec in simulator.simulate(scene, 45):
        r = rec.report
        at_fixed_point = fixed_point_residual(scene, x, v, rec.x) <= scene.tol
        assert r.friction_converged == at_fixed_point, f"step {rec.index}"
        assert r.friction_updates in (0, 1)
        outcomes.append(r.friction_converged)
        x, v = rec.x, rec.v
    assert True in outcomes and False in outcomes


def test_banded_and_superlu_give_the_same_newton_direction():
    """The integrator picks banded Cholesky for the lecture's mesh; SuperLU must agree with it."""
    banded = simulator.build_scene(mu=0.2)
    assert banded.solver.kind == "banded"
    solver = utils.SPDSolver.for_mesh(len(banded.x0), banded.e, "superlu")
    superlu = dataclasses.replace(banded, solver=solver)
    rec = run_steps(banded, 40)                  # into the sliding contact
    x, v = rec.x, rec.v
    directions = []
    for scene in (banded, superlu):
        lagged = lagged_at(scene, x, v, x)
        assert (lagged.mu_lambda > 0).any()
        y = x + 1e-4
        gradient = time_integrator.IP_grad(scene, lagged, y)
        directions.append(time_integrator.search_dir(scene, lagged, y, gradient))
    atol = 1e-10 * np.abs(directions[1]).max()
    assert np.allclose(directions[0], directions[1], rtol=0, atol=atol)
    x_b, _, _ = time_integrator.step(banded, x, v)
    x_s, _, _ = time_integrator.step(superlu, x, v)
    assert np.abs(x_b - x_s).max() < 1e-9


def test_a_node_below_the_slope_is_refused_with_or_without_friction():
    """x^n under the slope is bad input: a ValueError naming the node, with mu = 0 (no friction to
    check it) as with friction; and the IP refuses such an x (the line search's filter)."""
    for mu in (0.0, 0.11):
        scene = simulator.build_scene(mu=mu)
        with pytest.raises(ValueError, match="node .* distance"):
            time_integrator.step(scene, scene.x0 + [0.0, -0.6], scene.v0)
    scene = simulator.build_scene(mu=0.0)
    lagged = time_integrator.Lagged(scene.x0, scene.x0, None)
    below = scene.x0 + [0.0, -0.6]
    assert np.isfinite(time_integrator.IP_val(scene, lagged, scene.x0))
    assert time_integrator.IP_val(scene, lagged, below) == np.inf
    with pytest.raises(ValueError, match="distance"):
        time_integrator.IP_grad(scene, lagged, below)


@pytest.mark.parametrize("mu", [0.0, 0.5])
def test_incremental_potential_is_its_terms(mu):
    """IP_grad against finite differences of IP_val, and IP_hess as M + h^2 times the public
    (FD-checked, PSD-projected) Hessians of the scene's terms, at a state in contact."""
    import GravityEnergy
    import InertiaEnergy
    import MassSpringEnergy
    scene = simulator.build_scene(mu=mu)
    rec = run_steps(scene, 45)
    x, v = rec.x, rec.v
    lagged = lagged_at(scene, x, v, x)
    y = x + 2e-5 * np.random.default_rng(1).normal(size=x.shape)
    fd = fd_gradient(lambda z: time_integrator.IP_val(scene, lagged, z), y, 1e-8)
    assert_close(time_integrator.IP_grad(scene, lagged, y), fd, 1e-5, "IP_grad")
    s, h2 = scene, scene.h ** 2
    terms = [MassSpringEnergy.hess(y, s.e, s.l2, s.k), GravityEnergy.hess(y, s.m, s.g),
             BarrierEnergy.hess(y, s.n, s.o, s.contact_area, s.dhat, s.kappa)]
    if mu:
        terms.append(FrictionEnergy.hess((y - x) / s.h, lagged.mu_lambda, s.h, s.n, s.epsv))
    expected = dense(InertiaEnergy.hess(y, lagged.x_tilde, s.m), y.size)
    expected += h2 * sum(dense(t, y.size) for t in terms)
    blocks = time_integrator.IP_hess(scene, lagged, y)
    H = sum(dense(utils.blocks_to_ijv(*h), y.size) for h in blocks)
    assert_close(H, expected, 1e-13, "IP_hess", atol=1e-13 * np.abs(expected).max())


def test_a_body_at_rest_in_equilibrium_stays_put():
    """No gravity, no slope, at rest: grad E = 0 and p = 0, so the first trial cannot decrease E;
    that is convergence, not a failed line search (and not the round-off floor)."""
    scene = simulator.build_scene(gravity=(0.0, 0.0), slope=None)
    x, v, report = time_integrator.step(scene, scene.x0, scene.v0)
    assert np.array_equal(x, scene.x0) and not v.any()
    # exact: x = x_tilde and every spring at the rest length build_scene measured with the same
    # operations, so grad E is 0.0 to the bit and p = H^-1 0 = 0 whatever the BLAS kernel
    assert report.residual == 0.0 and not report.stalled


def test_the_steps_friction_force_is_the_one_its_last_friction_update_gives():
    """Algorithm 5 re-solves the impact with lambda of the new iterate: the step's friction force
    (the report's, which log.csv's W_friction, the arrows and the page use) is -grad P_f with
    mu*lambda at x^{n+1}, not the lagged mu*lambda^n, and the work is that force times the
    displacement."""
    scene = simulator.build_scene(friction_updates=5)
    x_n = scene.x0
    for record in simulator.simulate(scene, 60):
        if record.report.friction_updates > 0:
            break
        x_n = record.x
    report, x = record.report, record.x
    assert report.friction_updates > 0
    v = (x - x_n) / scene.h
    args = (scene.n, scene.o, scene.contact_area, scene.mu, scene.dhat, scene.kappa)
    mu_lambda_end = BarrierEnergy.compute_mu_lambda(x, *args)
    mu_lambda_n = BarrierEnergy.compute_mu_lambda(x_n, *args)
    expected = -FrictionEnergy.grad(v, mu_lambda_end, scene.h, scene.n, scene.epsv)
    lagged = -FrictionEnergy.grad(v, mu_lambda_n, scene.h, scene.n, scene.epsv)
    scale = np.abs(expected).max()
    assert np.abs(report.friction_force - expected).max() <= 1e-12 * scale        # the same formula
    # lambda did change
    assert np.abs(lagged - expected).max() > 0.01 * scale
    assert report.friction_work == pytest.approx(float(np.vdot(expected, x - x_n)), rel=1e-12)


def chalk_states(chalk_runs, drag, seconds=0.6, every=20):
    """States (x^n, v^n, n) of the chalk's shared run every `every` steps once pressed, moving."""
    scene, _, xs, vs = chalk_runs.states(seconds, drag=drag)        # helpers/runs.py: simulate's
    return scene, list(zip(xs, vs, range(1, len(xs) + 1)))[200::every]


@pytest.mark.parametrize("drag", [False, True])
def test_newton_from_x_tilde_takes_the_step_newton_from_x_n_takes(drag, chalk_runs):
    """Both starts minimize the same Incremental Potential to ||p||_inf / h <= tol: each ends within
    about its last ||p||_inf <= tol h of the minimizer, so the two differ by at most 2 tol h per
    coordinate (measured at the chalk's tol 1e-6: 0.96 tol h pushed, 0.73 tol h dragged). The
    prediction starts a sliding tip sliding, not at v = 0 in the mollifier's stiff static branch:
    the dragged chalk needs under half the iterations (measured 18 against 75 over these 20 states;
    pushed 29 against 67)."""
    scene, states = chalk_states(chalk_runs, drag)
    lecture = dataclasses.replace(scene, newton_start="x_n")
    iterations = {"x_n": 0, "x_tilde": 0}
    for x, v, n in states:
        a = time_integrator.step(scene, x, v, step_index=n)
        b = time_integrator.step(lecture, x, v, step_index=n)
        assert np.abs(a[0] - b[0]).max() <= 2 * scene.tol * scene.h
        iterations["x_tilde"] += a[2].newton_iterations
        iterations["x_n"] += b[2].newton_iterations
    if drag:
        assert 2 * iterations["x_tilde"] < iterations["x_n"], iterations


def test_the_prediction_is_cut_back_by_ccd_before_it_reaches_the_board():
    """x^n + h v^n would put the tip 1 mm below the board (the tip at dhat = 1 mm, falling at 2
    m/s): Newton starts at x^n + alpha h v^n with Algorithm 4's alpha = 0.9 d / (h |v_y|) = 0.45,
    above the board."""
    scene = simulator.build_chalk_scene()
    v = np.tile([0.0, -2.0], (len(scene.x0), 1))
    first = next(time_integrator.newton_iterates(scene, scene.x0, v))
    alpha = 0.9 * scene.dhat / (scene.h * 2.0)
    assert np.allclose(first.x, scene.x0 + alpha * scene.h * v, rtol=0, atol=1e-15)
    assert BarrierEnergy.distances(first.x, scene.n, scene.o).min() > 0.0
    square = simulator.build_scene()            # the lecture's: from x^n
    assert next(time_integrator.newton_iterates(square, square.x0, square.v0 + 1.0)).x is square.x0
