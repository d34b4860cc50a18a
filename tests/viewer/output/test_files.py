"""viewer/output/files.py: a run writes only into a new folder it made (or an empty one --out
names), tried as an attacker would: a name taken between the check and the write (runs at once:
test_claim.py), a folder that holds files or is another user's, a folder removed mid-run, names
too long, and a platform without POSIX-only names (os.O_NOFOLLOW, file owners)."""
import errno
import os
import shutil
import subprocess
import sys
import time

import pytest

from figures import cli as figures_cli
from helpers import ROOT
from helpers.command import ending, run_main as main
from viewer.output import whole_files

SIMULATOR = os.path.join(ROOT, "simulator.py")


def start(*args, **kwargs):
    """python simulator.py ARGS as a child process."""
    return subprocess.Popen([sys.executable, SIMULATOR, *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, **kwargs)


def wait_for(path, timeout=60):
    deadline = time.monotonic() + timeout
    while not os.path.exists(path):
        assert time.monotonic() < deadline, f"{path} never appeared"
        time.sleep(0.05)


# ---- create, never replace

def test_a_name_taken_between_the_check_and_the_write_is_never_overwritten(tmp_path, monkeypatch):
    """A user's file created (O_EXCL) under an output's name while the run writes it: the run's
    link fails, the user's file is untouched, the run ends in one line naming the output, not a
    temporary."""
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
    assert "summary.png: a file of that name appeared" in ending(lines), lines
    assert ".tmp-" not in ending(lines)
    assert not [n for n in os.listdir(tmp_path) if n.startswith(".tmp-")]


def test_a_folder_removed_mid_run_is_named_by_its_output(tmp_path, monkeypatch):
    """The output folder removed as a frame is written: the line names the frame, not its
    temporary, and says the folder disappeared."""
    real, calls = whole_files.write_temporary, []

    def gone(path, data):
        calls.append(path)
        if len(calls) == 5:
            shutil.rmtree(tmp_path / "out")
        return real(path, data)
    monkeypatch.setattr(whole_files, "write_temporary", gone)
    code, lines = main("--steps", "30", "--frame-stride", "1", "--out", str(tmp_path / "out"))
    said = ending(lines)
    assert code == 1 and "cannot write " in said and ".tmp-" not in said, lines
    assert os.path.basename(calls[4])[len(".tmp-12345678-"):] in said
    assert said.endswith("out/ disappeared as the run wrote it")


# ---- a new folder for each run (runs started at once, each into its own: test_claim.py)

def test_the_closing_line_counts_the_files_and_names_the_page(tmp_path, monkeypatch):
    """Its last line: how many files the folder holds, and its page (the folder is the page's)."""
    monkeypatch.chdir(tmp_path)
    code, lines = main("--steps", "3")
    folder = next((tmp_path / "output").iterdir())
    page = (folder / "index.html").as_uri()
    assert code == 0 and lines[-1] == f"wrote {len(os.listdir(folder))} files, the page: {page}"
    code, lines = main("--steps", "3", "--no-frames", "--out", "plain")
    assert code == 0 and lines[-1] == "wrote 3 files in plain/"        # log, plots, summary


def test_a_second_run_into_the_same_out_is_refused_and_changes_nothing(tmp_path):
    """--out names a new or empty folder: a second run there, or python -m figures, during the
    first or after it, is refused in one line, exit 2, and the first run's files are as it wrote
    them."""
    out = tmp_path / "o"
    first = start("--steps", "60", "--frame-stride", "1", "--out", str(out), cwd=ROOT)
    wait_for(out / "frame_00002.png")
    code, lines = main("--steps", "20", "--out", str(out))
    assert code == 2 and len(lines) == 1 and "is not empty" in lines[0], lines
    assert first.poll() is None             # still running: refused during the first
    assert figures_cli.main(["mollifier", "--out", str(out)]) == 2
    assert first.wait(timeout=300) == 0, first.stderr.read()
    rows = (out / "log.csv").read_text().splitlines()
    assert len(rows) == 62 and (out / "index.html").exists()
    assert not (out / "mollifier.png").exists()
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    assert main("--steps", "3", "--out", str(out))[0] == 2
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before


def test_an_empty_folder_is_taken_and_a_file_is_not(tmp_path):
    (tmp_path / "empty").mkdir()
    assert main("--steps", "3", "--no-frames", "--out", str(tmp_path / "empty"))[0] == 0
    (tmp_path / "a_file").write_text("mine")
    code, lines = main("--steps", "3", "--out", str(tmp_path / "a_file"))
    assert code == 2 and "is not a folder" in lines[0]
    assert (tmp_path / "a_file").read_text() == "mine"


@pytest.mark.skipif(not whole_files.HAS_OWNERS, reason="no file owners on this platform")
def test_a_folder_others_may_write_to_or_another_users_is_refused(tmp_path):
    """Others could plant names in it while the run writes: refused, nothing made. Another user's
    folder needs another uid to make: as root here, or skipped saying why."""
    shared = tmp_path / "shared"
    shared.mkdir()
    os.chmod(shared, 0o777)
    code, lines = main("--steps", "3", "--out", str(shared))
    assert code == 2 and "writable by others" in lines[0] and os.listdir(shared) == []
    if os.geteuid() != 0:
        pytest.skip("a folder owned by another uid needs root to make")
    os.chmod(shared, 0o755)
    os.chown(shared, 65534, 65534)
    code, lines = main("--steps", "3", "--out", str(shared))
    assert code == 2 and "another user's" in lines[0] and os.listdir(shared) == []


def test_a_link_planted_under_an_outputs_name_is_never_written_through(tmp_path, monkeypatch):
    """A link to a user's file planted mid-run under the name of the next output: the run's link
    fails, the user's file is untouched, one line names the output."""
    real = whole_files.write_temporary
    (tmp_path / "thesis.tex").write_text("years of work")

    def plant(path, data):
        real(path, data)
        if path.endswith("plots.png"):
            os.symlink(tmp_path / "thesis.tex", tmp_path / "o" / "plots.png")
    monkeypatch.setattr(whole_files, "write_temporary", plant)
    code, lines = main("--steps", "5", "--no-frames", "--out", str(tmp_path / "o"))
    assert code == 1 and "plots.png: a file of that name appeared" in ending(lines)
    assert (tmp_path / "thesis.tex").read_text() == "years of work"


# ---- refused before claimed

def test_a_list_value_making_a_name_too_long_is_refused_before_anything_is_written(tmp_path):
    value = "0." + "1" * 250
    code, lines = main("--mu", f"0.2,{value}", "--steps", "3", "--out", str(tmp_path / "o"))
    assert code == 2 and len(lines) == 1, lines
    assert "output name 'log_mu0.111" in lines[0] and "too long" in lines[0]
    assert not (tmp_path / "o").exists()


def folders_of_length(top, length):
    """Folders of at most 250 bytes below `top`, making a path `length` bytes long."""
    parts, left = [], length - len(top)
    while left > 1:
        parts.append("d" * min(250, left - 1))
        left -= len(parts[-1]) + 1
    return os.path.join(top, *parts)


@pytest.mark.parametrize("folder, why", [
    (lambda top: os.path.join(top, *["d" * 200] * 16, "x" * 300), "cannot be created"),
    (lambda top: os.path.join(top, *["d" * 250] * 20), "cannot be created"),
    (lambda top: folders_of_length(top, 4080), "cannot be written")])
def test_an_out_folder_too_long_leaves_nothing_behind(tmp_path, folder, why):
    """A name longer than the file system allows, a path too long to make, and a folder of 4080
    bytes that can be made but whose files' paths would be too long: refused in one line naming
    --out, and nothing left behind."""
    code, lines = main("--steps", "3", "--out", folder(str(tmp_path)))
    assert code == 2 and lines[0].startswith("simulator.py: error: --out: "), lines
    assert why in lines[0] and "too long" in lines[0] and os.listdir(tmp_path) == []


def test_a_folder_that_cannot_be_made_leaves_no_parent_behind(tmp_path, monkeypatch):
    real = os.mkdir

    def fail_the_last(path, *args):
        if os.path.basename(path) == "c":
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), path)
        real(path, *args)
    monkeypatch.setattr(os, "mkdir", fail_the_last)
    code, lines = main("--steps", "3", "--out", str(tmp_path / "a" / "b" / "c"))
    assert code == 2 and "cannot be created" in lines[0] and os.listdir(tmp_path) == []


# ---- without POSIX-only names (as on Windows)

WITHOUT_POSIX = """
import os, runpy, sys
for name in ("O_NOFOLLOW", "O_NONBLOCK", "geteuid", "getuid", "pathconf", "fchmod", "mkfifo"):
    if hasattr(os, name):
        delattr(os, name)
sys.argv = [sys.argv[1]] + sys.argv[2:]
runpy.run_path(sys.argv[0], run_name="__main__")
"""


def without_posix(*args):
    return subprocess.run([sys.executable, "-c", WITHOUT_POSIX, SIMULATOR, *args], cwd=ROOT,
                          capture_output=True, text=True, timeout=300)


def test_the_main_job_and_its_refusals_without_posix_only_names(tmp_path):
    """The main job, then a run into its folder, now not empty: refused as on POSIX, with no
    O_NOFOLLOW and no file owners."""
    out = tmp_path / "o"
    done = without_posix("--steps", "12", "--frame-stride", "3", "--out", str(out))
    assert done.returncode == 0, done.stderr
    assert (out / "index.html").exists()
    assert len((out / "log.csv").read_text().splitlines()) == 14
    before = sorted(os.listdir(out))
    done = without_posix("--steps", "12", "--frame-stride", "3", "--out", str(out))
    assert done.returncode == 2 and "is not empty" in done.stderr
    assert sorted(os.listdir(out)) == before


# ---- reporting never stops the work

SHELL = os.name == "posix" and os.path.exists("/dev/full")
RUN = ["--steps", "30", "--frame-stride", "3"]      # 10 progress lines, frames and all


def log_rows(folder):
    """log.csv's rows without wall_s, the one column that differs between two runs."""
    rows = (folder / "log.csv").read_text().splitlines()
    return [row.split(",")[:2] + row.split(",")[3:] for row in rows]


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The run as it goes with stderr read (in this process: its files are a child's)."""
    out = tmp_path_factory.mktemp("reference")
    code, lines = main(*RUN, "--out", str(out))
    assert code == 0, lines
    return out


@pytest.mark.skipif(not SHELL, reason="needs a POSIX shell and /dev/full")
@pytest.mark.parametrize("redirect", ["2>&1 | head -1", "2>/dev/full", ">/dev/full 2>&1", "2>&-"])
def test_a_broken_or_full_stderr_changes_nothing_a_run_computes(tmp_path, reference, redirect):
    """Progress and closing lines are best effort: the run still writes every file and exits 0."""
    out = tmp_path / "o"
    cmd = (f"'{sys.executable}' '{SIMULATOR}' {' '.join(RUN)} --out '{out}' {redirect}; "
           f"echo \"rc=${{PIPESTATUS[0]}}\" >'{tmp_path}/rc'")
    subprocess.run(["bash", "-c", cmd], cwd=ROOT, capture_output=True, timeout=300)
    assert (tmp_path / "rc").read_text().strip() == "rc=0"
    assert sorted(os.listdir(out)) == sorted(os.listdir(reference))
    assert log_rows(reference) == log_rows(out)


@pytest.mark.skipif(not SHELL, reason="needs a POSIX shell and /dev/full")
@pytest.mark.parametrize("redirect", [">/dev/full", "| head -0", ">&-"])
def test_figures_with_a_full_or_closed_stdout_still_end_well(tmp_path, redirect):
    cmd = (f"'{sys.executable}' -m figures mollifier --out '{tmp_path}' {redirect}; "
           f"echo \"rc=${{PIPESTATUS[0]}}\"")
    done = subprocess.run(["bash", "-c", cmd], cwd=ROOT, capture_output=True, text=True,
                          timeout=300)
    assert done.stdout.strip().endswith("rc=0") and done.stderr == ""
    assert (tmp_path / "mollifier.png").exists()


SELF_TERMINATING = """
import os, signal, sys, types
sys.path.insert(0, sys.argv[1])
os.close(2)                         # stderr closed: the start-up line cannot be written
module = types.ModuleType("loading")        # stands for viewer.main while numpy and scipy load
module.main = lambda argv: os.kill(os.getpid(), signal.SIGTERM) or 0
sys.modules["loading"] = module
from viewer.command import startup
sys.exit(startup.run_command_line(main="loading"))
"""


def test_sigterm_at_start_up_with_stderr_closed_exits_143():
    done = subprocess.run([sys.executable, "-c", SELF_TERMINATING, ROOT], capture_output=True,
                          timeout=60)
    assert done.returncode == 143
