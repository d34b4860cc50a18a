"""Smoke tests of the benchmark scripts (work-precision report, energies, speed and its comparison) at their
quick sizes, and of the reading path's line counter."""
import csv
import os
import shutil
import subprocess
import tempfile

import pytest

import benchmarks
from benchmarks import error_vs_runtime

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def checkout_state():
    """What a benchmark must not change: `git status --porcelain` of the checkout, and the size and
    modification time of every file in benchmarks/results/ (a file rewritten with the same bytes
    counts too). Skips the test where this is not a git checkout."""
    if shutil.which("git") is None:
        pytest.skip("git is not installed, so whether the checkout stays clean cannot be told")
    status = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=all"],
                            capture_output=True, text=True)
    if status.returncode != 0:
        pytest.skip(f"not inside a git checkout: {status.stderr.strip()}")
    stamps = {entry.name: (entry.stat().st_size, entry.stat().st_mtime_ns) for entry in os.scandir(benchmarks.RESULTS)}
    return status.stdout, stamps


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
    rows = energies.main(["--quick", "--out", str(tmp_path)])
    assert [r["n_seg"] for r in rows] == [8, 16]
    for r in rows:
        assert set(energies.COLUMNS) <= set(r) and all(r[c] > 0 for c in energies.COLUMNS[3:])
        assert r["ratio"] == r["energies_total_ms"] / r["factor_solve_ms"]
    assert (tmp_path / "energies.csv").read_text().splitlines()[0] == ",".join(energies.COLUMNS)
    assert "target ratio < 0.5" in capsys.readouterr().out


def test_smoke_runs_write_into_a_temporary_folder_and_leave_the_checkout_clean(tmp_path, monkeypatch, capsys):
    """Each benchmark's smoke run (--quick; speed also with --sizes, a partial table), without --out,
    writes into a new temporary folder of its own: `git status --porcelain` and benchmarks/results/
    stay as they were (issue 26). reading_path writes no file (its test checks the same around it);
    only a full run writes into benchmarks/results/."""
    from benchmarks import energies, speed
    before = checkout_state()
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))       # where tempfile.mkdtemp creates folders
    assert error_vs_runtime.main(["--quick"]) == 0
    energies.main(["--quick"])
    assert speed.main(["--quick", "--sizes", "4"]) == 0
    assert checkout_state() == before
    written = {folder.name.split("-")[0]: sorted(os.listdir(folder)) for folder in tmp_path.iterdir()}
    assert written == {"error_vs_runtime": ["error_vs_runtime.csv", "error_vs_runtime.png"],
                       "energies": ["energies.csv"], "speed": ["speed.csv"]}
    assert str(tmp_path) in capsys.readouterr().err                 # each says where it wrote
    assert benchmarks.output_folder(None, True, "speed") == benchmarks.RESULTS
    assert benchmarks.output_folder(str(tmp_path / "mine"), False, "speed") == str(tmp_path / "mine")


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


def test_speed_comparison_flags_a_newton_mismatch(monkeypatch):
    """Two trees whose runs take different Newton iteration counts are flagged in the comparison."""
    from benchmarks import speed_against
    newton = {"a": 10, "b": 11}
    monkeypatch.setattr(speed_against, "run_in_process", lambda tree, n_seg, steps: (0.01, 0.01, newton[tree]))
    row, = speed_against.compare("a", "b", {4: (5, 2)})
    assert row["newton_new"] == 10 and row["newton_old"] == 11 and row["noise"].startswith("NEWTON MISMATCH")
    assert row["cpu_ratio"] == 1.0


# the reading path's counter, on a source whose counts are read off its text
SOURCE = '''"""Module docstring: not counted."""
import math


def f(xs):
    """A docstring
    over two lines."""
    # a comment line
    total = sum(x * x for x in xs)

    return math.sqrt(total)  # a trailing comment: the line counts


def g():
    text = """a string that is not a docstring
    counts on both its lines"""
    return text


class C:
    """Class docstring."""

    def method(self):
        return 1
'''


def test_code_lines_leave_out_blanks_comments_and_docstrings():
    from benchmarks import reading_path
    assert reading_path.code_lines(SOURCE) == {2, 5, 9, 11, 14, 15, 16, 17, 20, 23, 24}


def test_reading_path_counts_the_functions_that_ran_once_with_their_generators(tmp_path):
    """f ran (its generator expression is part of f), method ran twice, g never ran: 2 functions, 3 + 2
    lines in mod.py; a file outside the tree's top level is not a project file."""
    from benchmarks import reading_path
    path = tmp_path / "mod.py"
    path.write_text(SOURCE)
    module = compile(SOURCE, str(path), "exec")
    codes = {}

    def walk(code):
        codes[code.co_name] = code
        for const in code.co_consts:
            if hasattr(const, "co_name"):
                walk(const)
    walk(module)
    ran = {codes["f"], codes["<genexpr>"], codes["method"]}
    assert reading_path.reading_path(ran, str(tmp_path)) == {"mod.py": (2, 5)}
    assert reading_path.functions_that_ran(ran, str(tmp_path)) == {"mod.py": {(5, "f"): {5, 9, 11}, (23, "method"): {23, 24}}}
    listed = reading_path.format_functions([("mod.py", "f", 5, 3), ("mod.py", "method", 23, 2)]).splitlines()
    assert [line.split() for line in listed] == [["mod.py:5", "f", "3"], ["mod.py:23", "method", "2"]]
    assert reading_path.is_project_file(str(path), str(tmp_path))
    assert not reading_path.is_project_file(str(tmp_path / "tests" / "mod.py"), str(tmp_path))


def test_reading_path_of_this_tree_against_itself(capsys):
    """python -m benchmarks.reading_path --against <this tree>: the same table twice, counting the
    integrator and the simulator, each file within its code lines, and the totals in the last line."""
    from benchmarks import reading_path
    before = checkout_state()
    assert reading_path.main(["--against", ROOT]) == 0
    assert checkout_state() == before                               # it writes no file
    out = capsys.readouterr().out.splitlines()
    tables = [out[out.index(title) + 2:] for title in ("working tree", ROOT)]
    tables = [table[:[line.split()[0] for line in table].index("total")] for table in tables]
    assert tables[0] == tables[1]
    per_file = {name: (int(functions), int(lines)) for name, functions, lines in map(str.split, tables[0])}
    assert {"time_integrator.py", "simulator.py", "utils.py"} <= set(per_file)
    for name, (functions, lines) in per_file.items():
        assert 0 < functions <= lines
        with open(os.path.join(ROOT, name)) as f:
            assert lines <= len(reading_path.code_lines(f.read()))
    functions, lines = reading_path.totals(per_file)
    assert out[-1] == f"working tree {lines} lines in {functions} functions; {ROOT} {lines} lines in {functions} functions"


def test_trees_to_compare_are_exported_with_git_archive(tmp_path):
    """--against REV: the commit's files are written into a folder, the checkout untouched."""
    from benchmarks import speed_against
    if shutil.which("git") is None or subprocess.run(["git", "-C", ROOT, "rev-parse", "HEAD"],
                                                     capture_output=True).returncode != 0:
        pytest.skip("not a git checkout")
    assert speed_against.export_tree("HEAD", str(tmp_path)) == str(tmp_path)
    assert (tmp_path / "time_integrator.py").is_file() and (tmp_path / "simulator.py").is_file()
    assert speed_against.export_tree(str(tmp_path), "unused") == str(tmp_path)
