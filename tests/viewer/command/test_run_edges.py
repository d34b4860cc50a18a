"""A run's edges, tried as a careful user would: their own files in the output folder, symbolic
links, a signal in each phase of the run, repeated flags, negative values in lists, flags that do
not apply, a full disk, and a state beyond float64 handed to the library."""
import errno
import os
import shutil
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import simulator
import time_integrator
import analysis.log
from helpers.command import ending, run_main as main
from helpers.fakes import signal_dropped_at_step
from helpers import ROOT
from viewer.command import cli, run
from viewer.output import files, whole_files
from viewer.pictures import draw, plots


def log_steps(path):
    """The steps log.csv holds, after checking every row is whole."""
    rows = path.read_text().splitlines()
    assert rows[0] == ",".join(analysis.log.COLUMNS)
    assert all(len(r.split(",")) == len(analysis.log.COLUMNS) for r in rows)
    return [int(r.split(",")[0]) for r in rows[1:]]


def leftovers(folder):
    """Temporary files left in the folder (names starting with '.')."""
    return [name for name in os.listdir(folder) if name.startswith(".")]


# ---- a run writes only into a new or empty folder

USERS = ["log.csv", "index.html", "plots.png", "summary.png", "frame_00003.png", "notes.txt"]


@pytest.mark.parametrize("name", USERS)
def test_a_users_file_in_the_out_folder_is_never_touched(tmp_path, name):
    """Whatever the user's file is called: refused before anything is written, in one line that says
    how to go on; the folder is as it was."""
    (tmp_path / name).write_text("the user's own")
    code, lines = main("--steps", "3", "--frame-stride", "1", "--out", str(tmp_path))
    assert code == 2 and len(lines) == 1, lines
    assert lines[0].startswith("simulator.py: error: --out: ") and "is not empty" in lines[0]
    assert "choose another --out" in lines[0]
    assert os.listdir(tmp_path) == [name] and (tmp_path / name).read_text() == "the user's own"


def test_a_symbolic_link_in_the_out_folder_is_never_written_through(tmp_path):
    """A dangling link with an output's name: refused, nothing written where it points."""
    out, target = tmp_path / "out", tmp_path / "elsewhere"
    out.mkdir()
    (out / "log.csv").symlink_to(target)
    code, lines = main("--steps", "3", "--frame-stride", "1", "--out", str(out))
    assert code == 2 and "is not empty" in lines[0] and not target.exists()
    assert os.listdir(out) == ["log.csv"]


# ---- a signal in each phase

def signal_during(monkeypatch, module, name, signum=signal.SIGINT):
    """Send this process `signum` the first time module.name is called (as a user's Ctrl+C would
    arrive at that moment), then run it."""
    real, sent = getattr(module, name), []

    def with_signal(*args, **kw):
        if not sent:
            sent.append(signum)
            os.kill(os.getpid(), signum)
        return real(*args, **kw)
    monkeypatch.setattr(module, name, with_signal)


def test_a_signal_while_pygame_loads_ends_the_run_in_one_line(tmp_path, monkeypatch):
    """pygame loads whole (no half-initialized module), then the run stops: exit 130, its one
    ending line (folded where the path makes it long)."""
    signal_during(monkeypatch, draw, "load_pygame")
    code, lines = main("--steps", "3", "--out", str(tmp_path))
    assert code == 130 and lines[0].startswith("simulator.py: "), lines
    assert ending(lines) == f"simulator.py: stopped: interrupted; nothing written in {tmp_path}/"
    import pygame
    assert pygame.font.get_init() and hasattr(pygame, "Surface")


@pytest.mark.parametrize("signum, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_signal_while_a_frame_is_written_keeps_files_whole(tmp_path, monkeypatch, signum, code):
    """The frame being written is finished, whole; no temporary is left; the steps kept are the last
    step in log.csv, and the last pictures are written for them: the line links the page."""
    real = whole_files.write_temporary

    def write(path, data):
        if path.endswith("-frame_00003.png"):     # the signal arrives as frame 3's PNG is written
            os.kill(os.getpid(), signum)
        return real(path, data)
    monkeypatch.setattr(whole_files, "write_temporary", write)
    status, lines = main("--steps", "300", "--frame-stride", "1", "--out", str(tmp_path))
    assert status == code and ending(lines).startswith("simulator.py: stopped: "), lines
    steps = log_steps(tmp_path / "log.csv")
    page = (tmp_path / "index.html").as_uri()
    assert ending(lines).endswith(f"; {steps[-1]} steps kept in {tmp_path}/; the page: {page}")
    assert steps == list(range(steps[-1] + 1))
    assert (tmp_path / "frame_00003.png").stat().st_size > 0 and not leftovers(tmp_path)
    assert all((tmp_path / name).exists() for name in ("summary.png", "plots.png", "index.html"))


@pytest.mark.parametrize("signum, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_signal_during_the_last_pictures_leaves_out_the_rest(tmp_path, monkeypatch, signum, code):
    """summary.png is written before the signal; plots.png and index.html are left out, and the line
    says so; the frames and log are kept whole."""
    signal_during(monkeypatch, plots, "draw_plots", signum)
    status, lines = main("--steps", "20", "--out", str(tmp_path))
    said = [line for line in lines if line.startswith("simulator.py:")]    # the others: progress
    assert status == code and len(said) == 1, lines
    assert ending(lines).startswith("simulator.py: stopped: ")
    assert "while writing the last pictures" in ending(lines)
    assert ending(lines).endswith(f"20 steps kept in {tmp_path}/; left out: plots.png, index.html")
    names = os.listdir(tmp_path)
    assert "summary.png" in names and "plots.png" not in names and "index.html" not in names
    assert log_steps(tmp_path / "log.csv") == list(range(21)) and not leftovers(tmp_path)


def test_ctrl_c_at_any_moment_of_a_real_run_is_one_line(tmp_path):
    """Real processes, Ctrl+C at moments from loading numpy to the frames: exit 130, the last line
    says it stopped, no traceback, no temporary file. Started together, one signal each."""
    delays = (0.5, 1.0, 2.0)        # (before 0.1 s Python itself is still starting: not yet ours)
    env = {**os.environ, "SDL_VIDEODRIVER": "dummy"}
    processes = [subprocess.Popen([sys.executable, os.path.join(ROOT, "simulator.py"),
                                   "--steps", "100000", "--out", str(tmp_path / str(k))],
                                  env=env, stderr=subprocess.PIPE, text=True)
                 for k in range(len(delays))]
    began = time.monotonic()
    for delay, process in zip(delays, processes):
        time.sleep(max(0.0, began + delay - time.monotonic()))
        process.send_signal(signal.SIGINT)
    for k, process in enumerate(processes):
        _, err = process.communicate(timeout=60)
        assert process.returncode == 130, err
        assert "Traceback" not in err
        assert ending(err.strip().splitlines()).startswith("simulator.py: stopped: interrupted")
        assert not (tmp_path / str(k)).exists() or not leftovers(tmp_path / str(k))


@pytest.mark.parametrize("signum, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_signal_whose_raise_cpython_drops_still_stops_the_run(tmp_path, monkeypatch, signum,
                                                                code):
    """Noted as it came: the run stops after that step's log row, in one line, no traceback (on
    main it ran on to the end, exit 0, 'Exception ignored' and a traceback on stderr)."""
    signal_dropped_at_step(monkeypatch, 3, signum)
    status, lines = main("--steps", "30", "--out", str(tmp_path))
    assert status == code and lines[-1].startswith("simulator.py: stopped: "), lines
    assert not any("Traceback" in line or "Exception ignored" in line for line in lines), lines
    assert log_steps(tmp_path / "log.csv") == list(range(5))    # step 3 -> row 4, then stopped
    assert lines[-1].endswith(f"; 4 steps kept in {tmp_path}/; the page: "
                              f"{(tmp_path / 'index.html').as_uri()}")


def test_a_signal_after_a_dropped_one_ends_the_run_as_the_first(tmp_path, monkeypatch):
    """SIGINT noted, its raise dropped, then SIGTERM within the step: 'interrupted', 130, as the
    first signal ends a run (it said 'terminated (SIGTERM)', 143: the second's Stopped raised)."""
    signal_dropped_at_step(monkeypatch, 3, signal.SIGINT)
    dropped = time_integrator.step

    def step(scene, x, v, step_index=0, **kw):
        record = dropped(scene, x, v, step_index=step_index, **kw)
        if step_index == 3:
            os.kill(os.getpid(), signal.SIGTERM)
        return record
    monkeypatch.setattr(time_integrator, "step", step)
    status, lines = main("--steps", "30", "--no-frames", "--out", str(tmp_path))
    assert (status, lines[-1]) == (130, f"simulator.py: stopped: interrupted; 3 steps kept in "
                                        f"{tmp_path}/"), lines


def test_a_second_signal_as_the_first_is_caught_waits(tmp_path, monkeypatch):
    """SIGTERM as the run turns SIGINT's Stopped into its ending (as a second signal sent with
    the first runs): the run ends as interrupted, its pictures written, its folder released (the
    second Stopped escaped to_files: 'stopped: terminated (SIGTERM); nothing written', the
    claim left in the folder)."""
    real_step, real_failure_of = time_integrator.step, run.failure_of

    def step(scene, x, v, step_index=0, **kw):
        if step_index == 3:
            os.kill(os.getpid(), signal.SIGINT)
        return real_step(scene, x, v, step_index=step_index, **kw)

    def failure_of(err, plan, when=""):
        os.kill(os.getpid(), signal.SIGTERM)
        return real_failure_of(err, plan, when)
    monkeypatch.setattr(time_integrator, "step", step)
    monkeypatch.setattr(run, "failure_of", failure_of)
    status, lines = main("--steps", "30", "--out", str(tmp_path))
    assert (status, lines[-1]) == (130, f"simulator.py: stopped: interrupted; 3 steps kept in "
                                        f"{tmp_path}/; the page: "
                                        f"{(tmp_path / 'index.html').as_uri()}"), lines
    assert not leftovers(tmp_path) and not (tmp_path / files.CLAIM).exists()


# ---- the command line

@pytest.mark.parametrize("args, flag", [(["--mu", "0,1", "--mu", "0.5"], "--mu"),
                                        (["--h", "0.01,0.02", "--dt", "0.005"], "--h"),
                                        (["--mu", "0.5", "--mu=0.1,0.2"], "--mu")])
def test_a_list_flag_given_twice_is_refused(tmp_path, args, flag):
    code, lines = main(*args, "--out", str(tmp_path / "o"))
    assert code == 2 and len(lines) == 1, lines
    assert lines[0].startswith(f"simulator.py: error: {flag}: ")
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("flag, values, parsed", [
    ("--v0", "1,0;-2,0", [(1.0, 0.0), (-2.0, 0.0)]),
    ("--center", "0,0;-1,1", [(0.0, 0.0), (-1.0, 1.0)]),
    ("--gravity", "0,-9.81;-1,-9.81", [(0.0, -9.81), (-1.0, -9.81)])])
def test_lists_of_pairs_take_negative_numbers(flag, values, parsed):
    for argv in ([flag, values], [f"{flag}={values}"]):
        runs = cli.parse_command_line(argv)
        assert [getattr(r, flag.lstrip("-")) for r in runs] == parsed
        assert [r.label for r in runs] == [f"{flag.lstrip('-')} = {v}" for v in values.split(";")]


def test_lists_of_numbers_take_negative_numbers():
    """Parsed as numbers; the scene then refuses mu < 0, naming the flag."""
    assert [r.k for r in cli.parse_command_line(["--k", "-1,2e4"])] == [-1.0, 2e4]
    assert [r.mu for r in cli.parse_command_line(["--mu", "0.2,-0.5"])] == [0.2, -0.5]
    code, lines = main("--mu", "0.2,-0.5", "--steps", "2")
    assert code == 2 and lines == ["simulator.py: error: --mu: mu must be >= 0, got -0.5"]


def test_a_comparison_with_negative_values_runs_and_names_its_files(tmp_path):
    code, lines = main("--v0", "1,0;-2,0", "--steps", "2", "--no-frames", "--out", str(tmp_path))
    assert code == 0, lines
    assert {"log_v0_1_0.csv", "log_v0_-2_0.csv"} <= set(os.listdir(tmp_path))
    assert not [name for name in os.listdir(tmp_path) if "=" in name]


@pytest.mark.parametrize("args, flag", [
    (["--speed", "-5"], "--speed"), (["--size", "nan"], "--size"), (["--speed", "2"], "--speed"),
    (["--density", "500", "--mass", "10"], "--mass"),
    (["--steps", "3", "--duration", "1"], "--duration"),
    (["--no-slope", "--slope-angle", "10"], "--slope-angle")])
def test_flags_that_do_not_apply_or_contradict_are_refused(tmp_path, args, flag):
    code, lines = main(*args, "--out", str(tmp_path / "o"))
    assert code == 2 and len(lines) == 1, lines
    assert lines[0].startswith("simulator.py: error: ") and flag in lines[0]
    assert not (tmp_path / "o").exists()


def test_the_library_refuses_density_and_mass_together():
    with pytest.raises(ValueError, match=r"^mass = 10.0 and rho = 500.0 are both given"):
        simulator.build_scene(rho=500.0, mass=10.0)
    assert simulator.build_scene(mass=10.0).m.sum() == pytest.approx(10.0)


# ---- the library

def test_an_accepted_iterate_beyond_float64_raises(monkeypatch):
    """E(x^n) finite, a trial point's E = -inf (overflowed): it would be accepted as a decrease,
    and the step raises NonFiniteState instead of returning it."""
    real = time_integrator.IP_val

    def overflowing(scene, lagged, x):
        return real(scene, lagged, x) if np.array_equal(x, scene.x0) else -np.inf
    monkeypatch.setattr(time_integrator, "IP_val", overflowing)
    scene = simulator.build_scene()
    with pytest.raises(time_integrator.NonFiniteState, match="E=-inf"):
        time_integrator.step(scene, scene.x0, scene.v0)


@pytest.mark.parametrize("overrides, culprit", [(dict(h=1e-320), "h"), (dict(dhat=1e-300), "dhat")])
def test_tiny_values_are_refused_naming_themselves(overrides, culprit):
    """h whose square underflows; a dhat so small the barrier's curvature 1/dhat overflows."""
    with pytest.raises(ValueError, match=f"^{culprit} = "):
        simulator.build_scene(**overrides)


def test_a_step_from_a_state_beyond_float64_raises():
    """E(x^n) = inf (x_tilde = x^n + h v^n overflows the inertia term): NonFiniteState, never a
    'stalled' step that returns v = 0."""
    scene = simulator.build_scene()
    with pytest.raises(time_integrator.NonFiniteState, match="not finite"):
        time_integrator.step(scene, scene.x0, scene.v0 + [0.0, -1e200])
    x, v, report = time_integrator.step(scene, scene.x0, scene.v0 + [0.0, -1e3])  # large, finite
    assert np.isfinite(x).all() and not report.stalled


# ---- a full disk

@pytest.fixture
def small_disk(tmp_path):
    """A 64 KiB tmpfs, where this machine lets the test mount one (root on Linux); else skipped."""
    mount = tmp_path / "disk"
    mount.mkdir()
    command = ["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(mount)]
    if shutil.which("mount") is None or subprocess.run(command, capture_output=True).returncode:
        pytest.skip("cannot mount a tmpfs here (needs root on Linux) to fill a disk for real")
    yield mount
    subprocess.run(["umount", str(mount)], check=True)


def fill(folder):
    """Fill the disk `folder` is on with a file of the user's, to the last byte."""
    fd = os.open(folder / "users-file", os.O_WRONLY | os.O_CREAT)
    try:
        while True:
            os.write(fd, b"\0" * 4096)
    except OSError as err:
        assert err.errno == errno.ENOSPC
    finally:
        os.close(fd)


def test_a_run_refused_on_a_full_disk_leaves_nothing_behind(small_disk):
    """The folders it made for the run are removed again when no file can be written in them."""
    fill(small_disk)
    before = sorted(os.listdir(small_disk))
    code, lines = main("--steps", "3", "--out", str(small_disk / "new" / "out"))
    assert code == 2 and len(lines) == 1, lines
    assert "cannot be written" in lines[0] and "No space left" in lines[0]
    assert sorted(os.listdir(small_disk)) == before


def test_a_full_disk_without_out_blames_the_folder_not_the_flag(small_disk, monkeypatch):
    """No --out given: the line names the folder tried under output/, not --out (it said
    '--out: out folder ... cannot be written', a flag the student never gave)."""
    monkeypatch.chdir(small_disk)
    fill(small_disk)
    code, lines = main("--steps", "3")
    assert code == 2 and len(lines) == 1, lines
    assert lines[0].startswith("simulator.py: error: folder 'output/square-"), lines
    assert lines[0].endswith("cannot be written: No space left on device"), lines
    assert sorted(os.listdir(small_disk / "output")) == []


def test_an_empty_read_only_folder_is_refused(small_disk):
    """An empty folder on a read-only disk: one line, exit 2, before anything else."""
    subprocess.run(["mount", "-o", "remount,ro", str(small_disk)], check=True)
    try:
        code, lines = main("--steps", "2", "--out", str(small_disk))
    finally:
        subprocess.run(["mount", "-o", "remount,rw", str(small_disk)], check=True)
    assert code == 2 and len(lines) == 1, lines
    assert "cannot be written: Read-only file system" in lines[0]
    assert os.listdir(small_disk) == []


def test_a_disk_filling_mid_run_keeps_a_true_count(small_disk):
    """--no-frames: log.csv fills the disk; 'steps kept' in the line is the last step it holds."""
    code, lines = main("--steps", "100000", "--no-frames", "--out", str(small_disk))
    said = f"cannot write {small_disk / 'log.csv'}: No space left on device"
    assert code == 1 and said in ending(lines), lines
    steps = log_steps(small_disk / "log.csv")
    assert f"; {steps[-1]} steps kept in {small_disk}/" in ending(lines)
    assert steps == list(range(steps[-1] + 1))
    assert not leftovers(small_disk)
