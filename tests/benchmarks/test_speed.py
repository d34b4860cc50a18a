"""benchmarks/speed.py: the quick table, and the comparison with another tree (--against)."""
import csv
import shutil
import subprocess

import pytest

from benchmarks import speed, tables
from helpers.checkout import ROOT, checkout_state


def test_speed_benchmark_quick_table_and_comparison(tmp_path, capsys):
    """--quick --against <this tree>: the table's rows for n_seg 4 and 8 and the comparison's row
    for n_seg 4, in the CSVs. The tree compared with itself runs the same trajectory, so both
    sides count the same Newton iterations and no mismatch is flagged (no timing is asserted)."""
    before = checkout_state()
    assert speed.main(["--quick", "--against", ROOT, "--out", str(tmp_path)]) == 0
    with open(tmp_path / "speed.csv") as f:
        rows = list(csv.DictReader(f))
    assert [int(r["n_seg"]) for r in rows] == [4, 8] and list(rows[0]) == speed.COLUMNS
    for r in rows:
        assert int(r["dof"]) == 2 * (int(r["n_seg"]) + 1) ** 2
        assert float(r["newton_per_step"]) >= 1
        assert float(r["cpu_ms_per_step"]) > 0 and 0 < float(r["solve_share"]) < 1
    with open(tmp_path / "speed-against.csv") as f:
        compared = list(csv.DictReader(f))
    assert [int(r["n_seg"]) for r in compared] == list(speed.AGAINST_QUICK)
    assert list(compared[0]) == speed.AGAINST_COLUMNS
    for r in compared:
        assert int(r["newton_new"]) == int(r["newton_old"]) > 0 and "MISMATCH" not in r["noise"]
        ratio = float(r["cpu_ms_new"]) / float(r["cpu_ms_old"])
        assert float(r["cpu_ratio"]) == pytest.approx(ratio, rel=1e-4)
    printed = capsys.readouterr().out
    assert "CPU new/old" in printed and "Newton/step" in printed
    assert checkout_state() == before


def test_speed_comparison_flags_a_newton_mismatch(monkeypatch):
    """Two trees whose runs take different Newton iteration counts are flagged."""
    newton = {"a": 10, "b": 11}
    monkeypatch.setattr(tables, "in_fresh_process",
                        lambda module, function, tree, n_seg, steps: (0.01, 0.01, newton[tree]))
    row, = speed.compare("a", "b", {4: (5, 2)})
    assert row["newton_new"] == 10 and row["newton_old"] == 11
    assert row["noise"].startswith("NEWTON MISMATCH") and row["cpu_ratio"] == 1.0


def test_trees_to_compare_are_exported_with_git_archive(tmp_path):
    """--against REV: the commit's files are written into a folder, the checkout untouched; a
    folder is taken as it is."""
    if shutil.which("git") is None or subprocess.run(
            ["git", "-C", ROOT, "rev-parse", "HEAD"], capture_output=True).returncode != 0:
        pytest.skip("not a git checkout")
    assert tables.export_tree("HEAD", str(tmp_path)) == str(tmp_path)
    assert (tmp_path / "time_integrator.py").is_file() and (tmp_path / "simulator.py").is_file()
    assert tables.export_tree(str(tmp_path), "unused") == str(tmp_path)
