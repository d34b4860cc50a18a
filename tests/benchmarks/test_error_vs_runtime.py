"""benchmarks/error_vs_runtime.py: the quick run of the work-precision report, its table, CSV
and plot."""
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
