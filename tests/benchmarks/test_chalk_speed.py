"""benchmarks/waits.py: whole simulator.py processes, the chalk's wait as a student meets it
(`benchmarks.speed --chalk`) and the frames' cost (`--frames`)."""
import csv
import os
import platform
import sys

import pytest

from benchmarks import speed, waits
from helpers.checkout import ROOT, checkout_state


def test_the_chalk_runs_under_the_python_given_count_newton_as_log_csv_does(tmp_path):
    """Real 0.3 s processes of P, this interpreter under a second name (a script that runs it).
    No timing is asserted; the Newton counts are log.csv's, so the dragged chalk from x^n, whose
    tip starts each solve at v = 0, takes more iterations per step than from x_tilde (measured
    1.99 against 1.03)."""
    python = sys.executable
    if os.name != "nt":             # the second name is a POSIX shell script
        python = str(tmp_path / "python-again")
        with open(python, "w") as f:
            f.write(f'#!/bin/sh\nexec "{sys.executable}" "$@"\n')
        os.chmod(python, 0o755)
    before = checkout_state()
    runs = {name: waits.RUNS[name] for name in ("dragged", "dragged, from x^n")}
    rows = waits.chalk_table(1, 0.3, runs, {python: waits.python_version(python)})
    assert [(r["python"], r["run"]) for r in rows] == [
        (f"{platform.python_version()} {python}", name) for name in runs]
    for r in rows:
        assert r["simulated_s"] == 0.3 and r["wall_s"] > r["stepping_wall_s"] > 0
        assert r["wall_per_simulated_s"] == r["wall_s"] / 0.3
    assert rows[0]["newton_per_step"] < rows[1]["newton_per_step"]
    assert checkout_state() == before


def test_the_chalk_table_has_each_run_once_with_quick(tmp_path, monkeypatch, capsys):
    """--chalk --quick: one 0.3 s process per run, under this interpreter, into chalk-speed.csv
    (the CSV's 6 significant digits), the table and its note printed, nothing in the checkout.
    (The processes are stubbed: the test above runs them.)"""
    calls = []

    def run_simulator(flags, python=sys.executable):
        calls.append((python, flags))
        return {"wall_s": 1.234567891, "cpu_s": 1.2, "stepping_wall_s": 0.5,
                "newton_per_step": 1.25, "simulated_s": 0.3, "frames": 0}
    monkeypatch.setattr(waits, "run_simulator", run_simulator)
    before = checkout_state()
    out = tmp_path / "out"
    assert speed.main(["--chalk", "--quick", "--out", str(out)]) == 0
    common = ["--scene", "chalk", "--no-frames", "--duration", "0.3"]
    assert calls == [(sys.executable, [*common, *flags]) for flags in waits.RUNS.values()]
    with open(out / "chalk-speed.csv") as f:
        rows = {r["run"]: r for r in csv.DictReader(f)}
    assert list(rows) == list(waits.RUNS) and list(rows["pushed"]) == waits.COLUMNS
    assert {r["python"] for r in rows.values()} == {
        f"{platform.python_version()} {sys.executable}"}
    assert {r["wall_s"] for r in rows.values()} == {"1.23457"}
    assert {r["wall_per_simulated_s"] for r in rows.values()} == {"4.11523"}
    printed = capsys.readouterr().out
    assert "wall / simulated s" in printed and "Target for" in printed
    assert "not judged: a short run's start-up" in printed
    assert checkout_state() == before


def test_each_python_runs_every_run_in_turn(monkeypatch):
    """chalk_table: the processes go round the interpreters and runs in turn, repeat after repeat;
    a row holds the medians of its own, named by version and path; the 3 s default is judged
    against the target per interpreter. (The processes are stubbed: the test above runs them.)"""
    calls = []

    def run_simulator(flags, python=sys.executable):
        calls.append((python, flags))
        wall = [3.0, 9.0, 6.0][(len(calls) - 1) // 4 % 3] + (python == "B")
        return {"wall_s": wall, "cpu_s": wall, "stepping_wall_s": 1.0,
                "newton_per_step": len(flags), "simulated_s": 3.0, "frames": 0}
    monkeypatch.setattr(waits, "run_simulator", run_simulator)
    runs = {"pushed": [], "dragged": ["--drag"]}
    rows = waits.chalk_table(3, None, runs, {"A": "3.11.2", "B": "3.14.0"})
    flags = [["--scene", "chalk", "--no-frames", *f] for f in runs.values()]
    assert calls == 3 * [(p, f) for p in "AB" for f in flags]
    assert [(r["python"], r["run"]) for r in rows] == [
        (f"{v} {p}", run) for p, v in (("A", "3.11.2"), ("B", "3.14.0")) for run in runs]
    assert [r["wall_s"] for r in rows] == [6.0, 6.0, 7.0, 7.0]          # medians of 3, 9, 6
    assert rows[1]["newton_per_step"] == 4 and rows[0]["noise"].startswith("NOISY")
    rows = [{**r, "wall_per_simulated_s": w} for r, w in zip(rows, (2.5, 9, 3.5, 9))]
    assert waits.format_chalk_table(rows, 3).endswith(
        "met with Python 3.11.2 (2.50 s); NOT met with Python 3.14.0 (3.50 s).")
    calls.clear()
    row = waits.chalk_table(1, 0.3, {"pushed": []})[0]
    assert calls == [(sys.executable, ["--scene", "chalk", "--no-frames", "--duration", "0.3"])]
    assert row["python"] == f"{platform.python_version()} {sys.executable}"


def test_the_frames_cost_is_the_ratio_of_the_medians_of_runs_in_turn(monkeypatch, capsys):
    """--frames: the default run and --no-frames in turn, repeat after repeat; the medians, their
    ratio against the target of 1.5x, frames per simulated second, the CPU times' ratio and the
    load. (The processes and the load are stubbed.)"""
    calls = []
    monkeypatch.setattr(os, "getloadavg", lambda: (4.0, 3.0, 2.0), raising=False)
    monkeypatch.setattr(os, "cpu_count", lambda: 2)

    def run_simulator(flags, python=sys.executable):
        calls.append(flags)
        wall = (2.0 if flags == [] else 1.0) * [1.0, 1.1, 0.9][(len(calls) - 1) // 2]
        return {"wall_s": wall, "cpu_s": 0.5 * wall, "stepping_wall_s": 0.5, "newton_per_step": 2.0,
                "simulated_s": 6.0, "frames": 201 if flags == [] else 0}
    monkeypatch.setattr(waits, "run_simulator", run_simulator)
    assert speed.main(["--frames", "--quick"]) == 0
    assert calls == 3 * [[], ["--no-frames"]]
    assert capsys.readouterr().out == (
        "python simulator.py: 2.00 s with 201 frames (33.3 per simulated second), 1.00 s with "
        "--no-frames (whole processes, medians of 3, run alternately): 2.00x (target <= 1.5x: NOT "
        "met; repeats spread 20%); CPU time 1.00 s against 0.50 s: 2.00x; load 4.0 on 2 cores\n")
    monkeypatch.delattr(os, "getloadavg")           # Windows: no load average to say
    assert waits.load_text() == ""


@pytest.mark.parametrize("argv, words", [
    (["--chalk", "--python", "/nonexistent/python"],
     "--python '/nonexistent/python' could not be run"),
    (["--chalk", "--python", ROOT], f"--python {ROOT!r} could not be run"),      # a folder
    (["--python", sys.executable], "--python needs --chalk"),
])
def test_a_bad_python_is_one_line_and_exit_2_before_anything_is_written(
        tmp_path, capsys, argv, words):
    """An interpreter that cannot be run (missing, a folder), or --python without --chalk: one
    line naming --python, exit status 2, no output folder made."""
    out = tmp_path / "out"
    assert speed.main([*argv, "--out", str(out)]) == 2
    printed = capsys.readouterr()
    lines = printed.err.splitlines()
    assert printed.out == "" and len(lines) == 1, printed.err
    assert lines[0].startswith("python -m benchmarks.speed: error: ") and words in lines[0]
    assert not out.exists()
