"""viewer/output/files.py: --out checked where it is written (issue 40, item 2): a '..' after a
link goes up from the link's target, as the kernel walks it; --out itself a link, and a link
another user planted in a sticky folder, are refused."""
import os

import pytest

from helpers.command import run_main as main
from viewer.output import files, whole_files

POSIX_LINKS = pytest.mark.skipif(not whole_files.HAS_OWNERS or not hasattr(os, "symlink"),
                                 reason="POSIX links and owners")


def linked(tmp_path):
    """x/a, a link to x/t1/t2; x/t1 holds the user's notes.txt."""
    (tmp_path / "x" / "t1" / "t2").mkdir(parents=True)
    (tmp_path / "x" / "t1" / "notes.txt").write_text("mine")
    os.symlink(tmp_path / "x" / "t1" / "t2", tmp_path / "x" / "a")
    return tmp_path / "x"


@POSIX_LINKS
def test_dotdot_after_a_link_is_checked_where_the_kernel_puts_it(tmp_path):
    """--out x/a/../b is x/t1/b to the kernel: the run makes and checks that folder, writes
    there, names it, and makes no x/b (on main: x/b made, the files written in x/t1/b)."""
    x = linked(tmp_path)
    code, lines = main("--steps", "3", "--no-frames", "--out", str(x / "a" / ".." / "b"))
    assert code == 0, lines
    assert lines[-1].endswith(f" in {x / 't1' / 'b'}/")
    assert sorted(os.listdir(x)) == ["a", "t1"]
    assert sorted(os.listdir(x / "t1" / "b")) == ["log.csv", "plots.png", "summary.png"]
    assert (x / "t1" / "notes.txt").read_text() == "mine"


@POSIX_LINKS
def test_dotdot_after_a_link_to_a_folder_that_is_not_empty_is_refused(tmp_path):
    """x/t1/b holds the user's file: --out x/a/../b is refused though x/b does not exist."""
    x = linked(tmp_path)
    (x / "t1" / "b").mkdir()
    (x / "t1" / "b" / "thesis.tex").write_text("years of work")
    code, lines = main("--steps", "3", "--no-frames", "--out", str(x / "a" / ".." / "b"))
    assert code == 2 and len(lines) == 1 and "is not empty" in lines[0], lines
    assert os.listdir(x / "t1" / "b") == ["thesis.tex"] and sorted(os.listdir(x)) == ["a", "t1"]


@POSIX_LINKS
def test_an_out_that_is_a_link_to_an_empty_folder_is_refused(tmp_path):
    (tmp_path / "empty").mkdir()
    os.symlink(tmp_path / "empty", tmp_path / "link")
    for out in (tmp_path / "link", f"{tmp_path / 'link'}/"):
        code, lines = main("--steps", "3", "--no-frames", "--out", str(out))
        assert code == 2 and len(lines) == 1 and "is a link to" in lines[0], lines
    assert os.listdir(tmp_path / "empty") == []


@POSIX_LINKS
def test_a_link_another_user_planted_in_a_sticky_folder_is_refused(tmp_path):
    """/tmp-like: a folder all may write to, sticky, of another user; in it a link of a third
    user's to a folder of ours. The kernel's fs.protected_symlinks would not follow it: refused,
    nothing written (on main the run wrote through it). Needs root to give the link an owner."""
    if os.geteuid() != 0:
        pytest.skip("a link owned by another uid needs root to make")
    shared, ours = tmp_path / "shared", tmp_path / "ours"
    shared.mkdir()
    ours.mkdir()
    os.chmod(shared, 0o1777)
    os.chown(shared, 65534, 65534)
    os.symlink(ours, shared / "planted")
    os.lchown(shared / "planted", 65533, 65533)
    code, lines = main("--steps", "3", "--no-frames", "--out", str(shared / "planted" / "run"))
    assert code == 2 and len(lines) == 1 and "another user's link" in lines[0], lines
    assert os.listdir(ours) == []
    os.lchown(shared / "planted", 0, 0)            # the user's own link: followed
    assert main("--steps", "3", "--no-frames", "--out", str(shared / "planted" / "run"))[0] == 0
    assert sorted(os.listdir(ours / "run")) == ["log.csv", "plots.png", "summary.png"]


@POSIX_LINKS
def test_a_loop_of_links_is_refused_in_one_line(tmp_path):
    os.symlink(tmp_path / "b", tmp_path / "a")
    os.symlink(tmp_path / "a", tmp_path / "b")
    code, lines = main("--steps", "3", "--no-frames", "--out", str(tmp_path / "a" / "run"))
    assert code == 2 and len(lines) == 1 and "too many links" in lines[0], lines
    assert sorted(os.listdir(tmp_path)) == ["a", "b"]


def test_resolved_is_the_absolute_path_where_there_are_no_links(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert files.resolved(os.path.join("p", "..", "q", ".", "r")) == str(tmp_path / "q" / "r")
    monkeypatch.setattr(whole_files, "HAS_OWNERS", False)       # as on Windows: '..' as text
    assert files.resolved(os.path.join("p", "..", "q")) == str(tmp_path / "q")
