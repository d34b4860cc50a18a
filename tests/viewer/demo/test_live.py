"""viewer/demo/live.py: the live demo without its window (no pygame): the run one step or one
Newton iteration at a time, its pacing to a clock, what the keys do, and its warnings. Driven here
with a fake clock; test_window.py drives the same through the window's keys."""
import io
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from helpers.command import recorded
from helpers.fakes import chalk_at
import simulator
import time_integrator
from analysis import diagnostics, wear
from viewer.demo import live

from helpers import ROOT

pytestmark = pytest.mark.usefixtures("shared_stepping")   # the runs' steps: helpers/runs.py
H = simulator.DEFAULTS["h"]


class FakeClock:
    """Wall time that moves only when told to."""

    def __init__(self):
        self.t = 0.0

    def now(self):
        return self.t

    def sleep(self, seconds):
        self.t += seconds


def test_a_step_is_the_same_whole_or_one_newton_iteration_at_a_time():
    """LiveRun.step is time_integrator.step; n after n (newton_iteration) yields each iterate and
    the n after the last completes the same step; a step begun with n and finished with step()
    (time_integrator.run_out) too."""
    scene = simulator.build_scene()
    whole, by_iteration, mixed = (live.LiveRun(scene, 100) for _ in range(3))
    for _ in range(30):                                             # to the impact
        for run in (whole, by_iteration, mixed):
            run.step()
    expected = time_integrator.step(scene, whole.x, whole.v, step_index=30)[0]
    record = whole.step()
    assert record.index == 30 and record.t == pytest.approx(0.31)
    assert np.array_equal(record.x, expected)
    count = 0
    while (record := by_iteration.newton_iteration()) is None:
        count += 1
        assert by_iteration.iteration == count and by_iteration.index == 30
        assert np.array_equal(by_iteration.shown_x, by_iteration.iterate.x_next)
    assert count >= 2 and np.array_equal(record.x, expected) and by_iteration.iterate is None
    assert mixed.newton_iteration() is None and mixed.iteration == 1
    assert np.array_equal(mixed.step().x, expected) and mixed.index == 31 and mixed.iterate is None
    mixed.restart()
    assert mixed.index == 0 and np.array_equal(mixed.x, scene.x0) and mixed.report is None


def test_the_pacer_says_the_time_due_and_the_rate_reached():
    clock = FakeClock()
    pacer = live.Pacer(clock, 0.5, H)
    clock.t = 2.0
    assert pacer.due() == pytest.approx(1.0)                        # at half speed
    pacer.start(0.3)
    clock.t = 2.4
    assert pacer.due() == pytest.approx(0.5)
    for k in range(200):                                # playing at a quarter of real time
        clock.t = 3.0 + 0.01 * k
        pacer.sample(0.0025 * k)
    assert pacer.rate() == pytest.approx(0.5)                       # 0.25x of the 0.5x asked
    pacer.start(0.0)                                                # a resume: measured afresh
    pacer.sample(0.0)
    assert pacer.rate() is None                                     # not a span of play yet


def test_the_demo_takes_the_steps_due_and_no_more():
    """Free steps (the clock stands still while stepping): after each frame of play, t is the last
    step's end that is due, t <= wall < t + h."""
    clock = FakeClock()
    demo = live.LiveDemo(simulator.build_scene(), 300, 1.0, None, clock, io.StringIO())
    for frame in range(1, 61):                          # one second at 60 frames a second
        clock.t = frame / 60
        demo.play()
        assert demo.run.t <= clock.t + 1e-9 < demo.run.t + H
    assert demo.slow is None and "slow" not in demo.warnings


def test_steps_slower_than_real_time_are_not_caught_up_and_are_said(monkeypatch):
    """Steps costing 3 h of wall time each: the demo falls behind no more than CATCH_UP (it goes on
    from where it is), plays at 1/3 of real time and notes so once."""
    clock, step = FakeClock(), time_integrator.step

    def slow_step(*args, **kw):
        clock.t += 3 * H
        return step(*args, **kw)

    monkeypatch.setattr(time_integrator, "step", slow_step)
    log = io.StringIO()
    demo = live.LiveDemo(simulator.build_scene(), 300, 1.0, None, clock, log)
    while demo.run.index < 150:
        started = clock.t
        demo.play()
        clock.t = max(clock.t, started + 1 / 60)        # the window's loop: 60 frames a second
        assert demo.pacer.due() - demo.run.t <= live.CATCH_UP + 2 * H
    assert demo.slow == pytest.approx(1 / 3, abs=0.02)
    assert demo.warnings["slow"].startswith("the window ran slower than real time: 0.3")
    assert log.getvalue().count("slower than real time") == 1


def test_the_keys_pause_step_and_restart():
    demo = live.LiveDemo(simulator.build_scene(), 10, 1.0, None, FakeClock(), io.StringIO())
    demo.toggle_pause()
    assert not demo.playing
    assert demo.one_step() and demo.run.index == 1
    demo.one_newton_iteration()
    assert demo.run.iteration == 1 and demo.run.index == 1
    while demo.run.index == 1:
        demo.one_newton_iteration()
    assert demo.message.startswith("step 2 done: Newton converged")
    while demo.one_step():
        pass
    assert demo.stopped() and demo.run.index == 10 and not demo.one_step()
    demo.restart()
    assert demo.playing and demo.run.index == 0         # stopped at the end: plays again


def test_the_demo_notes_each_warning_once_as_a_run_to_files_words_it():
    log = io.StringIO()
    demo = live.LiveDemo(simulator.build_scene(tol=1e-8), 40, 1.0, None, FakeClock(), log)
    while demo.one_step():
        pass
    stalled = [text for kind, text in demo.warnings.items() if kind == "stalled"]
    assert len(stalled) == 1 and "round-off floor" in stalled[0]
    assert log.getvalue().count("Newton stopped at float64's round-off floor") == 1


def test_the_demo_needs_no_pygame():
    code = textwrap.dedent("""
        import io, sys, simulator
        from viewer.demo import live
        class Clock:
            t = 0.0
            def now(self):
                return self.t
            def sleep(self, s):
                self.t += s
        clock = Clock()
        demo = live.LiveDemo(simulator.build_scene(), 20, 1.0, None, clock, io.StringIO())
        clock.t = 0.1
        demo.play()
        demo.toggle_pause()
        demo.one_newton_iteration()
        demo.one_step()
        print(demo.run.index, 'pygame' in sys.modules)""")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True,
                         timeout=120, env={**os.environ, "OPENBLAS_NUM_THREADS": "1"})
    assert out.returncode == 0 and out.stdout.split() == ["11", "False"], out.stderr


# ------------------------------------------------------------------------------------------------
# The chalk: its marks and its figures, as a run to files keeps and logs them
# ------------------------------------------------------------------------------------------------

# the pushed chalk sticks from step 2, slips over steps 206 to 220 (and at step 1; measured)
CHALK_STEPS = 215


def test_the_chalks_mark_and_figures_are_those_a_run_to_files_keeps(tmp_path, chalk_runs):
    """LiveRun.marks after each step is recording.Track.marks of the same steps (wear.Deposit.step
    over each step), bin for bin, left by the slips by step 215; tip_lines says the figures log.csv
    has for the state (tip_x, tip_speed, drive_speed, normal_force) and stuck or slipping
    (diagnostics.tip_stuck). A restart starts the mark afresh; a step completed one Newton iteration
    at a time leaves its deposit too. The recording's steps are the session's shared run's
    (helpers/runs.py: simulate's, the same bits as LiveRun.step's); the LiveRun steps its own."""
    stuck = chalk_at(200)           # first: chalk_at steps on from the nearest state kept before
    run = chalk_at(CHALK_STEPS)
    (track,) = recorded(tmp_path, [run.scene], CHALK_STEPS, chalk_runs.simulate)
    assert run.marks.first == track.marks.first
    assert np.array_equal(run.marks.values, track.marks.values) and run.marks.values.sum() > 0
    assert diagnostics.tip_stuck(run.scene, run.x, run.v) is False               # slipping now
    last = track.samples.last
    text = " ".join(live.tip_lines(run.scene, run.x, run.v, run.t))
    slipping = f"slipping: {last.tip_speed * 1e3:.3g} mm/s >= eps_v = 0.1 mm/s"
    assert f"tip at {last.tip_x * 100:.2f} cm, {slipping}" in text
    assert f"the hand's drive {last.drive_speed * 1e3:.3g} mm/s" in text
    assert last.drive_speed == pytest.approx(0.01)
    assert f"the board's normal force {last.normal_force:.3g} N" in text
    assert " stuck: " in live.tip_lines(stuck.scene, stuck.x, stuck.v, stuck.t)[0]
    assert diagnostics.tip_stuck(stuck.scene, stuck.x, stuck.v) is True
    start = live.LiveRun(run.scene, 10)
    assert start.marks.span() is None
    assert "off the board (d >= dhat)" in live.tip_lines(run.scene, start.x, start.v, 0.0)[0]
    while start.newton_iteration() is None:
        pass
    one = wear.Deposit()
    one.step(run.scene, run.scene.x0, start.x)
    assert start.index == 1 and start.marks.first == one.first
    assert np.array_equal(start.marks.values, one.values)
    run.restart()
    assert run.marks.span() is None and run.index == 0


def test_a_chalk_run_handed_out_shares_nothing_but_its_scene_with_those_kept():
    """helpers.fakes.chalk_at keeps the chalk's runs for the session and hands out copies: a test
    that changes its copy in place (its x and v, its StepReport, its marks) leaves the next copy of
    the same step as stepped, bit for bit; the scene is the one scene of them all."""
    first = chalk_at(CHALK_STEPS)
    stepped = (first.x.copy(), first.v.copy(), list(first.report.alphas),
               first.report.friction_force.copy(), first.marks.values.copy())
    first.x[:] += 1.0
    first.v[:] = 0.0
    first.report.alphas.append(0.5)
    first.report.friction_force[:] = np.nan
    first.marks.add(0, np.ones(3))
    again = chalk_at(CHALK_STEPS)
    assert again.scene is first.scene
    now = (again.x, again.v, again.report.alphas, again.report.friction_force, again.marks.values)
    for kept, seen in zip(stepped, now):
        assert np.array_equal(kept, seen)


def test_a_warning_the_window_prints_is_wrapped_to_100_columns():
    """Without --out the window prints a step's warnings itself: a folded mesh's took 160 columns
    on one line (a tester's --window --n-seg 16), where a run with files wraps it."""
    log = io.StringIO()
    demo = live.LiveDemo(simulator.build_scene(), 10, 1.0, None, FakeClock(), log)
    demo.note("inverted", "step 12 (t = 0.12 s): " + "a long warning word " * 10)
    lines = log.getvalue().splitlines()
    assert len(lines) > 1 and all(len(line) <= 100 for line in lines), lines
