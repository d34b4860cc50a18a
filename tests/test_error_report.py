"""Smoke test of the work-precision report (python -m benchmarks.error_vs_runtime) at its quick size."""
import csv
import os

from benchmarks import error_vs_runtime


def test_quick_report_writes_table_csv_and_png(tmp_path, capsys):
    assert error_vs_runtime.main(["--quick", "--out", str(tmp_path)]) == 0
    out, err = capsys.readouterr()
    assert "free fall" in out and "order" in out                   # the table, on stdout
    assert "[  1/" in err                                           # progress, on stderr
    with open(tmp_path / "error_vs_runtime.csv") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == error_vs_runtime.COLUMNS
    # two time steps of one case, at each tolerance
    assert len(rows) == len(error_vs_runtime.QUICK_HS) * len(error_vs_runtime.TOLS)
    assert {r["case"] for r in rows} == {"free fall"}
    assert all(float(r["error"]) > 0 and float(r["wall_per_sim_second"]) > 0 for r in rows)
    png = tmp_path / "error_vs_runtime.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and os.path.getsize(png) > 10_000


def test_energy_benchmark_quick_table(tmp_path, capsys):
    """benchmarks/energies.py --quick: one row per size with every column, ratios computed from them."""
    from benchmarks import energies
    rows = energies.main(["--quick", "--csv", str(tmp_path / "e.csv")])
    assert [r["n_seg"] for r in rows] == [8, 16]
    for r in rows:
        assert set(energies.COLUMNS) <= set(r) and all(r[c] > 0 for c in energies.COLUMNS[3:])
        assert r["ratio"] == r["energies_total_ms"] / r["factor_solve_ms"]
    assert (tmp_path / "e.csv").read_text().splitlines()[0] == ",".join(energies.COLUMNS)
    assert "target ratio < 0.5" in capsys.readouterr().out


def test_speed_benchmark_quick_table(tmp_path):
    """python -m benchmarks.speed --quick: rows for n_seg 4 and 8 with every column of the CSV, and
    a time split that adds up to the time per step (no timing is asserted, only the table's form)."""
    import csv
    import os
    import subprocess
    import sys
    from benchmarks import speed
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out = tmp_path / "speed.csv"
    result = subprocess.run([sys.executable, "-m", "benchmarks.speed", "--quick", "--csv", str(out)], cwd=root,
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    rows = list(csv.DictReader(open(out)))
    assert [int(r["n_seg"]) for r in rows] == [4, 8] and list(rows[0]) == speed.COLUMNS
    for r in rows:
        parts = sum(float(r[k]) for k in ("energy_assembly_ms", "solve_ms", "line_search_ms", "rest_ms"))
        assert float(r["newton_per_step"]) >= 1 and parts > 0 and int(r["dof"]) == 2 * (int(r["n_seg"]) + 1) ** 2
        assert float(r["in_step_factor_solve_ms"]) > 0 and float(r["ratio_per_newton_in_step"]) > 0
    assert "steps/s" in result.stdout and "lecture" in result.stdout
