"""benchmarks/speed_against.py: a Newton mismatch is flagged; trees are exported with git archive."""
import shutil
import subprocess

import pytest

from helpers.checkout import ROOT


def test_speed_comparison_flags_a_newton_mismatch(monkeypatch):
    """Two trees whose runs take different Newton iteration counts are flagged in the comparison."""
    from benchmarks import speed_against
    newton = {"a": 10, "b": 11}
    monkeypatch.setattr(speed_against, "run_in_process", lambda tree, n_seg, steps: (0.01, 0.01, newton[tree]))
    row, = speed_against.compare("a", "b", {4: (5, 2)})
    assert row["newton_new"] == 10 and row["newton_old"] == 11 and row["noise"].startswith("NEWTON MISMATCH")
    assert row["cpu_ratio"] == 1.0


def test_trees_to_compare_are_exported_with_git_archive(tmp_path):
    """--against REV: the commit's files are written into a folder, the checkout untouched."""
    from benchmarks import speed_against
    if shutil.which("git") is None or subprocess.run(["git", "-C", ROOT, "rev-parse", "HEAD"],
                                                     capture_output=True).returncode != 0:
        pytest.skip("not a git checkout")
    assert speed_against.export_tree("HEAD", str(tmp_path)) == str(tmp_path)
    assert (tmp_path / "time_integrator.py").is_file() and (tmp_path / "simulator.py").is_file()
    assert speed_against.export_tree(str(tmp_path), "unused") == str(tmp_path)
