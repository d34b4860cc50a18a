"""viewer/command/run.py: a signal at the last step (issue 40, item 3), whatever the moment, ends
the run in a closing line that says what is on disk, with the page's file:// link where it was
written; SIGHUP and SIGQUIT stop a run as SIGTERM does."""
import os
import signal
import subprocess
import sys
import time
from types import SimpleNamespace

import pytest

from helpers import ROOT
from helpers.command import ending, run_main
from viewer.command import run
from viewer.pictures import run_pictures

RUN = ["--steps", "6", "--frame-stride", "3"]


def interrupt(*args):
    """Stands for Ctrl+C arriving as the patched function is called."""
    raise run.Stopped(signal.SIGINT)


def expected(out, said=""):
    """The ending of the run RUN into `out` stopped by Ctrl+C after its last step, with its 6
    steps in log.csv and its page written, as helpers.command.ending joins its lines."""
    page = (out / "index.html").as_uri()
    return f"simulator.py: stopped: interrupted{said}; 6 steps kept in {out}/; the page: {page}"


def test_ctrl_c_as_the_closing_words_are_found_keeps_and_links_the_run(tmp_path, monkeypatch):
    """On main the line said 'nothing written' though log.csv held every step."""
    monkeypatch.setattr(run, "closing_words", interrupt)
    code, lines = run_main(*RUN, "--out", str(tmp_path))
    assert code == 130 and ending(lines) == expected(tmp_path), lines
    assert len((tmp_path / "log.csv").read_text().splitlines()) == 1 + 7


def test_ctrl_c_once_the_last_pictures_are_written_gives_the_pages_link(tmp_path, monkeypatch):
    real = run_pictures.write

    def written_then_interrupted(*args):
        real(*args)
        interrupt()
    monkeypatch.setattr(run_pictures, "write", written_then_interrupted)
    code, lines = run_main(*RUN, "--out", str(tmp_path))
    assert code == 130 and ending(lines) == expected(tmp_path, " while writing the last pictures")


def test_ctrl_c_between_the_pictures_and_the_closing_line(tmp_path, monkeypatch):
    """The signal arrives as signals.close() is called, outside every try of the ending: on main
    it left the run and the line said 'nothing written'."""
    real, calls = run.Signals.close, []

    def close(self):
        calls.append(self)
        if len(calls) == 1:
            interrupt()
        real(self)
    monkeypatch.setattr(run.Signals, "close", close)
    code, lines = run_main(*RUN, "--out", str(tmp_path))
    assert code == 130 and ending(lines) == expected(tmp_path, " as the run ended"), lines


def test_ctrl_c_as_the_ending_begins_names_the_pictures_left_out(tmp_path, monkeypatch):
    monkeypatch.setattr(run, "end", interrupt)
    code, lines = run_main(*RUN, "--out", str(tmp_path))
    assert code == 130, lines
    assert ending(lines) == (f"simulator.py: stopped: interrupted as the run ended; 6 steps kept "
                             f"in {tmp_path}/; left out: summary.png, plots.png, index.html")
    assert sorted(os.listdir(tmp_path)) == sorted(
        ["log.csv", "frame_00000.png", "frame_00000.obj", "frame_00001.png", "frame_00001.obj",
         "frame_00002.png", "frame_00002.obj"])


@pytest.mark.skipif(not hasattr(signal, "SIGHUP"), reason="no SIGHUP, SIGQUIT (Windows)")
@pytest.mark.parametrize("name, code, reason", [("SIGHUP", 129, "hangup (SIGHUP)"),
                                                ("SIGQUIT", 131, "quit (SIGQUIT)")])
def test_sighup_and_sigquit_stop_a_run_as_sigterm_does(tmp_path, name, code, reason):
    """A closed terminal (SIGHUP) or Ctrl+\\ (SIGQUIT): one line, exit 128 + the signal's number,
    log.csv and the last pictures kept (on main: killed without a word, or pygame's 'Fatal Python
    error', exit 134)."""
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "SDL_VIDEODRIVER": "dummy"}
    child = subprocess.Popen([sys.executable, os.path.join(ROOT, "simulator.py"), "--steps",
                              "1e8", "--no-frames", "--out", str(tmp_path)], env=env,
                             stderr=subprocess.PIPE, text=True)
    # Mid-run once log.csv holds a step's row: the run opens it under its own signal handlers (a
    # progress line, test_run_stops' sync, comes only after 2 s of wall time: PROGRESS_EVERY).
    log, deadline = tmp_path / "log.csv", time.monotonic() + 120
    while not (log.exists() and log.read_text().count("\n") >= 3):       # header, t = 0, step 1
        assert child.poll() is None and time.monotonic() < deadline, "the run ended or stalled"
        time.sleep(0.01)
    child.send_signal(getattr(signal, name))
    last = ending(child.stderr.read().splitlines())
    assert child.wait(timeout=120) == code
    steps = len((tmp_path / "log.csv").read_text().splitlines()) - 2
    assert last == f"simulator.py: stopped: {reason}; {steps} steps kept in {tmp_path}/", last
    assert sorted(os.listdir(tmp_path)) == ["log.csv", "plots.png", "summary.png"]


def test_a_comparison_whose_logs_differ_says_the_fewest_and_the_most_steps_kept(tmp_path):
    """Runs of a comparison step in turn up to each frame, so a signal can leave their logs a few
    steps apart (a tester's SIGHUP: 24, 24 and 21): the line said '21 steps kept'. It says the
    range where they differ and one number where they agree."""
    folder = SimpleNamespace(lost=False, folder=str(tmp_path), written={"log.csv"})
    tracks = [SimpleNamespace(logged=n, marks=None, tag=f"run{i}") for i, n in enumerate([24, 21])]
    plan = SimpleNamespace(frames=False)
    assert run.kept(tracks, folder, plan) == (f"21 to 24 steps kept in {tmp_path}/; left out: "
                                              "summary.png, plots.png")
    for track in tracks:
        track.logged = 21
    assert run.kept(tracks, folder, plan).startswith(f"21 steps kept in {tmp_path}/;")
