"""The live window (`python simulator.py --window`), driven as an instructor drives it: keys and the
close button posted as events into the running loop, under SDL's dummy video driver (conftest), with
a fake wall clock so that nothing waits on real time and the pacing is exact."""
import io
import os
import subprocess
import sys

import numpy as np
import pytest

import simulator
from helpers import legibility
import time_integrator
from viewer.command import run
from analysis import diagnostics
from viewer.pictures import draw, wrap
from viewer.demo import live, window
import viewer.main

from helpers import ROOT
from helpers.fakes import square_at
from helpers.window import (H, ScriptClock, frames_until, live_window, needs_newton_hook, press,
                            pygame, read_log)

pytestmark = pytest.mark.usefixtures("shared_stepping")   # the runs' steps: helpers/runs.py


# ------------------------------------------------------------------------------------------------
# The keys
# ------------------------------------------------------------------------------------------------

def test_space_pauses_and_holds_the_state_then_resumes():
    def script():
        yield from frames_until(lambda: w.run.index >= 5)
        press("K_SPACE")
        yield
        index, x, v = w.run.index, w.run.x.copy(), w.run.v.copy()
        for _ in range(120):                                        # 2 s: 200 steps would be due
            yield
            assert w.run.index == index and (w.run.x == x).all() and (w.run.v == v).all()
            assert not w.playing
        press("K_SPACE")
        yield from frames_until(lambda: w.run.index > index)

    w, clock = live_window()
    clock.script = script()
    assert w.loop() == 0


def test_right_arrow_advances_exactly_one_time_step():
    """While paused, each right arrow is one call of time_integrator.step from the state shown."""
    scene = simulator.build_scene()

    def script():
        yield from frames_until(lambda: w.run.index >= 40)          # past the impact (~ step 33)
        press("K_SPACE")
        yield
        for _ in range(3):
            index, x, v = w.run.index, w.run.x.copy(), w.run.v.copy()
            press("K_RIGHT")
            for _ in range(10):
                yield
            x_next, v_next, _ = time_integrator.step(scene, x, v, step_index=index)
            assert w.run.index == index + 1
            # the same computation
            assert np.array_equal(w.run.x, x_next) and np.array_equal(w.run.v, v_next)

    w, clock = live_window(scene)
    clock.script = script()
    assert w.loop() == 0


def test_r_restarts_from_the_initial_state_and_replays_the_same_run(tmp_path):
    """r puts back x0 and v0 at t = 0 and plays on; the steps computed again are the same, so the
    files keep every step computed (rows replaced, none dropped)."""
    scene = simulator.build_scene()
    pg = window.open_display()
    clock = ScriptClock()
    plan = run.Plan([scene], ["mu = 0.11"], [""], [300], str(tmp_path), stride=1, frames=False,
                    forces=True)
    signals = run.Signals()
    folder = plan.folder(signals)
    output = live.Files(plan, folder, io.StringIO())
    w = window.LiveWindow(pg, pg.display.set_mode((400, 400)), scene, 300, 1.0, output, clock)
    seen = {}

    def script():
        while w.run.index < 60:
            seen[w.run.index] = w.run.x.copy()
            yield
        seen[w.run.index] = w.run.x.copy()
        press("K_r")
        yield
        assert w.run.index == 0 and w.run.t == 0.0 and w.playing
        assert np.array_equal(w.run.x, scene.x0) and np.array_equal(w.run.v, scene.v0)
        yield from frames_until(lambda: w.run.index >= 30)
        index = max(i for i in seen if i <= w.run.index)
        if index == w.run.index:
            assert np.array_equal(w.run.x, seen[index])

    clock.script = script()
    assert w.loop() == 0
    output.track.csv.close()
    steps = [int(r["step"]) for r in read_log(tmp_path)]
    assert steps == list(range(max(seen) + 1)) and max(seen) >= 60       # each step once


def test_the_window_stays_open_on_the_last_frame_until_closed():
    def script():
        yield from frames_until(lambda: w.run.finished)
        for _ in range(300):
            yield
            assert w.run.index == 10 and not w.playing and not w.done
        assert w.status_lines()[0][0].startswith("end of the run")
        assert showing_the_current_state(w)
        press("K_SPACE")                                            # nothing left to play
        press("K_RIGHT")
        yield
        assert w.run.index == 10 and not w.playing

    w, clock = live_window(steps=10)
    clock.script = script()
    assert w.loop() == 0 and clock.frames > 300


# ------------------------------------------------------------------------------------------------
# Pacing
# ------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("speed, cost", [(1.0, 0.0), (0.25, 0.0), (1.0, 0.5)])
def test_simulated_time_follows_the_wall_clock_at_speed(monkeypatch, speed, cost):
    """A step costing `cost` of its own simulated time (in fake wall time): the loop takes exactly
    the steps whose end is due, t <= speed * wall < t + h, and never says it is slower than real
    time."""
    step = time_integrator.step

    def timed_step(*args, **kw):
        clock.t += cost * H / speed
        return step(*args, **kw)

    monkeypatch.setattr(time_integrator, "step", timed_step)

    def script():
        while not w.run.finished:
            if w.playing and cost == 0.0:       # free steps: wall time stands still in play()
                due = speed * clock.frame_end
                # 1e-9 s: round-off in t and due
                assert w.run.t <= due + 1e-9 and due < w.run.t + H
            assert w.slow is None
            yield

    w, clock = live_window(steps=150, speed=speed)
    clock.script = script()
    assert w.loop() == 0
    assert w.slow_frames == 0 and w.frames == clock.frames      # keeping up: every loop draws
    # the last step is taken within a frame of being due; the script sees it the frame after and its
    # close button ends the loop one frame later
    assert clock.t == pytest.approx(150 * H / speed, abs=3 / window.FPS)


def test_slower_than_real_time_is_said_on_screen(monkeypatch):
    """Steps costing 3x their simulated time: the window plays at 1/3 of real time (it does not rush
    to catch up) and says so, with the rate it reaches."""
    step = time_integrator.step

    def slow_step(*args, **kw):
        clock.t += 3 * H
        return step(*args, **kw)

    monkeypatch.setattr(time_integrator, "step", slow_step)

    def script():
        yield from frames_until(lambda: w.run.index >= 100)
        # the rate over the pacer's last second: 1/3, within one step (0.01 s) over >= 0.5 s
        assert w.slow == pytest.approx(1 / 3, abs=0.01 / 0.5)
        assert any("slower than real time: 0.33x" in text for text, _ in w.status_lines())

    w, clock = live_window()
    clock.script = script()
    assert w.loop() == 0 and w.slow_frames > 0


def test_frames_are_dropped_not_simulated_time_when_behind(monkeypatch):
    """Steps costing 1.2x their simulated time: the loop draws only every 1/MIN_FPS s, the rest of
    the time goes to the steps."""
    step = time_integrator.step

    def slow_step(*args, **kw):
        clock.t += 1.2 * H
        return step(*args, **kw)

    monkeypatch.setattr(time_integrator, "step", slow_step)
    drawn = []

    def script():
        while w.run.index < 200:
            if not drawn or w.drawn_at != drawn[-1]:
                drawn.append(w.drawn_at)
            yield

    w, clock = live_window()
    clock.script = script()
    assert w.loop() == 0
    later = [t for t in drawn if t > 1.0]                           # once behind
    assert min(np.diff(later)) >= 1.0 / window.MIN_FPS - 1e-9
    assert len(drawn) < 0.75 * clock.frames and w.slow_frames > 0


# ------------------------------------------------------------------------------------------------
# Size, text, display
# ------------------------------------------------------------------------------------------------

def test_window_fits_the_display_or_takes_size():
    """The dummy driver reports a 1024x768 desktop, as the projector: the window takes FIT of
    768."""
    pg = window.open_display()
    info = pg.display.Info()
    assert window.window_size(None, pg) == int(window.FIT * min(info.current_w, info.current_h))
    assert window.window_size(None, pg) <= 768 - 100    # room for a title bar and a panel
    assert window.window_size(500, pg) == 500


@pytest.mark.parametrize("size", [window.MIN_SIZE, 652, 900])
def test_every_line_of_text_fits_the_window(size):
    """The caption and every status line (a long failure message too) in rows within the window, as
    the window breaks them (between phrases, else words)."""
    w, _ = live_window(size=size)
    w.failure = time_integrator.NewtonNotConverged("Newton did not converge", 12, iterations=1000,
                                                   residual=0.5, tol=0.01, h=0.01)
    width = size - 24
    caption = f"t = {999.99:.2f} s   mu = {w.scene.mu:g}"
    texts = [caption] + [t for t, _ in w.status_lines()] + w.help_lines()
    for text in texts:
        for row in wrap.phrase_rows(w.font, text, width):
            assert w.font.size(row)[0] <= width or " " not in row.strip(), row
    w.draw()
    assert w.screen.get_size() == (size, size)


def paused_window(overrides, step, iteration, size):
    """A LiveWindow of `size` px paused in `step` (counted from 1) after `iteration` presses of
    n (its run's first step - 1 steps: helpers.fakes.square_at, stepped once a session)."""
    run = square_at(step - 1, steps=300, **overrides)
    w, _ = live_window(run.scene, size=size)
    w.run, w.playing = run, False
    for _ in range(iteration):
        assert w.run.newton_iteration() is None
    return w


@pytest.mark.parametrize("size", [600, 652, 900])
def test_no_text_in_the_window_is_smaller_than_the_projector_minimum(monkeypatch, size):
    """Every text the window draws in each of its views (the forces' legend, the slope's numbers,
    the status with a key's message and a warning, the key hints; the Newton view at the impact and
    in the halving demo, its inset's title, notes and scale bar, the node's label) has capitals at
    least draw.MIN_CAP_HEIGHT of the window tall, measured in pixels: 15 px at 652 (the legend, the
    numbers and the inset's notes had 7), and is in a colour of WCAG contrast at least 4.5:1 against
    the white background (the key hints: 5.9:1 in window.KEYS; they were 2.3:1 in light grey)."""
    drawn = legibility.record_text(monkeypatch)
    for overrides, step, iteration in [({}, 40, 0), ({}, 30, 1), ({"h": 0.03}, 18, 4)]:
        w = paused_window(overrides, step, iteration, size)
        if iteration == 0:
            w.message, w.warnings["test"] = "step 39 done: a key's message", "a warning"
        w.draw()
        assert iteration == 0 or w.inset is not None
    texts = {text for text, _, _ in drawn}
    assert {"normal force lambda_k n", "0 m", "paused before step 40", "node 0, x30",
            "(sets alpha_CCD)", "thin lines: springs", "node 15"} <= texts
    in_order = " ".join(text for text, _, _ in drawn)           # a note wrapped over rows reads on
    assert "below x^i, out of frame" in in_order and "q, Esc: quit" in in_order
    smallest = min(cap for _, cap, _ in drawn)
    assert smallest >= draw.MIN_CAP_HEIGHT * size
    contrast = {color: legibility.contrast_ratio(color) for _, _, color in drawn}
    assert min(contrast.values()) >= 4.5, contrast
    assert {window.KEYS, draw.GREEN, draw.RED, draw.BLUE, draw.BLACK} <= set(contrast)
    assert legibility.contrast_ratio(window.KEYS) == pytest.approx(5.9, abs=0.05)


@pytest.mark.parametrize("size", [600, 652, 900])
def test_the_windows_legend_swatch_sits_on_its_labels_row(size):
    """The forces' legend in the window (600 px: its swatches sat off their labels), laid out from
    the font's measured size: the normal force's red swatch (the only red at t = 0, in the air)
    within the rows of its label's ink and just left of it; the status lines start below the
    legend."""
    w, _ = live_window(size=size)
    w.draw()
    pixels = pygame().surfarray.array3d(w.screen)
    rows = legibility.swatch_and_label_rows(pixels, draw.NORMAL_COLOR, size // 3)
    top, low, first, last, gap = rows
    assert first <= top and low <= last and low - top + 1 >= 0.5 * (last - first + 1)
    assert gap <= draw.cap_height(w.font)


def test_no_display_is_one_line_and_exit_code_2(tmp_path):
    """A video driver that cannot start (as on a machine with no display): one line, exit code 2,
    nothing written."""
    argv = [sys.executable, os.path.join(ROOT, "simulator.py"), "--window", "--out",
            str(tmp_path / "o")]
    result = subprocess.run(argv, env={**os.environ, "SDL_VIDEODRIVER": "no-such-display"},
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("simulator.py: error: --window: no display"), result.stderr
    assert not (tmp_path / "o").exists()


def test_falling_back_to_a_memory_driver_is_no_display():
    """With no display SDL quietly picks its 'offscreen' driver: that is refused unless asked
    for."""
    assert window.display_problem("offscreen", None).endswith("; SDL: offscreen")
    assert window.display_problem("dummy", "x11").endswith("; SDL: dummy")
    assert window.display_problem("dummy", "dummy") is None
    assert window.display_problem("x11", None) is None


def test_a_shell_with_no_display_gets_the_error():
    """The instructor's case: no DISPLAY, no SDL_VIDEODRIVER. Skipped where SDL finds a screen
    anyway."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER")}
    probe = subprocess.run([sys.executable, "-c", "import pygame; pygame.display.init(); "
                            "print(pygame.display.get_driver())"],
                           env={**env, "PYGAME_HIDE_SUPPORT_PROMPT": "1"},
                           capture_output=True, text=True, timeout=60)
    if probe.returncode != 0 or probe.stdout.strip() not in window.MEMORY_DRIVERS:
        found = probe.stdout.strip() or probe.stderr.strip()
        pytest.skip(f"SDL opens a display here without DISPLAY ({found})")
    result = subprocess.run([sys.executable, os.path.join(ROOT, "simulator.py"), "--window"],
                            env=env, capture_output=True, text=True, timeout=120)
    assert result.returncode == 2
    assert result.stderr.strip().splitlines() == [result.stderr.strip()]
    assert result.stderr.strip() == ("simulator.py: error: --window: no display (DISPLAY unset; "
                                     "SDL: offscreen); use a desktop or Xvfb")
    assert len(result.stderr.strip()) <= 100        # it took 166 columns (a tester's)


@pytest.mark.parametrize("flags, message", [
    (["--size", "10"], "--size: "), (["--size", "1e9"], "--size: "),
    (["--size", "650.5"], "--size: "), (["--speed", "0"], "--speed: "),
    (["--speed", "-1"], "--speed: "), (["--speed", "nan"], "--speed: ")])
def test_bad_window_flags_are_one_line_and_exit_code_2(capsys, flags, message):
    assert viewer.main.main(["--window", *flags]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"simulator.py: error: {message}"), err


# ------------------------------------------------------------------------------------------------
# One Newton iteration at a time (Algorithm 4 on screen)
# ------------------------------------------------------------------------------------------------

@needs_newton_hook
@pytest.mark.parametrize("overrides, index", [
    ({}, 31), ({}, 40), ({"h": 0.03}, 17), ({"friction_updates": 3}, 31),
    ({"chalk": True}, 210), ({"chalk": True, "drag": True}, 20)])
def test_n_advances_exactly_one_newton_iteration_and_completes_the_step(overrides, index):
    """While paused, each n takes the next iterate of time_integrator.newton_iterates for the
    current step and shows it; the n after the last iterate completes the step, with the x^{n+1} of
    step(). Steps at the impact (the CCD bound below 1), sliding, at h = 0.03 where alpha is halved,
    with the fixed-point friction updates of Algorithm 5, and the chalk's: pushed, slipping (step
    211, in its first slip), and dragged, pressed onto the board (step 21); a chalk step that ends
    adds its deposit to the mark (wear.Deposit.step from x^n to x^{n+1}), the tip slipping where it
    is pushed."""
    overrides = dict(overrides)
    chalk = overrides.pop("chalk", False)
    scene = (simulator.build_chalk_scene if chalk else simulator.build_scene)(**overrides)

    def script():
        press("K_SPACE")                                            # paused at once,
        press("K_r")                                                # back at the start,
        for _ in range(index):                                      # and stepped to the step wanted
            press("K_RIGHT")
        yield
        assert w.run.index == index and not w.playing
        x, v = w.run.x.copy(), w.run.v.copy()
        mark = w.run.marks.copy() if chalk else None
        reference = time_integrator.newton_iterates(scene, x, v, step_index=index)
        red_before, updates = red_pixels(w), set()
        for count in range(1, 1000):
            press("K_n")
            yield
            try:
                expected = next(reference)
            except StopIteration as done:
                x_next, v_next, _ = done.value
                break
            assert w.run.index == index and w.run.iteration == count
            assert np.array_equal(w.run.shown_x, expected.x_next)
            assert np.array_equal(w.run.iterate.x, expected.x)
            lines = " ".join(text for text, _ in w.status_lines())
            assert f"Newton iteration {count}" in lines and f"{expected.alpha:.4g}" in lines
            assert f"{expected.alpha_ccd:.4g}" in lines and f"{expected.residual:.3g} m/s" in lines
            assert f"alpha_CCD / 2^{expected.halvings} = {expected.alpha:.4g}" in lines
            assert (f"friction update {expected.friction_update}," if expected.friction_update else
                    "lagged friction") in lines
            updates.add(expected.friction_update)
            assert red_pixels(w) > red_before                       # p drawn as red arrows
        assert count >= 2 and w.run.index == index + 1 and w.run.iterate is None
        # the lagged solve, then updates 1, 2, ... (measured: the impact's step 32 re-solves)
        assert updates == set(range(len(updates)))
        assert "friction_updates" not in overrides or 1 in updates
        assert np.array_equal(w.run.x, x_next) and np.array_equal(w.run.v, v_next)
        assert np.array_equal(w.run.x, time_integrator.step(scene, x, v, step_index=index)[0])
        if chalk:
            added = mark.step(scene, x, x_next)
            assert w.run.marks.first == mark.first
            assert np.array_equal(w.run.marks.values, mark.values)
            assert added > 0 or overrides.get("drag")                           # pushed, slipping
            pressed = bool(overrides.get("drag"))                               # dragged, pressed
            assert diagnostics.tip_stuck(scene, x_next, v_next) == pressed

    w, clock = live_window(scene)
    clock.script = script()
    assert w.loop() == 0


@needs_newton_hook
def test_right_arrow_after_n_finishes_that_step():
    scene = simulator.build_scene()

    def script():
        yield from frames_until(lambda: w.run.index >= 40)
        press("K_SPACE")
        yield
        index, x, v = w.run.index, w.run.x.copy(), w.run.v.copy()
        press("K_n")
        yield
        assert w.run.iteration == 1
        press("K_RIGHT")
        yield
        assert w.run.index == index + 1 and w.run.iterate is None
        assert np.array_equal(w.run.x, time_integrator.step(scene, x, v, step_index=index)[0])
        press("K_SPACE")                                            # n while playing does nothing
        press("K_n")
        yield
        assert w.run.iterate is None

    w, clock = live_window(scene)
    clock.script = script()
    assert w.loop() == 0


def red_pixels(w):
    """Pixels of the arrows' red in the window, as last drawn."""
    w.draw()
    pixels = pygame().surfarray.array3d(w.screen).reshape(-1, 3)
    return int((pixels == draw.RED).all(axis=1).sum())


def showing_the_current_state(w):
    """The screen shows what drawing the window's state now would show."""
    shown = pygame().surfarray.array3d(w.screen)
    w.draw()
    return np.array_equal(shown, pygame().surfarray.array3d(w.screen))


# ------------------------------------------------------------------------------------------------
# What a run to files warns about, the window shows under its caption and prints on stderr
# ------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("overrides, steps, words", [
    ({"n_seg": 8}, 60, "mesh triangles are inverted"),  # folds at the impact (docs/limits.md)
    ({"tol": 1e-8}, 40, "round-off floor"),             # stalls within the first 0.4 s
    ({"h": 1.0, "slope": None}, 1, "impacts are not resolved in time")])
def test_the_window_says_what_a_run_to_files_warns_about(overrides, steps, words):
    log = io.StringIO()
    pg = window.open_display()
    w = window.LiveWindow(pg, pg.display.set_mode((400, 400)), simulator.build_scene(**overrides),
                          steps, 1.0, None, ScriptClock(), log)
    w.clock.script = frames_until(lambda: w.run.finished)
    assert w.loop() == 0
    on_screen = [text for text, color in w.status_lines() if words in text]
    assert len(on_screen) == 1 and on_screen[0].startswith("warning: ")
    if "impacts" not in words:          # a scene's warnings are printed when the run starts
        assert log.getvalue().count(words) == 1
        assert log.getvalue().startswith("simulator.py: warning: ")


def test_the_window_says_the_square_sticks_and_how_fast_it_creeps():
    """Paused before step 581 (t = 5.80 s, stuck from 5.54 s) the status says the square sticks and
    creeps, at the contact nodes' mean speed downhill, beside the closed form 0.70 mm/s; sliding
    at step 101 it says nothing of it."""
    w = paused_window({}, 581, 0, 652)
    said = [text for text, _ in w.status_lines()]
    run = w.run
    u = diagnostics.contact_velocities(w.scene, run.x, run.v).mean()
    assert said[-1] == ("sticks: every contact below eps_v, creeps "
                        f"{1e3 * u:.2f} mm/s (closed form 0.70)")
    assert 0.3 < 1e3 * u < 0.7                  # below the closed form at the default tolerance
    w = paused_window({}, 101, 0, 652)
    assert not [text for text, _ in w.status_lines() if "sticks" in text]
