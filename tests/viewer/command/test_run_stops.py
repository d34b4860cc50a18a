"""What is kept when a run is stopped (SIGTERM, SIGKILL, a full disk): whole log rows and files, a
true count; and what a run of any length keeps in memory and in its PNGs."""
import csv
import errno
import io
import os
import re
import signal
import subprocess
import sys
import time

import numpy as np

import analysis.log
from helpers import ROOT
from helpers.command import ending, run_main
from helpers.fakes import fill_disk_after
from viewer.command import cli, frame_process, recording
from viewer.output import whole_files
from viewer.pictures import draw, frames


def frame_indices(folder):
    names = (re.match(r"frame_(\d+)\.png$", name) for name in os.listdir(folder))
    return sorted(int(m.group(1)) for m in names if m)


def start(out, *args):
    env = {**os.environ, "SDL_VIDEODRIVER": "dummy"}
    return subprocess.Popen([sys.executable, os.path.join(ROOT, "simulator.py"), "--out", str(out),
                             *args], env=env, stderr=subprocess.PIPE, text=True)


def wait_for(path, proc, timeout=120):
    deadline = time.monotonic() + timeout
    while not path.exists():
        assert proc.poll() is None and time.monotonic() < deadline, "the run ended or stalled"
        time.sleep(0.05)


def assert_whole_rows(path):
    text = path.read_text()
    assert text.endswith("\n")
    rows = list(csv.reader(io.StringIO(text)))
    assert rows[0] == analysis.log.COLUMNS
    assert all(len(r) == len(analysis.log.COLUMNS) for r in rows)
    return [int(r[0]) for r in rows[1:]]


def test_sigterm_on_a_very_long_run_prints_progress_then_stops_like_ctrl_c(tmp_path):
    """--steps 1e8: a progress line within a few seconds of wall time; SIGTERM then ends the run
    with a message and exit code 143 (128 + 15), keeping log.csv and writing the pictures."""
    proc = start(tmp_path, "--steps", "1e8", "--no-frames")
    began = time.monotonic()
    line = proc.stderr.readline()
    assert line.startswith("step ") and time.monotonic() - began < 30
    proc.send_signal(signal.SIGTERM)
    rest = proc.stderr.read()
    assert proc.wait(timeout=60) == 143
    said = ending(rest.strip().splitlines())
    assert said.startswith("simulator.py: stopped: terminated (SIGTERM)")
    steps = assert_whole_rows(tmp_path / "log.csv")
    assert steps == list(range(len(steps))) and len(steps) > 100
    assert (tmp_path / "summary.png").stat().st_size > 0
    assert (tmp_path / "plots.png").stat().st_size > 0


def test_sigkill_leaves_the_log_within_a_stride_of_the_frames(tmp_path):
    proc = start(tmp_path, "--steps", "100000", "--frame-stride", "2")
    wait_for(tmp_path / "frame_00020.png", proc)
    proc.kill()
    proc.wait(timeout=60)
    steps = assert_whole_rows(tmp_path / "log.csv")
    last_frame = max(frame_indices(tmp_path))
    # a row is written before its frame is sent to the frames' process: the log holds every frame's
    # step, and at most the frames sent and not yet written (AHEAD) and one stride more
    assert 2 * last_frame <= steps[-1] <= 2 * (last_frame + frame_process.AHEAD + 1)


def test_a_full_disk_is_one_line_exit_1_and_keeps_what_was_written(tmp_path, monkeypatch):
    fill_disk_after(monkeypatch, 12)
    code, lines = run_main("--steps", "100", "--out", str(tmp_path))
    assert code == 1 and len(lines) >= 1
    assert ending(lines).startswith("simulator.py: error: cannot write")
    assert "No space left on device" in ending(lines)
    assert not any(line.startswith("Traceback") for line in lines)
    steps = assert_whole_rows(tmp_path / "log.csv")
    assert frame_indices(tmp_path) == [0, 1, 2, 3, 4, 5]       # 6 frames + 6 OBJs written
    assert steps[-1] >= 15


def test_a_log_row_that_cannot_be_written_whole_is_cut_back(tmp_path, monkeypatch):
    log = whole_files.LineFile(str(tmp_path / "log.csv"), ",".join(analysis.log.COLUMNS))
    size = os.path.getsize(tmp_path / "log.csv")
    real = os.write

    def half_then_full(fd, data):
        if len(data) > 4:
            real(fd, data[:len(data) // 2])
            raise OSError(errno.ENOSPC, "No space left on device")
        return real(fd, data)
    monkeypatch.setattr(os, "write", half_then_full)
    try:
        log.append("1,2,3,4,5,6,7,8")
    except OSError as err:
        assert err.filename == str(tmp_path / "log.csv")        # named, as the closing line says
    else:
        raise AssertionError("the failed write was not raised")
    log.close()
    assert os.path.getsize(tmp_path / "log.csv") == size


def test_a_run_of_any_length_keeps_bounded_history():
    """A run of 1e8 steps keeps at most `cap` samples for its pictures: evenly spaced, from the
    first, with the newest always at hand."""
    history = recording.History(cap=10)
    for i in range(1000):
        history.add(i)
    assert len(history.items) <= 10 and history.items[0] == 0 and history.last == 999
    gaps = np.diff(history.items)
    assert (gaps == gaps[0]).all() and history.all()[-1] == 999


def test_frame_png_keeps_every_drawn_colour_exactly(tmp_path):
    """The frames' 3-3-2 palette (frames.BandedPng): the colours frames are drawn in come back
    exactly, any other colour within one palette step (36 of 255 in red and green, 85 in blue): a
    channel's top bits pick the level, so 192..223 of red all become level 6, 219."""
    import pygame
    colors = [(255, 255, 255), (0, 0, 0), draw.NORMAL_COLOR, draw.FRICTION_COLOR] + draw.RUN_COLORS
    surface = pygame.Surface((len(colors) + 1, 3))
    for i, color in enumerate(colors):
        surface.fill(color, (i, 0, 1, 3))
    surface.fill((200, 100, 50), (len(colors), 0, 1, 3))
    (tmp_path / "f.png").write_bytes(frames.BandedPng(*surface.get_size()).data(pygame,
                                                                              surface))
    back = pygame.surfarray.array3d(pygame.image.load(str(tmp_path / "f.png"))).astype(int)
    assert back.shape == (len(colors) + 1, 3, 3)
    assert [tuple(back[i, 1]) for i in range(len(colors))] == colors
    error = np.array([200, 100, 50]) - back[-1, 1]
    assert (np.abs(error) < [37, 37, 86]).all()


def test_a_signal_as_a_bad_command_line_is_said_waits(monkeypatch):
    """Ctrl+C as the error line is made: that line and exit code 2 (the Stopped the handler raised
    there escaped main, a traceback; found with SIGINT at the k-th profile event)."""
    real = cli.flag_of

    def flag_of(err):
        os.kill(os.getpid(), signal.SIGINT)
        return real(err)
    monkeypatch.setattr(cli, "flag_of", flag_of)
    assert run_main("--steps", "-5") == (
        2, ["simulator.py: error: --steps: steps must be a whole number >= 1, got -5.0"])


ENDED_THEN_SIGNALLED = """
import os, signal, sys, types
sys.path.insert(0, sys.argv[1])
from viewer.command import run, startup
def main(argv):                     # a run that has said its ending; Ctrl+C as main returns
    with run.Signals() as signals:
        print("done", file=sys.stderr)
        signals.close()
    os.kill(os.getpid(), signal.SIGINT)
    return 0
sys.modules["ended"] = types.SimpleNamespace(main=main)
sys.exit(startup.run_command_line(main="ended"))
"""


def test_a_signal_after_the_run_has_said_its_ending_changes_nothing():
    """Handed back start-up's handler, it said 'stopped: interrupted while starting; nothing
    written' under a finished run's closing and exited 130 (a real run: SIGINT at any of the
    about 50 profile events between run.Signals.__exit__ and start-up's SIG_IGN)."""
    done = subprocess.run([sys.executable, "-c", ENDED_THEN_SIGNALLED, ROOT], capture_output=True,
                          text=True, timeout=120)
    assert (done.returncode, done.stderr) == (0, "done\n")
