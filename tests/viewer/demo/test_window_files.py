"""The live window's run and files: how it ends (the close button, Esc, q, SIGTERM, a full disk) and
that it writes what a run without it writes (helpers.window drives it)."""
import errno
import io
import os
import re
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import simulator
from helpers.fakes import fill_disk_after, signal_dropped_at_step
from viewer.command import cli, frame_process, run
from viewer.demo import window
from viewer.pictures import frames
import viewer.main

from helpers import ROOT
from helpers.command import ending, page_data
from helpers.window import (LoadedClock, ScriptClock, differing_pixels, frames_until,
                            hidden, post, press, pygame, read_log, run_window)

pytestmark = pytest.mark.usefixtures("shared_stepping")   # the runs' steps: helpers/runs.py


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
    last = np.loadtxt(tmp_path / f"frame_{len(frames) - 1:05d}.obj", usecols=(1, 2),
                      comments=("#", "l", "f"))
    at = rows[(len(frames) - 1) * stride]                           # the step of the last frame
    # equal masses: the centre of mass is the nodes' mean
    assert last[:, 1].mean() == pytest.approx(float(at["com_y"]), abs=1e-6)
    for name in ("summary.png", "plots.png"):
        assert pygame().image.load(str(tmp_path / name)).get_width() > 0
    page = page_data(tmp_path)
    framed = [frame["runs"][0]["step"] for frame in page["frames"]]
    assert framed == [stride * j for j in range(len(frames))]


@pytest.fixture(scope="module")
def without_window(tmp_path_factory):
    """without_window(flags): the folder `simulator.py FLAGS --out` writes, run once a module for
    both pacings (one computation: the same files)."""
    kept = {}

    def run(flags):
        if tuple(flags) not in kept:
            plain = tmp_path_factory.mktemp("plain") / "out"
            assert viewer.main.main([*flags, "--out", str(plain)]) == 0
            kept[tuple(flags)] = plain
        return kept[tuple(flags)]
    return run


@pytest.mark.parametrize("pacing", [ScriptClock, LoadedClock])
@pytest.mark.parametrize("flags, frame_count", [(["--steps", "20", "--mu", "0.2"], 8),
                                               (["--scene", "chalk", "--steps", "240"], 9)])
def test_the_window_writes_the_files_a_run_without_it_writes(tmp_path, flags, frame_count, pacing,
                                                              without_window):
    """--window --out played to the end writes what `simulator.py --out` writes, by the same code:
    the same file names, log.csv the same but the wall times, the frames and OBJs byte for byte
    (one computation: the same steps, drawn the same way). The square, and the chalk (its frames
    with its mark, from the files' own Track, and marks.csv). Whatever the window's pacing: on a
    loaded machine (LoadedClock) it falls behind and drops frames of the window, never a step or a
    frame of the files (a frame of the files is due at a step, not at a wall-clock time)."""
    windowed, shown = played_to_the_end(tmp_path, flags, pacing())
    # loaded, the window fell behind: frames saying "slower than real time"
    assert (shown.slow_frames > 0) == (pacing is LoadedClock)
    same_files(without_window(flags), windowed, 2 * frame_count + 4 + ("chalk" in flags))


@pytest.mark.frame_process
def test_the_window_s_frames_are_written_by_the_frames_process(tmp_path, without_window,
                                                               monkeypatch):
    """As a run's frames (viewer/command/frame_process.py): painted and written by a second
    process while the window steps on, each counted once written, all of them by the window's
    end; the files those of a run without the window, byte for byte."""
    started = []
    real_init = frame_process.FrameProcess.__init__

    def init(self, *args):
        started.append(self)
        real_init(self, *args)
    monkeypatch.setattr(frame_process.FrameProcess, "__init__", init)
    flags = ["--steps", "20", "--mu", "0.2"]
    windowed, _ = played_to_the_end(tmp_path, flags, ScriptClock())
    assert len(started) == 1 and started[0].process.returncode == 0
    same_files(without_window(flags), windowed, 2 * 8 + 4)


def played_to_the_end(tmp_path, flags, clock):
    """`simulator.py --window FLAGS --out` played to the end on `clock`: its folder, the window."""
    def script():
        yield from frames_until(lambda: w_run.finished)

    windowed = tmp_path / "window"
    real_loop = window.LiveWindow.loop
    w_run = shown = None

    def loop(self, check=None):
        nonlocal w_run, shown
        w_run, shown = self.run, self
        clock.script = script()
        return real_loop(self, check)

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(window.LiveWindow, "loop", loop)
        assert run_window(["--window", *flags, "--out", str(windowed)], clock=clock) == 0
    return windowed, shown


def same_files(plain, windowed, count):
    """The `count` files of `windowed` are those of `plain`: a PNG and an OBJ a frame, the two
    pictures, the page and log.csv (and the chalk's marks.csv); log.csv the same but the wall
    times, the others byte for byte."""
    names = sorted(p.name for p in plain.iterdir())
    assert sorted(p.name for p in windowed.iterdir()) == names and len(names) == count
    drop_wall = [{k: v for k, v in r.items() if k != "wall_s"} for r in read_log(plain)]
    assert [{k: v for k, v in r.items() if k != "wall_s"} for r in read_log(windowed)] == drop_wall
    for name in names:
        if name != "log.csv":
            ours, theirs = (windowed / name).read_bytes(), (plain / name).read_bytes()
            assert ours == theirs, (name, differing_pixels(ours, theirs) if ".png" in name else "")


def test_without_out_nothing_is_written(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)

    def script():
        yield from frames_until(lambda: clock.t > 0.5)     # the run (20 steps) is over by then

    clock = ScriptClock(script())
    assert run_window(["--window", "--steps", "20"], clock=clock) == 0
    assert os.listdir(tmp_path) == []


def test_main_hands_window_runs_to_the_window(monkeypatch):
    """--window goes to viewer.demo.window.run_window, with no output folder unless --out is given;
    other runs to viewer.command.run.to_files, a comparison as one plan."""
    seen = []
    monkeypatch.setattr(window, "run_window",
                        lambda plan, speed, size, signals: seen.append((plan, speed, size)) or 0)
    monkeypatch.setattr(run, "to_files", lambda plan, signals: seen.append(plan) or 0)
    assert viewer.main.main(["--window", "--speed", "0.25", "--size", "500"]) == 0
    assert viewer.main.main(["--steps", "3", "--mu", "0.1,0.2"]) == 0
    assert seen[0][0].out is None and seen[0][1:] == (0.25, 500)
    assert [scene.mu for scene in seen[1].scenes] == [0.1, 0.2]
    assert seen[1].out is None                                      # a new folder


def test_a_comparison_in_the_window_is_refused_in_one_line(capsys):
    """In 100 columns: the tablecloth's took 108 (a tester's)."""
    assert viewer.main.main(["--window", "--mu", "0.1,0.2,0.3"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["simulator.py: error: --window shows one run; compare the 3 --mu runs without "
                   "it"]
    for args in (["--scene", "tablecloth", "--pull-speed", "1,4"],
                 ["--friction-iterations", ",".join(map(str, range(1, 12)))],
                 ["--scene", "grasp", "--lift-accel", "0.5,1"]):
        assert viewer.main.main(["--window", *args]) == 2
        (err,) = capsys.readouterr().err.strip().splitlines()
        assert len(err) <= 100 and "shows one run" in err, err


def test_without_out_a_run_writes_to_a_new_folder(tmp_path, monkeypatch):
    """--out has no default in the parser (the window writes nothing without it); a run to files
    writes to a new folder under output/ then."""
    monkeypatch.chdir(tmp_path)
    assert viewer.main.main(["--steps", "1", "--no-frames"]) == 0
    (folder,) = (tmp_path / "output").iterdir()
    assert folder.name.startswith("square-") and len(read_log(folder)) == 2


def test_sigterm_ends_the_window_as_it_ends_a_run_without_it(tmp_path):
    """SIGTERM (which SDL would turn into the close button) stops the run as without the window:
    exit code 143, one line saying so, the files kept (log.csv whole, a frame every stride of its
    steps, the pictures written)."""
    argv = [sys.executable, os.path.join(ROOT, "simulator.py"), "--window", "--steps", "100000",
            "--out", str(tmp_path)]
    process = subprocess.Popen(argv, env={**os.environ, "SDL_VIDEODRIVER": "dummy"},
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
    last = ending(err.strip().splitlines())
    assert last.startswith("simulator.py: stopped: terminated (SIGTERM); "), err
    steps = int(read_log(tmp_path)[-1]["step"])
    frames = len(list(tmp_path.glob("frame_*.obj")))
    # a row is written before its frame: the log holds every frame's step (3 * (frames - 1)), and up
    # to a stride more (the next frame's row written, its OBJ not yet)
    assert frames >= 6 and 3 * (frames - 1) <= steps <= 3 * frames
    assert (tmp_path / "summary.png").stat().st_size > 0 and (tmp_path / "index.html").exists()


def test_a_full_disk_stops_the_files_not_the_demo(tmp_path, monkeypatch):
    """A write failing (ENOSPC) at frame 3 (after frames 0-2 as PNG and OBJ): the window plays on to
    the end, the files stop where they were (log.csv whole, no pictures, as without the window), and
    closing says so in one line, exit 1."""
    fill_disk_after(monkeypatch, 6)

    def script():
        yield from frames_until(lambda: live[0].run.finished)
        status = " ".join(text for text, _ in live[0].status_lines())
        assert "files stopped: No space left on device" in status

    live, real_init = [], window.LiveWindow.__init__

    def init(self, *args, **kw):
        real_init(self, *args, **kw)
        live.append(self)
    monkeypatch.setattr(window.LiveWindow, "__init__", init)
    log = io.StringIO()
    code = run_window(["--window", "--steps", "30", "--out", str(tmp_path)],
                      clock=ScriptClock(script()), log=log)
    assert code == 1 and live[0].run.index == 30
    lines = log.getvalue().strip().splitlines()
    said = ending(lines)
    assert said.startswith("simulator.py: error: cannot write") and "No space left" in said
    assert f"steps kept in {tmp_path}/; left out: summary.png, plots.png, index.html" in said
    steps = [int(r["step"]) for r in read_log(tmp_path)]
    assert steps == list(range(10))         # frame 3 is step 9's: its row was written first
    frames = sorted(p.name for p in tmp_path.glob("frame_*.png"))
    assert frames == [f"frame_{j:05d}.png" for j in range(3)]
    assert not (tmp_path / "summary.png").exists()


def test_a_frame_failing_as_the_window_ends_stops_the_files_in_one_line(tmp_path, monkeypatch):
    """The frames' process says how its last frames went as the window ends (live.Files.close):
    a write failing there (ENOSPC) is the files' error as one during the run is, said once; exit
    1, log.csv whole, the last pictures and the page written as after a run's (only that frame
    failed here)."""
    def close(self):
        raise OSError(errno.ENOSPC, "No space left on device", str(tmp_path / "frame_00010.png"))

    def script():
        yield from frames_until(lambda: live[0].run.finished)

    live, real_init = [], window.LiveWindow.__init__

    def init(self, *args, **kw):
        real_init(self, *args, **kw)
        live.append(self)
    monkeypatch.setattr(window.LiveWindow, "__init__", init)
    monkeypatch.setattr(frames.FrameWriter, "close", close)
    log = io.StringIO()
    code = run_window(["--window", "--steps", "30", "--out", str(tmp_path)],
                      clock=ScriptClock(script()), log=log)
    lines = log.getvalue().strip().splitlines()
    assert code == 1 and live[0].write_error.errno == errno.ENOSPC
    failed = [line for line in lines if "writing the files failed" in line]
    assert failed == ["simulator.py: writing the files failed, none written after step 30: "
                      "No space left on device"]
    said = ending(lines)
    assert said.startswith("simulator.py: error: cannot write") and "No space left" in said
    assert f"30 steps kept in {tmp_path}/; the page: " in said and "left out" not in said
    assert (tmp_path / "summary.png").exists() and (tmp_path / "index.html").exists()
    assert [int(r["step"]) for r in read_log(tmp_path)] == list(range(31))


def test_a_signal_whose_raise_cpython_drops_still_ends_the_window(monkeypatch):
    """Noted as it came, raised by the next frame's check (no file to write is needed): 130 and one
    line (on main the window played on, with a traceback on stderr)."""
    signal_dropped_at_step(monkeypatch, 3)
    log = io.StringIO()
    assert run_window(["--window", "--steps", "20"], clock=ScriptClock(), log=log) == 130
    lines = log.getvalue().splitlines()
    assert lines == ["simulator.py: stopped: interrupted; nothing written"], lines


def test_after_a_restart_the_closing_says_the_step_shown_and_the_steps_written(tmp_path):
    """r at 0.3 s, q at 0.1 s of the replay: the line said '10 steps (0.10 s) in the window'
    while log.csv held 30 (a tester's tablecloth: 76 against 120)."""
    def script():
        while clock.t < 0.3:
            yield
        press("K_r")
        start = clock.t
        while clock.t < start + 0.1:
            yield
        press("K_q")
        yield

    clock, log = ScriptClock(script()), io.StringIO()
    assert run_window(["--window", "--steps", "100", "--out", str(tmp_path)], clock=clock,
                      log=log) == 0
    written = int(read_log(tmp_path)[-1]["step"])
    (line,) = [line for line in log.getvalue().splitlines() if "window ended" in line]
    shown = int(re.search(r"the window ended at step (\d+) ", line).group(1))
    assert shown < written and f"(log.csv to step {written})" in line, line
