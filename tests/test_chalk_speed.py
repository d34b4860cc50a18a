"""benchmarks/chalk_speed.py: the chalk's wait as a student meets it (`python -m benchmarks.speed --chalk`)."""
import csv
import subprocess
import sys

from helpers.checkout import ROOT, checkout_state


def test_the_chalk_speed_table_has_each_run_and_counts_newton_as_log_csv_does(tmp_path):
    """--chalk --quick: one 0.3 s process per run into chalk-speed.csv, nothing in the checkout. No timing
    is asserted; the Newton counts are log.csv's, so the dragged chalk from x^n, whose tip starts each
    solve at v = 0, takes more iterations per step than from x_tilde (measured 1.99 against 1.03)."""
    from benchmarks import chalk_speed
    before = checkout_state()
    result = subprocess.run([sys.executable, "-m", "benchmarks.speed", "--chalk", "--quick", "--out", str(tmp_path)],
                            cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    rows = {r["run"]: r for r in csv.DictReader(open(tmp_path / "chalk-speed.csv"))}
    assert list(rows) == list(chalk_speed.RUNS) and list(next(iter(rows.values()))) == chalk_speed.COLUMNS
    for r in rows.values():
        assert float(r["simulated_s"]) == 0.3 and float(r["wall_s"]) > float(r["stepping_wall_s"]) > 0
        per_second = float(r["wall_per_simulated_s"])      # the CSV's 6 significant digits
        assert abs(per_second - float(r["wall_s"]) / 0.3) <= 1e-5 * per_second
    assert float(rows["dragged"]["newton_per_step"]) < float(rows["dragged, from x^n"]["newton_per_step"])
    assert "wall / simulated s" in result.stdout and "Target for" in result.stdout
    assert checkout_state() == before
