"""`--scene tablecloth` as a run records it: the energy budget with the surface's work and the heat,
log.csv's surface columns, and the closing line's travel beside the closed form."""
import csv
import math
import re
import types

import numpy as np
import pytest

import simulator
from analysis import closing, log
from helpers.command import closing_text, recorded, run_main
from scenes import tablecloth
from viewer.command import cli

pytestmark = pytest.mark.usefixtures("shared_stepping")   # the runs' steps: helpers/runs.py

SLOW, FAST = 1.0, 4.0       # m/s; sqrt(mu g L) = 1.4 m/s lies between


def steps(scenes):
    """The default length of a run of these scenes (cli.default_duration), in steps."""
    return round(cli.default_duration(scenes) / scenes[0].h)


@pytest.fixture(scope="module")
def tracks(tmp_path_factory):
    """A slow and a fast pull recorded side by side for the command line's default duration."""
    scenes = [simulator.build_tablecloth_scene(pull_speed=U) for U in (SLOW, FAST)]
    return recorded(tmp_path_factory.mktemp("cloth"), scenes, steps(scenes))


@pytest.mark.parametrize("k", [0, 1])
def test_the_budget_closes_and_friction_only_heats(tracks, k):
    """E(t) = E(0) + W_surface + W_hand - heat - D with D >= 0, heat never falling (friction's power
    in the surface's frame <= 0), and in the end all the surface's work is heat or D: mu M g L where
    the cloth outruns the dish, M U^2 where the dish catches it (half its kinetic energy, half heat
    as it catches up). Friction's lab-frame work is positive: it gave the dish its kinetic energy.
    Round-off: each figure sums ~300 terms of at most ~1 J, exact to ~1e-13 J; 1e-11 J leaves
    margin. A step may lower D by Newton's tolerance seen through friction's stiffness 2 mu lambda /
    eps_v, at most 2 mu M |g| (tol / eps_v) U h (the dish riding the cloth, measured 6.0e-6 J of
    the 9.8e-6 J bound at U 1 m/s): an unconverged step is not an exact implicit Euler step."""
    track = tracks[k]
    scene, samples = track.scene, track.samples.all()
    assert [s.step for s in samples] == list(range(track.steps + 1))        # every step kept
    E = np.array([s.energies["total"] for s in samples])
    W_surface, heat, D = (np.array([getattr(s, name) for s in samples])
                          for name in ("surface_work", "heat", "numerical_dissipation"))
    W_hand = np.array([s.hand_work for s in samples])
    assert np.allclose(E, E[0] + W_surface + W_hand - heat - D, rtol=0, atol=1e-11)
    assert D.min() >= -1e-11 and np.diff(heat).min() >= -1e-11
    U, M, g = scene.surface.pull_speed, scene.m.sum(), -scene.g[1]
    newton = 2 * scene.mu * M * g * (scene.tol / scene.epsv) * U * scene.h
    assert np.diff(D).min() >= -newton
    slow = U * U < scene.mu * g * scene.surface.pull_length
    expected = M * U * U if slow else scene.mu * M * g * scene.surface.pull_length
    assert W_surface[-1] == pytest.approx(expected, rel=0.01)
    assert heat[-1] + D[-1] == pytest.approx(W_surface[-1], abs=1e-6)      # at rest where it began
    peak = max(s.energies["kinetic"] for s in samples)      # at min(U, mu g T), T = L / U
    speed = min(U, scene.mu * g * scene.surface.pull_length / U)
    assert peak == pytest.approx(0.5 * M * speed**2, rel=0.01)
    assert max(s.friction_work for s in samples) >= peak    # friction's lab-frame work gave it


@pytest.fixture(scope="module")
def compared(tmp_path_factory):
    """`python simulator.py --scene tablecloth --pull-speed 1,4 --no-frames`: exit code, the closing
    lines joined, and each run's log.csv rows."""
    out = tmp_path_factory.mktemp("compared")
    code, lines = run_main("--scene", "tablecloth", "--pull-speed", "1,4", "--no-frames",
                           "--out", str(out))
    logs = {}
    for U in ("1", "4"):
        with open(out / f"log_pull-speed{U}.csv") as f:
            logs[float(U)] = list(csv.DictReader(f))
    return code, closing_text(lines), logs


def test_a_comparison_says_each_travel_beside_the_closed_form(compared):
    """The closing gives each run's travel, final, in the runs' order, and how far it is off the
    closed form: the run lasts until the slower closed-form dish has stopped, plus STOP_MARGIN,
    and both have (every node slower than eps_v)."""
    code, last, logs = compared
    assert code == 0, last
    scene = simulator.build_tablecloth_scene(pull_speed=SLOW)
    stop = tablecloth.stop_time(SLOW, 1.0, 0.2, 0.05, 9.81)
    assert last.startswith(f"simulated {round((stop + cli.STOP_MARGIN) / scene.h)} steps")
    words = re.search(r"; the dish travelled (\S+, \S+) m \(closed form (\S+) %, (\S+) %\);", last)
    travels, offs = words.group(1), words.groups()[1:]
    for U, travel, off in zip((1.0, 4.0), travels.split(", "), offs):
        exact = tablecloth.travel(U, 1.0, 0.2)
        assert float(travel) == pytest.approx(exact, rel=0.01) and abs(float(off)) < 1
        assert float(off) == pytest.approx(100 * (float(travel) - exact) / exact, abs=0.1)
        assert abs(float(logs[U][-1]["v_tangential"])) < scene.epsv


def test_the_log_has_the_surface_s_speed_the_slip_and_the_heat(compared):
    """The square's columns, then the surface's: v_s is U during the pull (t_pull, t_pull + L / U]
    and 0 outside it; the slip, relative to the cloth, is U less what the dish gained (mu g h) in
    the pull's first step; W_surface - W_friction is the heat."""
    _, _, logs = compared
    scene = simulator.build_tablecloth_scene()
    assert list(logs[FAST][0]) == log.columns(scene) == log.COLUMNS + [
        "surface_speed", "slip_speed", "W_surface", "heat"]
    for U, rows in logs.items():
        t = np.array([float(r["t"]) for r in rows])
        pulling = (t > 0.05 + 1e-9) & (t <= 0.05 + 1.0 / U + 1e-9)
        assert np.allclose([float(r["surface_speed"]) for r in rows], np.where(pulling, U, 0.0))
        first = rows[int(np.argmax(pulling))]
        assert float(first["slip_speed"]) == pytest.approx(U - 0.2 * 9.81 * scene.h, rel=1e-3)
        for r in rows:
            heat = float(r["W_surface"]) - float(r["W_friction"])
            assert float(r["heat"]) == pytest.approx(heat, abs=1e-8)


def dish(label, travel, **overrides):
    """A tablecloth track as the closing words read it: its scene, first and last centre of mass."""
    scene = simulator.build_tablecloth_scene(**overrides)
    items = [types.SimpleNamespace(com=np.array([0.0, 0.03]))]
    last = types.SimpleNamespace(com=np.array([travel, 0.03]))
    return types.SimpleNamespace(label=label, scene=scene, t=10.0,      # after the dish stopped
                                 samples=types.SimpleNamespace(items=items, last=last))


def test_the_closing_words_name_the_closed_form_s_branch():
    exact = 0.2 * 9.81 / 16
    assert closing.closing_words([dish("", exact * 0.99996)]) == \
        "the dish travelled 0.1226 m, closed form mu g L^2 / U^2 = 0.1226 m (-0.0 %)"
    both = [dish("pull-speed = 1", 1.02, pull_speed=1.0),
            dish("pull-speed = 8", 0.0, pull_speed=8.0, mu=0.0)]
    assert closing.closing_words(both) == \
        "the dish travelled 1.0200, 0.0000 m (closed form +2.0 %, - %)"
    assert closing.closing_note(both).endswith(" (the centre of mass along the pull, end minus "
                                               "start)")
    assert math.isclose(tablecloth.travel(4.0, 1.0, 0.2), exact)
