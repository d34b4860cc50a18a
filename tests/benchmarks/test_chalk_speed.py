"""benchmarks/chalk_speed.py: the chalk's wait as a student meets it (`python -m benchmarks.speed --chalk`)."""
import csv
import os
import platform
import subprocess
import sys

import pytest

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
    assert {r["python"] for r in rows.values()} == {f"{platform.python_version()} {sys.executable}"}
    for r in rows.values():
        assert float(r["simulated_s"]) == 0.3 and float(r["wall_s"]) > float(r["stepping_wall_s"]) > 0
        per_second = float(r["wall_per_simulated_s"])      # the CSV's 6 significant digits
        assert abs(per_second - float(r["wall_s"]) / 0.3) <= 1e-5 * per_second
    assert float(rows["dragged"]["newton_per_step"]) < float(rows["dragged, from x^n"]["newton_per_step"])
    assert "wall / simulated s" in result.stdout and "Target for" in result.stdout
    assert checkout_state() == before


def test_each_python_runs_every_run_in_turn(tmp_path):
    """--python A,B: the runs under each interpreter (here this one under a second name, a script that
    runs it), the rows named by each one's version and path, and a verdict per interpreter; only the
    pushed run, once, 0.3 s (chalk_table's `runs`), nothing in the checkout."""
    from benchmarks import chalk_speed
    if os.name == "nt":
        pytest.skip("the second name is a POSIX shell script")
    other = tmp_path / "python-again"
    other.write_text(f'#!/bin/sh\nexec "{sys.executable}" "$@"\n')
    other.chmod(0o755)
    before = checkout_state()
    pythons = {sys.executable: platform.python_version(), str(other): chalk_speed.python_version(str(other))}
    rows = chalk_speed.chalk_table(1, 0.3, {"pushed": []}, pythons)
    assert [(r["python"], r["run"]) for r in rows] == [(f"{v} {p}", "pushed") for p, v in pythons.items()]
    assert all(r["simulated_s"] == 0.3 and r["newton_per_step"] > 0 for r in rows)
    assert rows[0]["newton_per_step"] == rows[1]["newton_per_step"]        # one interpreter: one trajectory
    rows = [{**r, "simulated_s": 3.0, "wall_per_simulated_s": w} for r, w in zip(rows, (2.5, 3.5))]
    assert chalk_speed.format_chalk_table(rows, 1).endswith(
        f"met with Python {platform.python_version()} (2.50 s); NOT met with Python {pythons[str(other)]} (3.50 s).")
    assert checkout_state() == before


@pytest.mark.parametrize("argv, words", [
    (["--chalk", "--python", "/nonexistent/python"], "--python '/nonexistent/python' could not be run"),
    (["--chalk", "--python", ROOT], f"--python {ROOT!r} could not be run"),           # a folder
    (["--python", sys.executable], "--python needs --chalk"),
])
def test_a_bad_python_is_one_line_and_exit_2_before_anything_is_written(tmp_path, argv, words):
    """An interpreter that cannot be run (missing, a folder), or --python without --chalk: one line naming
    --python, exit status 2, no output folder made."""
    out = tmp_path / "out"
    result = subprocess.run([sys.executable, "-m", "benchmarks.speed", *argv, "--out", str(out)], cwd=ROOT,
                            capture_output=True, text=True, timeout=300)
    lines = result.stderr.splitlines()
    assert result.returncode == 2 and result.stdout == "" and len(lines) == 1, result.stderr
    assert lines[0].startswith("python -m benchmarks.speed: error: ") and words in lines[0] and not out.exists()
