"""viewer/command/frame_process.py: a run's frames drawn and written by a second process are the
bytes the run's own process writes; each counts once the process says it is written; its errors,
its end and the signals stop the run as a frame written in the run's process would."""
import os
import pickle
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import simulator
from helpers import ROOT
from helpers.command import ending, page_data, run_main
from scenes import grasp
from viewer.command import frame_process
from viewer.pictures import frames

pytestmark = [pytest.mark.frame_process,      # tests/conftest.py: the frames in a second process
              pytest.mark.usefixtures("shared_stepping")]   # the runs' steps: helpers/runs.py


def files_of(folder):
    return {name: (folder / name).read_bytes() for name in os.listdir(folder)}


def frames_on_page(folder):
    """How many frames the run's page plays (frames 0 to that - 1)."""
    return len(page_data(folder)["frames"])


def test_every_scene_pickles_whole():
    """The process is handed the scenes pickled (Scene.__reduce__): the same arrays, the same
    numbers, params read-only again."""
    for build in (simulator.build_scene, simulator.build_chalk_scene,
                  simulator.build_tablecloth_scene, grasp.build_grasp_scene):
        scene = build()
        back = pickle.loads(pickle.dumps(scene))
        assert type(back.params).__name__ == "mappingproxy" and back.params == scene.params
        for name, value in vars(scene).items():
            if isinstance(value, np.ndarray):
                assert np.array_equal(getattr(back, name), value), name
        assert (back.mu, back.h, back.cells, back.body) == (scene.mu, scene.h, scene.cells,
                                                              scene.body)


@pytest.mark.parametrize("args", [[], ["--scene", "chalk", "--steps", "150"],
                                  ["--mu", "0.1,0.2", "--steps", "30"]])
def test_the_frames_are_the_bytes_the_runs_own_process_writes(tmp_path, monkeypatch, args):
    """The same run with its frames written here (frames.FrameWriter) and by the frames' process:
    every frame, OBJ and the page byte for byte (log.csv aside: its wall times)."""
    args = args or ["--steps", "60"]
    apart, here = tmp_path / "apart", tmp_path / "here"
    assert run_main(*args, "--out", str(apart))[0] == 0
    monkeypatch.setattr(frame_process, "FrameProcess", frames.FrameWriter)
    assert run_main(*args, "--out", str(here))[0] == 0
    a, b = files_of(apart), files_of(here)
    assert sorted(a) == sorted(b)
    drawn = [name for name in a if name.startswith("frame_") or name == "index.html"]
    assert len(drawn) > 6 and all(a[name] == b[name] for name in drawn)


def test_a_frame_its_process_cannot_write_stops_the_run_as_here(tmp_path, monkeypatch):
    """A file planted under frame 3's name before the process writes it: the process's OSError
    ends the run (exit 1, 'cannot write' that frame), frames 0 to 2 counted on the page, no
    temporary file left."""
    write = frame_process.FrameProcess.write

    def planting(self, j):
        if j == 3:
            (tmp_path / "frame_00003.png").write_text("planted")
        return write(self, j)
    monkeypatch.setattr(frame_process.FrameProcess, "write", planting)
    code, lines = run_main("--steps", "60", "--out", str(tmp_path))
    said = ending(lines)
    assert code == 1 and "cannot write" in said and "frame_00003.png" in said, said
    assert "a file of that name appeared" in said
    assert frames_on_page(tmp_path) == 3
    assert (tmp_path / "frame_00003.png").read_text() == "planted"
    assert not [name for name in os.listdir(tmp_path) if name.startswith(".tmp")]


def test_its_end_before_a_frame_stops_the_run_with_its_exit_code(tmp_path, monkeypatch):
    """The process killed as frame 5 is sent: the run ends (exit 1) saying it ended and how
    (exit code -9), with the frames it wrote before counted."""
    write = frame_process.FrameProcess.write

    def killing(self, j):
        if j == 5:
            while self.sent:                    # frames 0 to 4 written first
                self.receive()
            self.process.kill()
            self.process.wait()
        return write(self, j)
    monkeypatch.setattr(frame_process.FrameProcess, "write", killing)
    code, lines = run_main("--steps", "60", "--out", str(tmp_path))
    said = ending(lines)
    assert code == 1 and "the frames' process ended (exit code -9)" in said, said
    assert "frame_00005.png" in said
    assert frames_on_page(tmp_path) == 5


@pytest.mark.skipif(sys.platform == "win32", reason="sessions: POSIX")
def test_the_process_is_in_a_session_of_its_own(tmp_path, monkeypatch):
    """The terminal's Ctrl+C and hangup go to its foreground process group: the frames' process
    is in a session of its own, so only the run gets them, and says how it ended."""
    sessions = []
    write = frame_process.FrameProcess.write

    def noting(self, j):
        sessions.append(os.getsid(self.process.pid))
        return write(self, j)
    monkeypatch.setattr(frame_process.FrameProcess, "write", noting)
    assert run_main("--steps", "6", "--out", str(tmp_path))[0] == 0
    assert sessions and sessions[0] != os.getsid(0) and sessions[0] == sessions[-1]


@pytest.mark.skipif(sys.platform == "win32", reason="process groups and SIGINT: POSIX")
def test_ctrl_c_to_the_run_and_its_frames_process_is_said_once(tmp_path):
    """Ctrl+C to the terminal's group (the run's): it says it stopped (exit 130), no traceback,
    every frame written is on the page, and its frames' process has ended."""
    env = {**os.environ, "SDL_VIDEODRIVER": "dummy"}
    proc = subprocess.Popen([sys.executable, os.path.join(ROOT, "simulator.py"), "--out",
                             str(tmp_path), "--steps", "100000"], env=env,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)
    deadline = time.monotonic() + 120
    while not (tmp_path / "frame_00010.png").exists():
        assert proc.poll() is None and time.monotonic() < deadline, "the run ended or stalled"
        time.sleep(0.05)
    children = subprocess.run(["ps", "-o", "pid=", "--ppid", str(proc.pid)], capture_output=True,
                              text=True).stdout.split()
    assert len(children) == 1
    os.killpg(proc.pid, signal.SIGINT)
    said = proc.stderr.read()
    assert proc.wait(timeout=60) == 130
    assert "Traceback" not in said and "KeyboardInterrupt" not in said, said
    assert ending(said.strip().splitlines()).startswith("simulator.py: stopped: interrupted")
    with pytest.raises(ProcessLookupError):     # ended (and reaped) before the run did
        os.kill(int(children[0]), 0)
    pngs = [name for name in os.listdir(tmp_path) if name.endswith(".png")
            and name.startswith("frame_")]
    assert frames_on_page(tmp_path) == len(pngs) > 10


def test_a_signal_as_a_frame_is_sent_counts_that_frame(tmp_path, monkeypatch, capfd):
    """Ctrl+C as frame 5 is sent: the run stops (exit 130) with frame 5 noted as sent, so every
    frame on disk is on the page, and the process ends without a word. (It was raised between
    the send and its note: frame 5 was written but not counted, and its answer met a closed pipe,
    'BrokenPipeError' on the run's stderr, 1 CI run in 10.)"""
    send = frame_process.FrameProcess.send

    def signalling(self, message, frame):
        send(self, message, frame)
        if frame is not None and frame.index == 5:
            os.kill(os.getpid(), signal.SIGINT)
    monkeypatch.setattr(frame_process.FrameProcess, "send", signalling)
    code, lines = run_main("--steps", "60", "--out", str(tmp_path))
    assert code == 130 and ending(lines).startswith("simulator.py: stopped: interrupted"), lines
    pngs = [name for name in os.listdir(tmp_path) if name.startswith("frame_")
            and name.endswith(".png")]
    assert frames_on_page(tmp_path) == len(pngs) == 6
    said = capfd.readouterr().err
    assert "Traceback" not in said and "Exception ignored" not in said, said
