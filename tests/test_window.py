"""The live window (`python simulator.py --window`), driven as an instructor drives it: keys and the close
button posted as events into the running loop, under SDL's dummy video driver (conftest), with a fake
wall clock so that nothing waits on real time and the pacing is exact."""
import csv
import io
import json
import os
import re
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import simulator
from helpers.fakes import chalk_at, fill_disk_after
from helpers import legibility
import time_integrator
from viewer.command import cli, run
from analysis import diagnostics
from viewer.pictures import draw, frames, marks
from viewer.demo import live, window
import viewer.main

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
H = simulator.DEFAULTS["h"]
needs_newton_hook = pytest.mark.skipif(not hasattr(time_integrator, "newton_iterates"),
                                       reason="time_integrator.newton_iterates (the Newton-iteration hook) not there yet")


def pygame():
    import pygame
    return pygame


def post(event_type, **attributes):
    pygame().event.post(pygame().event.Event(event_type, **attributes))


def press(key_name):
    pg = pygame()
    post(pg.KEYDOWN, key=getattr(pg, key_name))


class ScriptClock:
    """A fake wall clock for the window's loop: sleep() moves it on, then runs the test's script up to
    its next `yield` (one frame of the loop), where the script posts events and checks the window.
    When the script ends, the close button is pressed; a loop that outlives max_frames fails."""

    def __init__(self, script=None, max_frames=20000):
        self.t, self.script, self.frames, self.max_frames = 0.0, script, 0, max_frames
        self.frame_end = 0.0                # the time the last frame's sleep began

    def now(self):
        return self.t

    def sleep(self, seconds):
        self.frame_end = self.t
        self.t += seconds
        self.frames += 1
        assert self.frames < self.max_frames, "the window's loop did not end"
        if self.script is not None:
            try:
                next(self.script)
            except StopIteration:
                self.script = None
                post(pygame().QUIT)


def live_window(scene=None, steps=300, speed=1.0, size=400, recorder=None):
    """A LiveWindow on the dummy display with a ScriptClock (give it its script, then loop())."""
    pg = window.open_display()
    screen = pg.display.set_mode((size, size))
    clock = ScriptClock()
    scene = scene or simulator.build_scene()
    return window.LiveWindow(pg, screen, scene, steps, speed, recorder, clock), clock


def frames_until(condition, limit=5000):
    """Yield frames until condition() holds."""
    for _ in range(limit):
        if condition():
            return
        yield
    raise AssertionError("condition never reached")


def run_window(argv, **kw):
    """viewer.demo.window.run_window as the command line calls it, for `argv`."""
    (args,) = cli.parse_command_line(argv)
    with run.Signals() as signals:
        return window.run_window(cli.plan_from_args([args]), args.speed, args.size, signals, **kw)


def hidden(folder):
    """The folder's names starting with '.': temporary files left over."""
    return [p.name for p in folder.iterdir() if p.name.startswith(".")]


def read_log(folder):
    with open(folder / "log.csv") as f:
        return list(csv.DictReader(f))


# ------------------------------------------------------------------------------------------------
# Ending the run, and the files
# ------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("how", ["close button", "K_ESCAPE", "K_q"])
def test_close_button_esc_and_q_end_the_run_with_exit_0_and_files_intact(tmp_path, how):
    """Ended mid-run (about 0.25 s into a 1 s run): exit code 0, and every step computed is in
    log.csv, with a frame and OBJ every stride steps (3 at h = 0.01, as without the window), the
    pictures and the page written, nothing half written."""
    def script():
        while clock.t < 0.25:
            yield
        post(pygame().QUIT) if how == "close button" else press(how)
        yield

    clock = ScriptClock(script())
    code = run_window(["--window", "--steps", "100", "--out", str(tmp_path)], clock=clock)
    assert code == 0
    rows = read_log(tmp_path)
    steps = int(rows[-1]["step"])
    assert 10 <= steps < 100                         # ended mid-run, as asked
    assert [int(r["step"]) for r in rows] == list(range(steps + 1))
    stride = cli.frame_stride(cli.parse_command_line([])[0], [simulator.build_scene()])
    frames = sorted(p.name for p in tmp_path.glob("frame_*.png"))
    assert stride == 3 and frames == [f"frame_{j:05d}.png" for j in range(steps // stride + 1)]
    assert len(list(tmp_path.glob("frame_*.obj"))) == len(frames)
    assert not hidden(tmp_path)                                             # no temporaries left
    last = np.loadtxt(tmp_path / f"frame_{len(frames) - 1:05d}.obj", usecols=(1, 2), comments=("#", "l", "f"))
    at = rows[(len(frames) - 1) * stride]                           # the step of the last frame
    assert last[:, 1].mean() == pytest.approx(float(at["com_y"]), abs=1e-6)  # equal masses: the mean
    for name in ("summary.png", "plots.png"):
        assert pygame().image.load(str(tmp_path / name)).get_width() > 0
    page = json.loads(re.search(r"const run = (\{.*\});", (tmp_path / "index.html").read_text()).group(1))
    assert [frame["runs"][0]["step"] for frame in page["frames"]] == [stride * j for j in range(len(frames))]


@pytest.mark.parametrize("flags, frame_count", [(["--steps", "20", "--mu", "0.2"], 8),
                                               (["--scene", "chalk", "--steps", "240"], 9)])
def test_the_window_writes_the_files_a_run_without_it_writes(tmp_path, flags, frame_count):
    """--window --out played to the end writes what `simulator.py --out` writes, by the same code:
    the same file names, log.csv the same but the wall times, the frames and OBJs byte for byte
    (one computation: the same steps, drawn the same way). The square, and the chalk (its frames
    with its mark, from the files' own Track, and marks.csv)."""
    def script():
        yield from frames_until(lambda: w_run.finished)

    clock = ScriptClock()
    windowed, plain = tmp_path / "window", tmp_path / "plain"
    real_loop = window.LiveWindow.loop
    w_run = None

    def loop(self):
        nonlocal w_run
        w_run = self.run
        clock.script = script()
        return real_loop(self)

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(window.LiveWindow, "loop", loop)
        assert run_window(["--window", *flags, "--out", str(windowed)], clock=clock) == 0
    assert viewer.main.main([*flags, "--out", str(plain)]) == 0
    names = sorted(p.name for p in plain.iterdir())
    assert sorted(p.name for p in windowed.iterdir()) == names
    assert len(names) == 2 * frame_count + 4 + ("chalk" in flags)      # the chalk's marks.csv
    drop_wall = [{k: v for k, v in r.items() if k != "wall_s"} for r in read_log(plain)]
    assert [{k: v for k, v in r.items() if k != "wall_s"} for r in read_log(windowed)] == drop_wall
    for name in names:
        if name != "log.csv":
            assert (windowed / name).read_bytes() == (plain / name).read_bytes(), name


def test_without_out_nothing_is_written(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)

    def script():
        yield from frames_until(lambda: clock.t > 0.5)     # the run (20 steps) is over by then

    clock = ScriptClock(script())
    assert run_window(["--window", "--steps", "20"], clock=clock) == 0
    assert os.listdir(tmp_path) == []


def test_main_hands_window_runs_to_the_window(monkeypatch):
    """--window goes to viewer.demo.window.run_window, with no output folder unless --out is given; other
    runs to viewer.command.run.to_files, a comparison as one plan."""
    seen = []
    monkeypatch.setattr(window, "run_window", lambda plan, speed, size, signals: seen.append((plan, speed, size)) or 0)
    monkeypatch.setattr(run, "to_files", lambda plan, signals: seen.append(plan) or 0)
    assert viewer.main.main(["--window", "--speed", "0.25", "--size", "500"]) == 0
    assert viewer.main.main(["--steps", "3", "--mu", "0.1,0.2"]) == 0
    assert seen[0][0].out is None and seen[0][1:] == (0.25, 500)
    assert [scene.mu for scene in seen[1].scenes] == [0.1, 0.2] and seen[1].out is None      # a new folder


def test_a_comparison_in_the_window_is_refused_in_one_line(capsys):
    assert viewer.main.main(["--window", "--mu", "0.1,0.2,0.3"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["simulator.py: error: --window shows one run; --mu was given 3 values (compare them without "
                   "--window)"]


def test_without_out_a_run_writes_to_a_new_folder(tmp_path, monkeypatch):
    """--out has no default in the parser (the window writes nothing without it); a run to files
    writes to a new folder under output/ then."""
    monkeypatch.chdir(tmp_path)
    assert viewer.main.main(["--steps", "1", "--no-frames"]) == 0
    (folder,) = (tmp_path / "output").iterdir()
    assert folder.name.startswith("square-") and len(read_log(folder)) == 2


def test_sigterm_ends_the_window_as_it_ends_a_run_without_it(tmp_path):
    """SIGTERM (which SDL would turn into the close button) stops the run as without the window: exit
    code 143, one line saying so, the files kept (log.csv whole, a frame every stride of its steps,
    the pictures written)."""
    process = subprocess.Popen([sys.executable, os.path.join(ROOT, "simulator.py"), "--window", "--steps", "100000",
                                "--out", str(tmp_path)], env={**os.environ, "SDL_VIDEODRIVER": "dummy"},
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 120
        while not (tmp_path / "frame_00005.obj").exists():         # the window is running
            assert process.poll() is None and time.monotonic() < deadline, process.communicate()
            time.sleep(0.05)
        process.send_signal(signal.SIGTERM)
        _, err = process.communicate(timeout=60)
    finally:
        process.kill()
    assert process.returncode == 143, err
    assert err.strip().splitlines()[-1].startswith("simulator.py: stopped: terminated (SIGTERM); "), err
    steps = int(read_log(tmp_path)[-1]["step"])
    frames = len(list(tmp_path.glob("frame_*.obj")))
    # a row is written before its frame: the log holds every frame's step (3 * (frames - 1)), and up
    # to a stride more (the next frame's row written, its OBJ not yet)
    assert frames >= 6 and 3 * (frames - 1) <= steps <= 3 * frames
    assert (tmp_path / "summary.png").stat().st_size > 0 and (tmp_path / "index.html").exists()


def test_a_full_disk_stops_the_files_not_the_demo(tmp_path, monkeypatch):
    """A write failing (ENOSPC) at frame 3 (after frames 0-2 as PNG and OBJ): the window plays on to the end, the files stop where they
    were (log.csv whole, no pictures, as without the window), and closing says so in one line, exit 1."""
    fill_disk_after(monkeypatch, 6)

    def script():
        yield from frames_until(lambda: live[0].run.finished)
        assert any("files stopped: No space left on device" in text for text, _ in live[0].status_lines())

    live, real_init = [], window.LiveWindow.__init__

    def init(self, *args, **kw):
        real_init(self, *args, **kw)
        live.append(self)
    monkeypatch.setattr(window.LiveWindow, "__init__", init)
    log = io.StringIO()
    code = run_window(["--window", "--steps", "30", "--out", str(tmp_path)], clock=ScriptClock(script()), log=log)
    assert code == 1 and live[0].run.index == 30
    lines = log.getvalue().strip().splitlines()
    assert lines[-1].startswith("simulator.py: error: cannot write") and "No space left on device" in lines[-1]
    assert f"steps kept in {tmp_path}/; left out: summary.png, plots.png, index.html" in lines[-1]
    steps = [int(r["step"]) for r in read_log(tmp_path)]
    assert steps == list(range(10))                     # frame 3 is step 9's: its row was written first
    assert sorted(p.name for p in tmp_path.glob("frame_*.png")) == [f"frame_{j:05d}.png" for j in range(3)]
    assert not (tmp_path / "summary.png").exists()


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
            assert np.array_equal(w.run.x, x_next) and np.array_equal(w.run.v, v_next)  # the same computation

    w, clock = live_window(scene)
    clock.script = script()
    assert w.loop() == 0


def test_r_restarts_from_the_initial_state_and_replays_the_same_run(tmp_path):
    """r puts back x0 and v0 at t = 0 and plays on; the steps computed again are the same, so the files
    keep every step computed (rows replaced, none dropped)."""
    scene = simulator.build_scene()
    pg = window.open_display()
    clock = ScriptClock()
    plan = run.Plan([scene], ["mu = 0.11"], [""], [300], str(tmp_path), stride=1, frames=False, forces=True)
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
    """A step costing `cost` of its own simulated time (in fake wall time): the loop takes exactly the
    steps whose end is due, t <= speed * wall < t + h, and never says it is slower than real time."""
    step = time_integrator.step

    def timed_step(*args, **kw):
        clock.t += cost * H / speed
        return step(*args, **kw)

    monkeypatch.setattr(time_integrator, "step", timed_step)

    def script():
        while not w.run.finished:
            if w.playing and cost == 0.0:                   # free steps: wall time stands still in play()
                due = speed * clock.frame_end
                assert w.run.t <= due + 1e-9 and due < w.run.t + H      # 1e-9 s: round-off in t and due
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
    """Steps costing 3x their simulated time: the window plays at 1/3 of real time (it does not rush to
    catch up) and says so, with the rate it reaches."""
    step = time_integrator.step

    def slow_step(*args, **kw):
        clock.t += 3 * H
        return step(*args, **kw)

    monkeypatch.setattr(time_integrator, "step", slow_step)

    def script():
        yield from frames_until(lambda: w.run.index >= 100)
        # the rate over the pacer's last second: 1/3, within one step (0.01 s) over >= 0.5 s of samples
        assert w.slow == pytest.approx(1 / 3, abs=0.01 / 0.5)
        assert any("slower than real time: 0.33x" in text for text, _ in w.status_lines())

    w, clock = live_window()
    clock.script = script()
    assert w.loop() == 0 and w.slow_frames > 0


def test_frames_are_dropped_not_simulated_time_when_behind(monkeypatch):
    """Steps costing 1.2x their simulated time: the loop draws only every 1/MIN_FPS s, the rest of the
    time goes to the steps."""
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
    """The dummy driver reports a 1024x768 desktop, as the projector: the window takes FIT of 768."""
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
    texts = [f"t = {999.99:.2f} s   mu = {w.scene.mu:g}"] + [t for t, _ in w.status_lines()] + w.help_lines()
    for text in texts:
        for row in w.rows(text, width):
            assert w.font.size(row)[0] <= width or " " not in row.strip(), row
    w.draw()
    assert w.screen.get_size() == (size, size)


def paused_window(overrides, step, iteration, size):
    """A LiveWindow of `size` px paused in `step` (counted from 1) after `iteration` presses of n."""
    w, _ = live_window(simulator.build_scene(**overrides), size=size)
    w.playing = False
    for _ in range(step - 1):
        w.run.step()
    for _ in range(iteration):
        assert w.run.newton_iteration() is None
    return w


@pytest.mark.parametrize("size", [600, 652, 900])
def test_no_text_in_the_window_is_smaller_than_the_projector_minimum(monkeypatch, size):
    """Every text the window draws in each of its views (the forces' legend, the slope's numbers, the
    status with a key's message and a warning, the key hints; the Newton view at the impact and in the
    halving demo, its inset's title, notes and scale bar, the node's label) has capitals at least
    draw.MIN_CAP_HEIGHT of the window tall, measured in pixels: 15 px at 652 (the legend, the numbers
    and the inset's notes had 7), and is in a colour of WCAG contrast at least 4.5:1 against the white
    background (the key hints: 5.9:1 in window.KEYS; they were 2.3:1 in light grey)."""
    drawn = legibility.record_text(monkeypatch)
    for overrides, step, iteration in [({}, 40, 0), ({}, 30, 1), ({"h": 0.03}, 18, 4)]:
        w = paused_window(overrides, step, iteration, size)
        if iteration == 0:
            w.message, w.warnings["test"] = "step 39 done: a key's message", "a warning"
        w.draw()
        assert iteration == 0 or w.inset is not None
    texts = {text for text, _, _ in drawn}
    assert {"normal force lambda_k n", "0 m", "paused before step 40", "node 0, x30", "(sets alpha_CCD)",
            "thin lines: springs", "node 15"} <= texts
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
    """The forces' legend in the window (600 px: its swatches sat off their labels), laid out from the
    font's measured size: the normal force's red swatch (the only red at t = 0, in the air) within the
    rows of its label's ink and just left of it; the status lines start below the legend."""
    w, _ = live_window(size=size)
    w.draw()
    pixels = pygame().surfarray.array3d(w.screen)
    top, low, first, last, gap = legibility.swatch_and_label_rows(pixels, draw.NORMAL_COLOR, size // 3)
    assert first <= top and low <= last and low - top + 1 >= 0.5 * (last - first + 1)
    assert gap <= draw.cap_height(w.font)


def test_no_display_is_one_line_and_exit_code_2(tmp_path):
    """A video driver that cannot start (as on a machine with no display): one line, exit code 2,
    nothing written."""
    result = subprocess.run([sys.executable, os.path.join(ROOT, "simulator.py"), "--window", "--out",
                             str(tmp_path / "o")], env={**os.environ, "SDL_VIDEODRIVER": "no-such-display"},
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("simulator.py: error: no display"), result.stderr
    assert not (tmp_path / "o").exists()


def test_falling_back_to_a_memory_driver_is_no_display():
    """With no display SDL quietly picks its 'offscreen' driver: that is refused unless asked for."""
    assert "no display" in window.display_problem("offscreen", None)
    assert "no display" in window.display_problem("dummy", "x11")
    assert window.display_problem("dummy", "dummy") is None
    assert window.display_problem("x11", None) is None


def test_a_shell_with_no_display_gets_the_error():
    """The instructor's case: no DISPLAY, no SDL_VIDEODRIVER. Skipped where SDL finds a screen anyway."""
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER")}
    probe = subprocess.run([sys.executable, "-c", "import pygame; pygame.display.init(); "
                            "print(pygame.display.get_driver())"], env={**env, "PYGAME_HIDE_SUPPORT_PROMPT": "1"},
                           capture_output=True, text=True, timeout=60)
    if probe.returncode != 0 or probe.stdout.strip() not in window.MEMORY_DRIVERS:
        pytest.skip(f"SDL opens a display here without DISPLAY ({probe.stdout.strip() or probe.stderr.strip()})")
    result = subprocess.run([sys.executable, os.path.join(ROOT, "simulator.py"), "--window"], env=env,
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 2
    assert result.stderr.strip().splitlines() == [result.stderr.strip()]
    assert "no display" in result.stderr and "DISPLAY is not set" in result.stderr


@pytest.mark.parametrize("flags, message", [
    (["--size", "10"], "--size: "), (["--size", "1e9"], "--size: "), (["--size", "650.5"], "--size: "),
    (["--speed", "0"], "--speed: "), (["--speed", "-1"], "--speed: "), (["--speed", "nan"], "--speed: ")])
def test_bad_window_flags_are_one_line_and_exit_code_2(capsys, flags, message):
    assert viewer.main.main(["--window", *flags]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"simulator.py: error: {message}"), err


# ------------------------------------------------------------------------------------------------
# One Newton iteration at a time (Algorithm 4 on screen)
# ------------------------------------------------------------------------------------------------

@needs_newton_hook
@pytest.mark.parametrize("overrides, index", [({}, 31), ({}, 40), ({"h": 0.03}, 17), ({"friction_updates": 3}, 31),
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
    scene = simulator.build_chalk_scene(**overrides) if chalk else simulator.build_scene(**overrides)

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
            assert np.array_equal(w.run.shown_x, expected.x_next) and np.array_equal(w.run.iterate.x, expected.x)
            lines = " ".join(text for text, _ in w.status_lines())
            assert f"Newton iteration {count}" in lines and f"{expected.alpha:.4g}" in lines
            assert f"{expected.alpha_ccd:.4g}" in lines and f"{expected.residual:.3g} m/s" in lines
            assert f"alpha_CCD / 2^{expected.halvings} = {expected.alpha:.4g}" in lines
            assert (f"friction update {expected.friction_update}," if expected.friction_update else
                    "lagged friction") in lines
            updates.add(expected.friction_update)
            assert red_pixels(w) > red_before                       # p drawn as red arrows
        assert count >= 2 and w.run.index == index + 1 and w.run.iterate is None
        assert updates == set(range(len(updates)))                  # the lagged solve, then updates 1, 2, ...
        assert "friction_updates" not in overrides or 1 in updates  # (measured: the impact's step 32 re-solves)
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
    ({"n_seg": 8}, 60, "mesh triangles are inverted"),              # folds at the impact (docs/limits.md)
    ({"tol": 1e-8}, 40, "round-off floor"),                          # stalls within the first 0.4 s
    ({"h": 1.0, "slope": None}, 1, "impacts are not resolved in time")])
def test_the_window_says_what_a_run_to_files_warns_about(overrides, steps, words):
    log = io.StringIO()
    pg = window.open_display()
    w = window.LiveWindow(pg, pg.display.set_mode((400, 400)), simulator.build_scene(**overrides), steps, 1.0,
                          None, ScriptClock(), log)
    w.clock.script = frames_until(lambda: w.run.finished)
    assert w.loop() == 0
    on_screen = [text for text, color in w.status_lines() if words in text]
    assert len(on_screen) == 1 and on_screen[0].startswith("warning: ")
    if "impacts" not in words:                       # a scene's warnings are printed when the run starts
        assert log.getvalue().count(words) == 1 and log.getvalue().startswith("simulator.py: warning: ")


# ------------------------------------------------------------------------------------------------
# The chalk (--scene chalk): its view, its hand, forces and marks, its figures
# ------------------------------------------------------------------------------------------------

PUSHED, DRAGGED = (False, 240), (True, 400)     # (drag, steps): a slip's or a slide's mark by then


def chalk_window(steps, drag=False, size=652):
    """A LiveWindow of the chalk paused after `steps` steps (helpers.fakes.chalk_at), drawn once."""
    run_ = chalk_at(steps, drag)
    w, _ = live_window(run_.scene, steps=run_.steps, size=size)
    w.run, w.playing = run_, False
    w.draw()
    return w


def key_hints_top(w):
    """The first row of pixels of the key hints at the bottom."""
    rows = [row for text in w.help_lines() for row in w.rows(text, w.size - 24)]
    return w.size - 6 - len(rows) * w.font.get_linesize()


def chalk_top(w):
    """The highest row of pixels of the chalk and its hand's targets (7 px squares) in the window."""
    return min(w.view(w.run.shown_x)[:, 1].min(), w.view(w.scene.hand.targets(w.run.t))[:, 1].min() - 3)


def mark_columns(w):
    """The columns of the window where the chalk's mark is grey under the board: along the mark's
    lowest row (marks.draw_marks: MARK_HEIGHT deep from 2 rows under the board's line), a neutral
    grey darker than white."""
    board = round(float(w.view(marks.board_point(w.scene, 0.0))[0, 1])) + 2
    depth = round(marks.MARK_HEIGHT * w.view.unit * w.view.scale)
    row = pygame().surfarray.array3d(w.screen)[:, board + depth - 1].astype(int)
    grey = (row[:, 0] == row[:, 1]) & (row[:, 1] == row[:, 2]) & (row[:, 0] < 255)
    return set(np.flatnonzero(grey).tolist())


@pytest.mark.parametrize("drag, steps", [PUSHED, DRAGGED])
def test_the_chalk_window_draws_the_frame_of_the_chalk_its_hand_forces_and_mark(drag, steps):
    """The window shows the chalk as its frames do, zoomed as they zoom it (draw.View.of, at the
    window's size): below the status lines, the window is the frame draw.draw_frame draws of the
    state (the board, the chalk, the hand's targets and springs, the contact forces, the chalk's
    mark and its strip, kept off the rows of the status lines and the key hints); the hand's targets
    are there, and the mark in grey under the board over the stretch it covers."""
    w = chalk_window(steps, drag)
    scene, size, frame_view = w.scene, w.size, draw.View.of(w.scene)
    assert w.view.scale == pytest.approx(frame_view.scale * size / draw.RESOLUTION) and w.view.unit == frame_view.unit
    run_ = frames.frame_run(scene, w.run.x, w.run.report, w.label, draw.BLUE, True)
    run_["marks"] = w.run.marks
    top, bottom = w.text_bottom, key_hints_top(w)
    frame, legends = draw.draw_frame(pygame(), [run_], w.run.t, w.view, w.fonts, w.newton_per_metre, w.reserve)
    assert w.reserve == (top - legends, size - bottom)
    shown, drawn = pygame().surfarray.array3d(w.screen), pygame().surfarray.array3d(frame)
    assert np.array_equal(shown[:, top:bottom], drawn[:, top:bottom])
    px = w.view(w.run.x)
    assert px[:, 0].min() > 0 and px[:, 0].max() < size and top < px[:, 1].min() and px[:, 1].max() < bottom
    box = shown[int(px[:, 0].min()):int(px[:, 0].max()) + 1, int(px[:, 1].min()):int(px[:, 1].max()) + 1]
    bluish = box[:, :, 2].astype(int) - box[:, :, :2].max(axis=2) > 60              # the chalk's springs, anti-aliased
    assert bluish.sum() > 2000                                                      # (3300 at 652 px)
    for q in np.rint(w.view(scene.hand.targets(w.run.t))).astype(int):
        assert tuple(shown[q[0], q[1]]) == draw.HAND_COLOR                            # the hand's targets
    assert np.all(shown[:, top:bottom] == draw.NORMAL_COLOR, axis=2).sum() > 20      # the board's push
    lo, hi = (float(w.view(marks.board_point(scene, s))[0, 0]) for s in w.run.marks.span())
    columns = mark_columns(w)
    assert min(columns) >= lo - 1 and max(columns) <= hi + 1 and len(columns) >= 0.8 * (hi - lo) > 2


def test_the_chalks_mark_grows_as_the_run_goes_and_starts_afresh_at_r():
    """Stuck, the tip leaves almost nothing; slipping, it draws on (the first slip, about 1 mm,
    comes between steps 200 and 250): the mark drawn at step 250 holds that of step 200 and reaches
    beyond it; r clears it."""
    before = chalk_window(200)
    old = mark_columns(before)                                  # (one screen: read it first)
    after = chalk_window(250)
    new = mark_columns(after)
    assert old < new and max(new) > max(old)
    after.restart()
    after.draw()
    assert not mark_columns(after)


def test_the_chalk_windows_status_says_the_chalks_figures_and_no_slope(monkeypatch):
    """Under the caption, the chalk's figures of the state shown (live.tip_lines: the tip's place
    and speed, stuck or slipping, the hand's drive, the board's normal force), as drawn; the Newton
    view says its iterate's figures instead, of the board (its inset's node the nearest to it): no
    text says 'slope'. The slipping state: the middle of the first slip after the press, as
    diagnostics.tip_stuck has the first 300 states (flags[i] is state i + 1's), not a fixed step
    (step 240, slipping when this test was written, is stuck in today's run); the stuck one: 300."""
    drawn = legibility.record_text(monkeypatch)
    stepped, flags = live.LiveRun(simulator.build_chalk_scene(), 300), []
    while not stepped.finished:
        stepped.step()
        flags.append(diagnostics.tip_stuck(stepped.scene, stepped.x, stepped.v))
    assert len(flags) == 300 and flags[-1]
    first_slip = next(i for i in range(1, 300) if flags[i - 1] and not flags[i])
    slip_end = next(i for i in range(first_slip, 300) if flags[i])
    slipping, stuck = chalk_window((first_slip + slip_end) // 2 + 1), chalk_window(300)
    for w, state in ((slipping, "slipping: "), (stuck, "stuck: ")):
        lines = [text for text, _ in w.status_lines()]
        assert lines == [f"paused before step {w.run.index + 1}"] + live.tip_lines(w.scene, w.run.x, w.run.v, w.run.t)
        assert lines[1].startswith("tip at ") and state in lines[1] and "the hand's drive 10 mm/s" in lines[2]
    texts = [text for text, _, _ in drawn]
    assert set(live.tip_lines(stuck.scene, stuck.run.x, stuck.run.v, stuck.run.t)) <= set(texts)
    stuck.one_newton_iteration()
    stuck.draw()
    lines = [text for text, _ in stuck.status_lines()]
    assert lines[0] == "paused in step 301" and lines[1] == "step 301, Newton iteration 1 (lagged friction)"
    assert "inset: one node and the board magnified together; p (red) to scale" in lines
    assert stuck.inset.why == "nearest the board" and stuck.inset.node == diagnostics.tip(stuck.scene, stuck.run.x)[0]
    texts = " ".join(text for text, _, _ in drawn)
    assert "(nearest the board)" in texts and "the board: " in texts and "slope" not in texts


@pytest.mark.parametrize("size", [600, 652, 900])
def test_no_text_in_the_chalk_window_is_small_faint_or_over_the_chalk(monkeypatch, size):
    """The chalk's window is as legible as the square's: every text (the legends of the forces, the
    hand and the mark, the board's numbers in cm, the chalk's figures, the mark's strip's title and
    scale bar, the Newton view's lines and inset) with capitals at least draw.MIN_CAP_HEIGHT of the window tall, in a colour of contrast at
    least 4.5:1 on white; the legends' swatches on their labels' rows. The board is low enough that
    the status lines end above the chalk and its hand, and its numbers above the key hints (the
    Newton view's lines too from 652 px; at 600 they wrap onto a row more, over the hand)."""
    drawn = legibility.record_text(monkeypatch)
    w = chalk_window(240, size=size)
    assert w.text_bottom < chalk_top(w)
    pixels = pygame().surfarray.array3d(w.screen)
    for color in (draw.HAND_COLOR, marks.SWATCH):
        top, low, first, last, gap = legibility.swatch_and_label_rows(pixels, color, w.text_bottom)
        assert first <= top and low <= last and gap <= draw.cap_height(w.font)
    numbers = [text for text, _, color in drawn if text.endswith(" cm") and color == draw.BLUE]
    assert "0 cm" in numbers
    ink = np.nonzero((pixels[:, int(w.view(w.scene.o)[1]) + 2:] == draw.BLUE).all(axis=2).any(axis=0))[0]
    assert int(w.view(w.scene.o)[1]) + 2 + ink.max() < key_hints_top(w)      # the numbers' blue, above the hints
    w.one_newton_iteration()
    w.draw()
    assert w.inset is not None and (size == 600 or w.text_bottom < chalk_top(w))
    texts = {text for text, _, _ in drawn}
    assert {"the hand: its targets and springs", "the chalk's mark: lambda x slid length (Archard)",
            "normal force lambda_k n", "paused before step 241", "(nearest the board)",
            "thin lines: springs", marks.title(), marks.bar_label()} <= texts
    assert min(cap for _, cap, _ in drawn) >= draw.MIN_CAP_HEIGHT * size
    assert min(legibility.contrast_ratio(color) for _, _, color in drawn) >= 4.5


def strip_of(w):
    """The Strip of the mark draw.draw_frame drew in the window `w` (marks.layout on the window's
    rows)."""
    run_ = {"scene": w.scene, "x": w.run.shown_x, "marks": w.run.marks, "color": draw.BLUE}
    below = draw.draw_slope(pygame(), pygame().Surface((w.size, w.size)), w.scene, w.view, draw.BLUE, w.font)
    return marks.layout([run_], w.run.t, w.view, w.font, w.text_bottom, key_hints_top(w), below)


@pytest.mark.parametrize("size", [600, 652, 900])
@pytest.mark.parametrize("drag, steps", [PUSHED, DRAGGED])
def test_the_windows_strip_sits_beside_the_chalk_over_nothing_and_goes_for_the_newton_view(size, drag, steps):
    """No room under the window's board (its numbers, then the key hints): the mark's strip stands
    above the board beside the chalk, on the side with more room, clear of the chalk and its hand's
    targets, under the status lines and above the board, inside the window, at x8 of the window's
    own scale (the frames' times size / 900), its title and border drawn; under its board each
    column over the window's mark (at 240 and 400 steps) the grey of the deposit of the board it
    spans. In the Newton view (n) the Newton inset takes that room: no strip (no room reserved for
    it, its border gone)."""
    w = chalk_window(steps, drag, size)
    strip = strip_of(w)
    left, top, width, height = strip.rect
    body = np.vstack([w.view(w.run.x), w.view(w.scene.hand.targets(w.run.t))])
    board = int(w.view(w.scene.o)[1])
    assert strip.where == "beside the chalk" and strip.scale == pytest.approx(8 * 4000.0 * size / draw.RESOLUTION)
    assert left + width < body[:, 0].min() - 3 or left > body[:, 0].max() + 3
    assert w.text_bottom < top and top + height < board and 0 <= left and left + width <= size
    shown = pygame().surfarray.array3d(w.screen)
    assert np.all(shown[left:left + width, top] == 0) and np.all(shown[left, top:top + height] == 0)      # its border
    lo, hi = (float(strip.column(s)) for s in w.run.marks.span())
    columns = np.arange(max(int(np.floor(lo)), 2), min(int(np.ceil(hi)), width - 2))
    y = top + strip.rows[0][0] + strip.board + 2 + strip.band // 2
    want = marks.greys(w.run.marks.shade(strip.board_at(columns), strip.board_at(columns + 1)))
    assert len(columns) > 20 and np.array_equal(shown[left + columns, y], want)
    w.one_newton_iteration()
    w.draw()
    assert w.reserve is None and w.inset is not None
    assert not np.all(pygame().surfarray.array3d(w.screen)[left:left + width, top] == 0)
