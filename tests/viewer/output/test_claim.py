"""viewer/output/files.py: the run's folder claimed in one atomic step by the run that writes it
(issue 40, item 1): a second claimant made to appear between two steps of the claim, then 2 and 8
runs started at once; a folder deleted or replaced while the run writes it."""
import os
import re
import shutil
import signal
import subprocess
import sys
import time

import pytest

from helpers import ROOT
from helpers.command import ending, run_main as main
from viewer.command import run
from viewer.output import files, whole_files

SIMULATOR = os.path.join(ROOT, "simulator.py")


# ---- a second claimant between two steps of the claim

def test_a_default_folder_taken_as_it_is_made_gives_the_next_name(tmp_path, monkeypatch):
    """Another run makes output/square-<date>-<time>/ and writes in it just before this one's
    mkdir: this run takes the -2 name, and output/ and the other run's folder are left as they
    are (on main the run removed output/ here and died with 'Directory not empty')."""
    monkeypatch.chdir(tmp_path)
    real, other = os.mkdir, []

    def second_claimant(path, *args):
        if not other and os.path.dirname(path) == files.OUTPUT:
            real(path)                              # the other run's folder and log
            (tmp_path / path / "log.csv").write_text("the other run's\n")
            other.append(os.path.basename(path))
        real(path, *args)
    monkeypatch.setattr(os, "mkdir", second_claimant)
    code, lines = main("--steps", "3", "--no-frames")
    assert code == 0, lines
    ours = sorted(os.listdir(tmp_path / "output"))
    assert ours == sorted([other[0], other[0] + "-2"])
    assert os.listdir(tmp_path / "output" / other[0]) == ["log.csv"]
    assert (tmp_path / "output" / other[0] / "log.csv").read_text() == "the other run's\n"
    assert lines[-1].endswith(f"in output/{other[0]}-2/")
    assert len((tmp_path / "output" / ours[1] / "log.csv").read_text().splitlines()) == 5


def test_a_parent_made_by_another_run_at_the_same_moment_is_shared(tmp_path, monkeypatch):
    """--out a/b/c while another run makes a/ (and its own a/d/) in the same moment: the parent is
    taken as found, the run writes a/b/c, the other run's folder stays (on main: 'File exists')."""
    real, top = os.mkdir, str(tmp_path / "a")

    def second_claimant(path, *args):
        if os.fspath(path) == top and not os.path.exists(top):
            real(top)
            real(os.path.join(top, "d"))
        real(path, *args)
    monkeypatch.setattr(os, "mkdir", second_claimant)
    code, lines = main("--steps", "3", "--no-frames", "--out", str(tmp_path / "a" / "b" / "c"))
    assert code == 0, lines
    assert sorted(os.listdir(tmp_path / "a")) == ["b", "d"]
    assert sorted(os.listdir(tmp_path / "a" / "b" / "c")) == ["log.csv", "plots.png",
                                                              "summary.png"]


def test_one_empty_out_claimed_by_two_runs_at_once_is_one_runs(tmp_path, monkeypatch):
    """A second run claims the same empty --out between this run's check that it is empty and its
    first file: exactly one of the two has it, the other is refused in one line naming it (on
    main both took it)."""
    out = tmp_path / "o"
    out.mkdir()
    real, second = os.listdir, []

    def second_claimant(path="."):
        if not second and os.fspath(path) in (str(out), os.path.realpath(out)):
            second.append(None)
            try:
                second[0] = files.RunFolder.make(str(out), "square", ["log.csv"], run.Signals())
            except ValueError as err:
                second[0] = err
        return real(path)
    monkeypatch.setattr(os, "listdir", second_claimant)
    code, lines = main("--steps", "3", "--no-frames", "--out", str(out))
    monkeypatch.undo()
    if isinstance(second[0], files.RunFolder):      # the second won: this run is refused
        assert code == 2 and len(lines) == 1 and str(out) in lines[0], lines
        assert "taken by a run started at once" in lines[0] or "not empty" in lines[0]
        assert os.listdir(out) == [files.CLAIM]     # the second's claim, nothing of this run's
    else:
        assert code == 0 and str(out) in str(second[0]), (lines, second)
        assert files.CLAIM not in os.listdir(out)


def test_a_refused_claim_leaves_the_other_runs_folder(tmp_path):
    """A run that loses an --out it made itself to another run's claim removes nothing: rmdir of
    what it made fails while the other run's claim is in it."""
    out = tmp_path / "p" / "o"
    winner = files.RunFolder.make(str(out), "square", ["log.csv"], run.Signals())
    with pytest.raises(ValueError, match="not empty"):
        files.RunFolder.make(str(out), "square", ["log.csv"], run.Signals())
    assert os.listdir(out) == [files.CLAIM]
    winner.release()
    assert os.listdir(out) == [] and not winner.lost


def test_a_claim_made_after_the_folder_was_found_empty_is_refused_as_taken(tmp_path, monkeypatch):
    """Another run's claim file made between this run's look at the empty --out and its own claim
    (O_EXCL): refused in one line, '... was taken by a run started at once', and the other run's
    claim left as it was (the races below mostly meet 'not empty' instead)."""
    out = tmp_path / "o"
    out.mkdir()
    found_empty = files.check_empty

    def then_claimed(path, *args):
        found_empty(path, *args)
        (out / files.CLAIM).write_text("the other run's\n")
    monkeypatch.setattr(files, "check_empty", then_claimed)
    code, lines = main("--steps", "3", "--no-frames", "--out", str(out))
    assert code == 2 and len(lines) == 1, lines
    assert lines[0] == (f"simulator.py: error: --out: out folder {str(out)!r} was taken by a run "
                        f"started at once: choose another --out")
    assert os.listdir(out) == [files.CLAIM]
    assert (out / files.CLAIM).read_text() == "the other run's\n"


# ---- runs started at once

FORKED = """
import os, runpy, sys, time
root, folder, count = sys.argv[1], sys.argv[2], int(sys.argv[3])
sys.path.insert(0, root)
import pygame, scipy.linalg, viewer.main    # what the runs load, loaded once: each forks from here
go, pids = os.path.join(folder, "go"), []
for k in range(count):
    pid = os.fork()
    if pid == 0:                        # a run, a process of its own: stderr to err<k>, then go
        os.dup2(os.open(os.path.join(folder, f"err{k}"), os.O_WRONLY | os.O_CREAT), 2)
        while not os.path.exists(go):
            time.sleep(0.001)
        sys.argv = [os.path.join(root, "simulator.py")] + sys.argv[4:]
        try:
            runpy.run_path(sys.argv[0], run_name="__main__")
        except SystemExit as ended:
            sys.stderr.flush()
            os._exit(ended.code)
        os._exit(70)                    # simulator.py ended without an exit code
    pids.append(pid)
open(go, "w").close()
print(*(os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1]) for pid in pids))
"""
READY_THEN_GO = """
import os, runpy, sys, time
root, ready, go = sys.argv[1:4]
sys.path.insert(0, root)
import viewer.main                  # numpy loaded: then every run claims at once
open(ready, "w").close()
while not os.path.exists(go):
    time.sleep(0.001)
sys.argv = [os.path.join(root, "simulator.py")] + sys.argv[4:]
runpy.run_path(sys.argv[0], run_name="__main__")
"""


# 8 runs at once (slow); the quick suite races 2, which the full suite leaves out: the 8 check the
# same, with more claimants on the same names (tests/conftest.py, quick_twin).
RACERS = [pytest.param(2, marks=pytest.mark.quick_twin), pytest.param(8, marks=pytest.mark.slow)]


def at_once(tmp_path, count, *args):
    """`count` runs of `python simulator.py ARGS` in `tmp_path`, each a process of its own, let go
    the same moment once all have loaded; their (exit code, stderr lines). Where the OS forks,
    one process loads numpy, scipy and pygame and forks the runs (8 processes each loading them
    took about 5 s of CPU); elsewhere (Windows) each run is started and loads them itself."""
    go = tmp_path / "go"
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "SDL_VIDEODRIVER": "dummy"}
    if hasattr(os, "fork"):
        forked = subprocess.run([sys.executable, "-c", FORKED, ROOT, str(tmp_path), str(count),
                                 *args], cwd=tmp_path, env=env, capture_output=True, text=True,
                                timeout=300)
        assert forked.returncode == 0 and not forked.stderr, forked
        return [(int(code), (tmp_path / f"err{k}").read_text().splitlines())
                for k, code in enumerate(forked.stdout.split())]
    children = [subprocess.Popen([sys.executable, "-c", READY_THEN_GO, ROOT,
                                  str(tmp_path / f"ready{k}"), str(go), *args],
                                 cwd=tmp_path, env=env, stderr=subprocess.PIPE, text=True)
                for k in range(count)]
    deadline = time.monotonic() + 300
    while not all((tmp_path / f"ready{k}").exists() for k in range(count)):
        assert time.monotonic() < deadline and all(c.poll() is None for c in children)
        time.sleep(0.01)
    go.touch()
    return [(c.wait(timeout=300), c.stderr.read().splitlines()) for c in children]


@pytest.mark.parametrize("count", RACERS)
def test_runs_started_at_once_each_get_a_folder_of_their_own(tmp_path, count):
    """Without --out each run makes output/<scene>-<date>-<time>/ (a suffix where that is taken),
    so runs started together never share a folder; a file the user left in output/ is untouched."""
    (tmp_path / "output").mkdir()
    (tmp_path / "output" / "notes.txt").write_text("mine")
    ended = at_once(tmp_path, count, "--steps", "3", "--no-frames")
    assert all(code == 0 for code, _ in ended), ended
    assert (tmp_path / "output" / "notes.txt").read_text() == "mine"
    runs = sorted(set(os.listdir(tmp_path / "output")) - {"notes.txt"})
    assert len(runs) == count and all(re.fullmatch(r"square-\d{8}-\d{6}(-\d+)?", r) for r in runs)
    said = sorted(lines[-1].rsplit(" in ", 1)[1] for _, lines in ended)
    assert said == sorted(f"output/{r}/" for r in runs)
    for name in runs:
        folder = tmp_path / "output" / name
        assert sorted(os.listdir(folder)) == ["log.csv", "plots.png", "summary.png"]
        assert len((folder / "log.csv").read_text().splitlines()) == 5


@pytest.mark.parametrize("count", RACERS)
def test_runs_started_at_once_into_one_empty_out_one_wins(tmp_path, count):
    """Exactly one run writes the folder; every other is refused in one line naming it, exit 2,
    and nothing of theirs is in it."""
    (tmp_path / "o").mkdir()
    ended = at_once(tmp_path, count, "--steps", "3", "--no-frames", "--out", "o")
    codes = sorted(code for code, _ in ended)
    assert codes == [0] + [2] * (count - 1), ended
    for code, lines in ended:
        if code == 2:
            assert len(lines) == 1 and lines[0].startswith("simulator.py: error: --out: "), lines
            assert "out folder 'o' " in lines[0]
            assert "taken by a run started at once" in lines[0] or "not empty" in lines[0]
    assert sorted(os.listdir(tmp_path / "o")) == ["log.csv", "plots.png", "summary.png"]
    assert len((tmp_path / "o" / "log.csv").read_text().splitlines()) == 5


# ---- a folder gone while the run writes it

def test_a_folder_deleted_and_made_again_mid_run_is_not_claimed_as_written(tmp_path, monkeypatch):
    """rm -rf of the run's folder, then an empty folder of that name (another run's, a user's):
    the files written after land there, log.csv does not. The run ends with exit 1 and says its
    folder disappeared, never 'log.csv ... in' it (on main: exit 0)."""
    out, real, calls = tmp_path / "o", whole_files.write_temporary, []

    def replaced(path, data):
        calls.append(path)
        if len(calls) == 10:
            shutil.rmtree(out)
            out.mkdir()
        return real(path, data)
    monkeypatch.setattr(whole_files, "write_temporary", replaced)
    code, lines = main("--steps", "30", "--frame-stride", "1", "--out", str(out))
    assert code == 1 and ending(lines) == (f"simulator.py: error: the run's folder was deleted "
                                           f"or moved; nothing kept: {out}/ disappeared as the "
                                           f"run wrote it")
    assert "log.csv" not in os.listdir(out)


def test_a_folder_deleted_after_frame_10_ends_with_exit_1(tmp_path):
    """rm -rf of the folder of a running process once frame 10 is there: exit 1 and a closing
    line that says the folder disappeared."""
    out = tmp_path / "o"
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "SDL_VIDEODRIVER": "dummy"}
    child = subprocess.Popen([sys.executable, SIMULATOR, "--steps", "100000", "--frame-stride",
                              "1", "--out", str(out)], env=env, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while not (out / "frame_00010.png").exists():
        assert child.poll() is None and time.monotonic() < deadline
        time.sleep(0.02)
    while out.exists():             # rm -rf again where the run wrote a file as it was listed
        assert time.monotonic() < deadline
        shutil.rmtree(out, ignore_errors=True)
    assert child.wait(timeout=120) == 1
    last = ending(child.stderr.read().splitlines())
    assert last.endswith(f"nothing kept: {out}/ disappeared as the run wrote it"), last


def test_a_signal_while_the_folder_is_claimed_leaves_nothing_made(tmp_path, monkeypatch):
    """Ctrl+C as the folder is made and probed (signals held): Stopped once it is, and the folder,
    its parent and its claim are gone again, as 'nothing written' says (on main: left behind)."""
    signals = run.Signals()

    def interrupted_probe(folder, name):
        signals.pending = signal.SIGINT             # as the handler does while signals are held
    monkeypatch.setattr(files, "probe", interrupted_probe)
    with pytest.raises(run.Stopped):
        files.RunFolder.make(str(tmp_path / "p" / "o"), "square", ["log.csv"], signals)
    assert os.listdir(tmp_path) == []
