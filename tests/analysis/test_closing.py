"""analysis/closing.py: the square's closing words. IPC's mollified friction has no true static
friction: a run that sticks still creeps, and its words say how fast (measured) beside the closed
form eps_v (1 - sqrt(1 - tan(theta) / mu)) and the Newton tolerance that blurs it."""
import math
import types

import numpy as np
import pytest

import closed_forms
import simulator
from analysis import closing, diagnostics
from helpers.command import recorded
from scenes import square

# The lecture's slope and mu, by hand: 1e-3 (1 - sqrt(1 - 0.1 / 0.11)) m/s
LECTURE_CREEP = 1e-3 * (1.0 - math.sqrt(1.0 - 0.1 / 0.11))


def track(u, rest_since, label="a", sliding=0, **scene):
    """A square's track as the closing words read it: a state every h = 0.01 s with the contact
    nodes' mean velocity u[k] along the tangent (m/s)."""
    scene = simulator.build_scene(**scene)
    states = [types.SimpleNamespace(t=k * scene.h, contact_velocity=float(uk), sliding=sliding)
              for k, uk in enumerate(u)]
    samples = types.SimpleNamespace(all=lambda: states, last=states[-1])
    return types.SimpleNamespace(label=label, scene=scene, rest_since=rest_since, samples=samples,
                                 t=states[-1].t, tangent=diagnostics.tangent(scene))


def creeping(u_star, rocking, rest_step=400, periods=5, per_period=20):
    """Sliding at 0.1 m/s until step `rest_step`, then u_star (m/s) rocking at +-`rocking` (m/s)
    over whole periods, one more state at the end."""
    k = np.arange(periods * per_period + 1)
    return np.r_[np.full(rest_step, 0.1), u_star + rocking * np.sin(2 * np.pi * k / per_period)]


def test_the_creep_is_the_mean_contact_velocity_since_it_stuck():
    """The sliding before the stick (0.1 m/s, 140 times the creep) does not enter; rocking at +-5
    mm/s over whole periods averages out, but for the one state past them: rocking / 101 states."""
    u = creeping(0.7e-3, 5e-3)
    assert closing.creep(track(u, rest_since=4.0)) == pytest.approx(0.7e-3, abs=5e-3 / 101)
    assert closing.creep(track(u, rest_since=None)) is None
    # a slope descending to the left: the tangent points uphill, the creep is still downhill
    left = track(-u, rest_since=4.0, slope=(-0.1, 1.0))
    assert closing.creep(left) == pytest.approx(0.7e-3, abs=5e-3 / 101)


def test_a_square_that_sticks_says_it_creeps_beside_the_closed_form():
    """At the default tolerance (10 mm/s, 14 times the creep) the words say the creep is below
    it; at 1e-4 m/s (a seventh of it) near it; at 1e-5 m/s they give three digits and no
    tolerance. A comparison says each run's part and the flags once."""
    assert closed_forms.creep_speed(simulator.build_scene()) == pytest.approx(LECTURE_CREEP)
    said = closing.rest_words([track(creeping(0.52e-3, 0.0, 554), rest_since=5.54)])
    assert said == ("the square sticks at 5.54 s, creeps 0.52 mm/s (closed form "
                    f"{1e3 * LECTURE_CREEP:.2f}, set by --epsv) below --tol 0.01")
    assert len(said) <= 100 and "rest" not in said
    near = closing.rest_words([track(creeping(0.64e-3, 0.0, 554), rest_since=5.54, tol=1e-4)])
    assert near == ("the square sticks at 5.54 s, creeps 0.64 mm/s (closed form "
                    f"{1e3 * LECTURE_CREEP:.2f}, set by --epsv) near --tol 0.0001")
    tight = closing.rest_words([track(creeping(0.695e-3, 0.0, 554), rest_since=5.54, tol=1e-5)])
    assert tight == ("the square sticks at 5.54 s, creeps 0.695 mm/s (closed form "
                     f"{1e3 * LECTURE_CREEP:.3f}, set by --epsv)")
    sliding = track(np.full(300, 0.05), None, "mu = 0.1", sliding=2, mu=0.1)
    air = track(np.zeros(300), None, "mu = 0.3", mu=0.3)
    stuck = track(creeping(0.22e-3, 0.0, rest_step=280), 2.8, "mu = 0.2", mu=0.2)
    form = 1e3 * 1e-3 * (1.0 - math.sqrt(1.0 - 0.1 / 0.2))
    runs = [sliding, air, stuck]
    assert closing.rest_words(runs) == (
        "mu = 0.1: still slides at 2.99 s; mu = 0.3: is in the air at 2.99 s; mu = 0.2: sticks "
        f"at 2.80 s, creeps 0.22 mm/s (closed form {form:.2f}); creep set by --epsv, below --tol")
    assert closing.closing_words(runs) == closing.rest_words(runs)
    also = track(creeping(0.52e-3, 0.0, rest_step=554), 5.54, "mu = 0.11", mu=0.11)
    slow = 1e3 * 1e-3 * (1.0 - math.sqrt(1.0 - 0.1 / 0.11))
    assert closing.rest_words([sliding, also, stuck]) == (      # the stuck together: 3 lines
        f"mu = 0.1: still slides at 2.99 s; mu = 0.11, 0.2: stick at 5.54, 2.80 s, creep 0.52, "
        f"0.22 mm/s, below --tol (closed form {slow:.2f}, {form:.2f})")
    assert closing.closing_note(runs).startswith(closing.rest_words(runs) + " (sticks: every ")


@pytest.mark.slow
def test_the_default_square_creeps_at_the_closed_form_at_a_tight_tolerance(tmp_path):
    """The lecture's square at tol 1e-5 m/s (70 times below the creep) for 14 s: the measured
    creep is the closed form's within 2 % (issue 41 measured -2.5 % to +1.6 % by fits of the
    centre of mass from t = 8 s); the default tolerance measures it 20-40 % slow."""
    scene = simulator.build_scene(tol=1e-5)
    (tr,) = recorded(tmp_path, [scene], 1400)
    assert 6.0 < tr.rest_since < 7.0
    assert closing.creep(tr) == pytest.approx(LECTURE_CREEP, rel=0.02)
    assert closing.rest_words([tr]).startswith(f"the square sticks at {tr.rest_since:.2f} s, "
                                               f"creeps {1e3 * closing.creep(tr):.3f} mm/s")


def test_a_state_where_every_contact_sticks_says_its_creep():
    """The window's line for a state (closing.state_words): the square at rest on the slope, moved
    at 0.45 mm/s downhill, sticks and creeps at that speed beside the closed form; at 2 mm/s (above
    eps_v = 1 mm/s) it slides, and in the air it touches nothing: no line."""
    scene = square.resting_scene(0.1, 0.11)
    down = diagnostics.tangent(scene)
    words = closing.state_words(scene, scene.x0, np.tile(0.45e-3 * down, (len(scene.x0), 1)), 0.0)
    exact = 1e3 * 1e-3 * (1.0 - math.sqrt(1.0 - 0.1 / 0.11))
    assert words == f"sticks: every contact below eps_v, creeps 0.45 mm/s (closed form {exact:.2f})"
    assert closing.state_words(scene, scene.x0, np.tile(2e-3 * down, (len(scene.x0), 1)), 0.0) \
        is None
    assert closing.state_words(scene, scene.x0 + [0.0, 1.0], 0.0 * scene.x0, 0.0) is None
