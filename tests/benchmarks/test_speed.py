"""benchmarks/speed.py: the quick table and the comparison it runs (--against)."""
import csv
import subprocess

import pytest

from helpers.checkout import ROOT, checkout_state


def test_speed_benchmark_quick_table_and_comparison(tmp_path):
    """python -m benchmarks.speed --quick --against <this tree>: the table's rows for n_seg 4 and 8 and
    the comparison's row for n_seg 4, in the CSVs. The tree compared with itself runs the same
    trajectory, so both sides must count the same Newton iterations and no mismatch may be flagged
    (no timing is asserted, only the tables' form and the iteration counts)."""
    import sys
    from benchmarks import speed, speed_against
    before = checkout_state()
    out = tmp_path / "speed.csv"
    result = subprocess.run([sys.executable, "-m", "benchmarks.speed", "--quick", "--against", ROOT, "--out", str(tmp_path)],
                            cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    rows = list(csv.DictReader(open(out)))
    assert [int(r["n_seg"]) for r in rows] == [4, 8] and list(rows[0]) == speed.COLUMNS
    for r in rows:
        assert int(r["dof"]) == 2 * (int(r["n_seg"]) + 1) ** 2 and float(r["newton_per_step"]) >= 1
        assert float(r["cpu_ms_per_step"]) > 0 and 0 < float(r["solve_share"]) < 1
    compared = list(csv.DictReader(open(tmp_path / "speed-against.csv")))
    assert [int(r["n_seg"]) for r in compared] == list(speed_against.AGAINST_QUICK)
    assert list(compared[0]) == speed_against.AGAINST_COLUMNS
    for r in compared:
        assert int(r["newton_new"]) == int(r["newton_old"]) > 0 and "MISMATCH" not in r["noise"]
        assert float(r["cpu_ratio"]) == pytest.approx(float(r["cpu_ms_new"]) / float(r["cpu_ms_old"]), rel=1e-4)
    assert "CPU new/old" in result.stdout and "Newton/step" in result.stdout
    assert checkout_state() == before
