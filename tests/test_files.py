"""viewer/files.py: a run's folder is its own, tried as an attacker would: a name taken between the
check and the write, two runs at once, a user's new content under an owned name, another user's
manifest, a FIFO, a folder or manifest removed mid-run, names too long, and a platform without
POSIX-only names (os.O_NOFOLLOW, fcntl, file owners)."""
import errno
import os
import shutil
import signal
import subprocess
import sys
import time

import pytest

from helpers.command import run_main as main
from viewer import files, folder_lock, manifest, run, whole_files

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SIMULATOR = os.path.join(ROOT, "simulator.py")


def start(*args, **kwargs):
    """python simulator.py ARGS as a child process."""
    return subprocess.Popen([sys.executable, SIMULATOR, *args], cwd=ROOT, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, **kwargs)


def wait_for(path, timeout=60):
    deadline = time.monotonic() + timeout
    while not os.path.exists(path):
        assert time.monotonic() < deadline, f"{path} never appeared"
        time.sleep(0.05)


# ---- create, never replace ------------------------------------------------------------------------

def test_a_name_taken_between_the_check_and_the_write_is_never_overwritten(tmp_path, monkeypatch):
    """A user's file created (O_EXCL) under an output's name while the run writes it: the run's link
    fails, the user's file is untouched, the run ends in one line naming the output, not a temporary."""
    real = whole_files.write_temporary

    def race(path, data):
        ident = real(path, data)
        if path.endswith("summary.png"):
            fd = os.open(tmp_path / "summary.png", os.O_WRONLY | os.O_CREAT | os.O_EXCL)
            os.write(fd, b"the user's own")
            os.close(fd)
        return ident
    monkeypatch.setattr(whole_files, "write_temporary", race)
    code, lines = main("--steps", "5", "--no-frames", "--out", str(tmp_path))
    assert code == 1 and (tmp_path / "summary.png").read_bytes() == b"the user's own"
    assert "summary.png: a file of that name appeared" in lines[-1] and ".tmp-" not in lines[-1], lines
    assert not [n for n in os.listdir(tmp_path) if n.startswith(".tmp-")]


def test_a_folder_removed_mid_run_is_named_by_its_output(tmp_path, monkeypatch):
    """The output folder removed as a frame is written: the line names the frame, not its temporary."""
    real, calls = whole_files.write_temporary, []

    def gone(path, data):
        calls.append(path)
        if len(calls) == 5:
            shutil.rmtree(tmp_path / "out")
        return real(path, data)
    monkeypatch.setattr(whole_files, "write_temporary", gone)
    code, lines = main("--steps", "30", "--frame-stride", "1", "--out", str(tmp_path / "out"))
    assert code == 1 and "cannot write " in lines[-1] and ".tmp-" not in lines[-1], lines
    assert os.path.basename(calls[-1])[len(".tmp-12345678-"):] in lines[-1]


def test_a_manifest_removed_mid_run_is_written_again_whole(tmp_path, monkeypatch):
    """The manifest deleted during a run: the run writes it again from what it knows, so the next run
    still owns every file (and removes the stale frames)."""
    real, calls = whole_files.write_temporary, []

    def remove_manifest(path, data):
        calls.append(path)
        if len(calls) == 4:
            os.remove(tmp_path / files.MANIFEST)
        return real(path, data)
    monkeypatch.setattr(whole_files, "write_temporary", remove_manifest)
    assert main("--steps", "8", "--frame-stride", "1", "--out", str(tmp_path))[0] == 0
    listed = manifest.read_manifest(str(tmp_path))
    on_disk = set(os.listdir(tmp_path)) - set(files.OWN)
    assert set(listed) == on_disk and all(ident is not None for ident in listed.values())
    monkeypatch.undo()
    assert main("--steps", "3", "--frame-stride", "1", "--out", str(tmp_path))[0] == 0
    assert not (tmp_path / "frame_00005.png").exists()       # the longer run's frame: owned, removed


# ---- one run per folder -----------------------------------------------------------------------------

def test_a_second_claim_of_a_held_folder_is_refused_naming_the_holder(tmp_path):
    first = files.OutputFolder.claim(str(tmp_path), {"a.png"}, run.Signals())
    try:
        with pytest.raises(ValueError, match=rf"in use by another run \(pid {os.getpid()}\)"):
            files.OutputFolder.claim(str(tmp_path), {"b.png"}, run.Signals())
    finally:
        first.close()
    files.OutputFolder.claim(str(tmp_path), {"b.png"}, run.Signals()).close()      # free again
    assert os.listdir(tmp_path) == [files.MANIFEST]            # the lock goes with its run


def test_two_runs_into_one_folder_at_once(tmp_path):
    """The second run is refused before it touches anything (exit 2, the holder's pid); the first
    finishes as if alone, and the folder is usable afterwards."""
    out = tmp_path / "o"
    first = start("--steps", "400", "--out", str(out))
    wait_for(out / "frame_00002.png")
    second = subprocess.run([sys.executable, SIMULATOR, "--steps", "20", "--out", str(out)], cwd=ROOT,
                            capture_output=True, text=True, timeout=120)
    assert second.returncode == 2 and f"in use by another run (pid {first.pid})" in second.stderr, second.stderr
    assert second.stderr.count("\n") == 1
    figures = subprocess.run([sys.executable, "-m", "figures", "mollifier", "--out", str(out)], cwd=ROOT,
                             capture_output=True, text=True, timeout=120)
    assert figures.returncode == 2 and f"pid {first.pid}" in figures.stderr
    assert first.wait(timeout=300) == 0, first.stderr.read()
    rows = (out / "log.csv").read_text().splitlines()
    assert len(rows) == 402 and (out / "index.html").exists() and not (out / "mollifier.png").exists()
    assert main("--steps", "3", "--out", str(out))[0] == 0


def test_a_run_killed_with_sigkill_leaves_a_folder_the_next_run_takes_over(tmp_path):
    if not hasattr(signal, "SIGKILL"):
        pytest.skip("no SIGKILL on this platform")
    out = tmp_path / "o"
    child = start("--steps", "2000", "--out", str(out))
    wait_for(out / "frame_00003.png")
    child.kill()
    child.wait(timeout=60)
    assert (out / files.LOCK).exists()              # left behind, but no longer locked by anyone
    code, lines = main("--steps", "3", "--out", str(out))
    assert code == 0, lines
    assert not (out / "frame_00004.png").exists() and not (out / files.LOCK).exists()


def test_a_stale_lock_file_is_taken_over_where_the_file_is_the_lock(tmp_path, monkeypatch):
    """Where the platform has no lock of its own (lock() gives None), the file is the lock: held while
    its pid runs, taken over once it no longer does."""
    monkeypatch.setattr(folder_lock, "lock", lambda fd: None)
    (tmp_path / files.LOCK).write_text(f"{os.getpid()} now\n")
    with pytest.raises(ValueError, match=rf"pid {os.getpid()}"):
        files.OutputFolder.claim(str(tmp_path), {"a.png"}, run.Signals())
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    (tmp_path / files.LOCK).write_text(f"{dead.stdout.strip()} earlier\n")
    folder = files.OutputFolder.claim(str(tmp_path), {"a.png"}, run.Signals())
    assert (tmp_path / files.LOCK).read_text().split()[0] == str(os.getpid())
    folder.close()


# ---- ownership by identity -------------------------------------------------------------------------

def test_a_users_new_content_under_an_owned_name_is_never_removed(tmp_path):
    assert main("--steps", "3", "--out", str(tmp_path))[0] == 0
    (tmp_path / "log.csv").write_text("mine\n")            # the same inode, new content
    code, lines = main("--steps", "3", "--out", str(tmp_path))
    assert code == 2 and "log.csv, changed since this simulator wrote it" in lines[0]
    assert (tmp_path / "log.csv").read_text() == "mine\n"


def test_a_changed_file_the_run_would_only_remove_is_refused_too(tmp_path):
    """A frame of a longer earlier run, edited by the user: the shorter run would remove it as stale;
    it refuses instead, naming it."""
    assert main("--steps", "9", "--frame-stride", "1", "--out", str(tmp_path))[0] == 0
    (tmp_path / "frame_00008.obj").write_text("my edit\n")
    code, lines = main("--steps", "3", "--frame-stride", "1", "--out", str(tmp_path))
    assert code == 2 and "frame_00008.obj, changed since" in lines[0]
    assert (tmp_path / "frame_00008.obj").read_text() == "my edit\n" and (tmp_path / "frame_00002.png").exists()


@pytest.mark.skipif(not whole_files.HAS_OWNERS, reason="no file owners on this platform")
def test_a_manifest_others_may_write_is_refused_and_nothing_removed(tmp_path):
    assert main("--steps", "3", "--out", str(tmp_path))[0] == 0
    before = sorted(os.listdir(tmp_path))
    os.chmod(tmp_path / files.MANIFEST, 0o622)
    code, lines = main("--steps", "3", "--out", str(tmp_path))
    assert code == 2 and files.MANIFEST in lines[0] and sorted(os.listdir(tmp_path)) == before


@pytest.mark.skipif(not whole_files.HAS_OWNERS, reason="no file owners on this platform")
def test_a_manifest_planted_by_another_user_is_refused(tmp_path):
    """In a folder others may write to, another user's manifest listing the user's file: refused, the
    file kept. Planting it needs another uid: the test runs as root, or says why it cannot."""
    if os.geteuid() != 0:
        pytest.skip("planting a file owned by another uid needs root")
    os.chmod(tmp_path, 0o1777)
    (tmp_path / "thesis.tex").write_text("years of work")
    st = os.stat(tmp_path / "thesis.tex")
    (tmp_path / files.MANIFEST).write_text(
        f"{manifest.HEADER}\nthesis.tex\t{st.st_dev}\t{st.st_ino}\t{st.st_size}\t{st.st_mtime_ns}\n")
    os.chmod(tmp_path / files.MANIFEST, 0o600)
    os.chown(tmp_path / files.MANIFEST, 65534, 65534)
    code, lines = main("--steps", "3", "--out", str(tmp_path))
    assert code == 2 and "another user could have written" in lines[0]
    assert (tmp_path / "thesis.tex").read_text() == "years of work"


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs on this platform")
@pytest.mark.parametrize("name", [files.MANIFEST, files.LOCK])
def test_a_fifo_in_place_of_the_folders_own_files_is_refused_at_once(tmp_path, name):
    out = tmp_path / "o"
    out.mkdir()
    os.mkfifo(tmp_path / "fifo")
    os.symlink(tmp_path / "fifo", out / name)
    began = time.monotonic()
    done = subprocess.run([sys.executable, SIMULATOR, "--steps", "3", "--out", str(out)], cwd=ROOT,
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 2 and name in done.stderr and time.monotonic() - began < 20
    os.remove(out / name)
    os.mkfifo(out / name)
    began = time.monotonic()
    assert main("--steps", "3", "--out", str(out))[0] == 2 and time.monotonic() - began < 1.0


# ---- refused before claimed ---------------------------------------------------------------------------

def test_a_list_value_making_a_name_too_long_is_refused_before_anything_is_written(tmp_path):
    value = "0." + "1" * 250
    code, lines = main("--mu", f"0.2,{value}", "--steps", "3", "--out", str(tmp_path / "o"))
    assert code == 2 and len(lines) == 1 and "output name 'log_mu0.111" in lines[0] and "too long" in lines[0]
    assert not (tmp_path / "o").exists()


def test_an_out_folder_too_long_leaves_nothing_behind(tmp_path):
    deep = os.path.join(str(tmp_path), *["d" * 200] * 16, "x" * 300)
    code, lines = main("--steps", "3", "--out", deep)
    assert code == 2 and lines[0].startswith("simulator.py: error: --out: ") and os.listdir(tmp_path) == []
    deep = os.path.join(str(tmp_path), *["d" * 250] * 20)
    code, lines = main("--steps", "3", "--out", deep)
    assert code == 2 and "too deep" in lines[0] and os.listdir(tmp_path) == []


def test_a_folder_that_cannot_be_made_leaves_no_parent_behind(tmp_path, monkeypatch):
    real = os.mkdir

    def fail_the_last(path, *args):
        if os.path.basename(path) == "c":
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), path)
        real(path, *args)
    monkeypatch.setattr(os, "mkdir", fail_the_last)
    code, lines = main("--steps", "3", "--out", str(tmp_path / "a" / "b" / "c"))
    assert code == 2 and "cannot be created" in lines[0] and os.listdir(tmp_path) == []


# ---- without POSIX-only names (as on Windows) ----------------------------------------------------------

WITHOUT_POSIX = """
import os, runpy, sys
for name in ("O_NOFOLLOW", "O_NONBLOCK", "geteuid", "getuid", "pathconf", "fchmod", "mkfifo"):
    if hasattr(os, name):
        delattr(os, name)
sys.modules["fcntl"] = None             # import fcntl fails, as on Windows (and msvcrt is not there)
sys.argv = [sys.argv[1]] + sys.argv[2:]
runpy.run_path(sys.argv[0], run_name="__main__")
"""


def without_posix(*args):
    return subprocess.run([sys.executable, "-c", WITHOUT_POSIX, SIMULATOR, *args], cwd=ROOT, capture_output=True,
                          text=True, timeout=300)


def test_the_main_job_and_its_refusals_without_posix_only_names(tmp_path):
    """The main job, then a symbolic link under an output's name, a user's file, and a held folder: each
    kept as on POSIX, with no O_NOFOLLOW, no fcntl (the lock file is the lock), no file owners."""
    out = tmp_path / "o"
    done = without_posix("--steps", "12", "--frame-stride", "3", "--out", str(out))
    assert done.returncode == 0, done.stderr
    assert (out / "index.html").exists() and len((out / "log.csv").read_text().splitlines()) == 14
    (out / "frame_00002.png").unlink()
    (tmp_path / "target").write_text("mine")
    os.symlink(tmp_path / "target", out / "frame_00002.png")
    done = without_posix("--steps", "12", "--frame-stride", "3", "--out", str(out))
    assert done.returncode == 2 and "frame_00002.png, a symbolic link" in done.stderr
    assert (tmp_path / "target").read_text() == "mine" and (out / "frame_00002.png").is_symlink()
    (out / "frame_00002.png").unlink()
    (out / files.LOCK).write_text(f"{os.getpid()} now\n")          # a live holder
    done = without_posix("--steps", "12", "--out", str(out))
    assert done.returncode == 2 and f"pid {os.getpid()}" in done.stderr
    assert (out / files.LOCK).read_text().startswith(str(os.getpid()))


# ---- reporting never stops the work ----------------------------------------------------------------

SHELL = os.name == "posix" and os.path.exists("/dev/full")


@pytest.mark.skipif(not SHELL, reason="needs a POSIX shell and /dev/full")
@pytest.mark.parametrize("redirect", ["2>&1 | head -1", "2>/dev/full", ">/dev/full 2>&1", "2>&-"])
def test_a_broken_or_full_stderr_changes_nothing_a_run_computes(tmp_path, redirect):
    """Progress and closing lines are best effort: the run still writes every file and exits 0."""
    reference = tmp_path / "ref"
    assert subprocess.run([sys.executable, SIMULATOR, "--steps", "120", "--out", str(reference)], cwd=ROOT,
                          capture_output=True, timeout=300).returncode == 0
    out = tmp_path / "o"
    cmd = f"'{sys.executable}' '{SIMULATOR}' --steps 120 --out '{out}' {redirect}; echo \"rc=$?\" >'{tmp_path}/rc'"
    if "|" in redirect:
        cmd = (f"'{sys.executable}' '{SIMULATOR}' --steps 120 --out '{out}' {redirect}; "
               f"echo \"rc=${{PIPESTATUS[0]}}\" >'{tmp_path}/rc'")
    subprocess.run(["bash", "-c", cmd], cwd=ROOT, capture_output=True, timeout=300)
    assert (tmp_path / "rc").read_text().strip() == "rc=0"
    assert sorted(os.listdir(out)) == sorted(os.listdir(reference))
    strip = [lambda row: row.split(",", 3)[:2] + row.split(",", 3)[3:]]      # wall_s differs
    rows = [[strip[0](r) for r in (d / "log.csv").read_text().splitlines()] for d in (reference, out)]
    assert rows[0] == rows[1]


@pytest.mark.skipif(not SHELL, reason="needs a POSIX shell and /dev/full")
@pytest.mark.parametrize("redirect", [">/dev/full", "| head -0", ">&-"])
def test_figures_with_a_full_or_closed_stdout_still_end_well(tmp_path, redirect):
    cmd = f"'{sys.executable}' -m figures mollifier --out '{tmp_path}' {redirect}; echo \"rc=${{PIPESTATUS[0]}}\""
    done = subprocess.run(["bash", "-c", cmd], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert done.stdout.strip().endswith("rc=0") and done.stderr == "" and (tmp_path / "mollifier.png").exists()


SELF_TERMINATING = """
import os, signal, sys, types
sys.path.insert(0, sys.argv[1])
os.close(2)                                     # stderr closed: the start-up line cannot be written
module = types.ModuleType("loading")            # stands for viewer.cli while numpy and scipy load
module.main = lambda argv: os.kill(os.getpid(), signal.SIGTERM) or 0
sys.modules["loading"] = module
from viewer import startup
sys.exit(startup.run_command_line(main="loading"))
"""


def test_sigterm_at_start_up_with_stderr_closed_exits_143():
    done = subprocess.run([sys.executable, "-c", SELF_TERMINATING, ROOT], capture_output=True, timeout=60)
    assert done.returncode == 143
