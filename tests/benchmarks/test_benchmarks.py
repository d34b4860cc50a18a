"""benchmarks/: where they write (a smoke run never over benchmarks/results/), and the energies'
quick table."""
import os
import tempfile

import pytest

from benchmarks import energies, error_vs_runtime, reading_path, speed, tables
from helpers.checkout import checkout_state


def test_energy_benchmark_quick_table(tmp_path, capsys):
    """energies --quick: one row per size with every column, the ratio computed from them."""
    rows = energies.main(["--quick", "--out", str(tmp_path)])
    assert [r["n_seg"] for r in rows] == [8, 16]
    for r in rows:
        assert set(energies.COLUMNS) <= set(r) and all(r[c] > 0 for c in energies.COLUMNS[3:])
        assert r["ratio"] == r["energies_total_ms"] / r["factor_solve_ms"]
    assert (tmp_path / "energies.csv").read_text().splitlines()[0] == ",".join(energies.COLUMNS)
    assert "target ratio < 0.5" in capsys.readouterr().out


def test_smoke_runs_write_into_a_temporary_folder_and_leave_the_checkout_clean(
        tmp_path, monkeypatch, capsys):
    """Each benchmark's smoke run (--quick; speed also with --sizes, a partial table), without
    --out, writes into a new temporary folder of its own: `git status --porcelain` and
    benchmarks/results/ stay as they were (issue 26); only a full run writes into results/."""
    before = checkout_state()
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))     # where mkdtemp makes folders
    assert error_vs_runtime.main(["--quick"]) == 0
    energies.main(["--quick"])
    assert speed.main(["--quick", "--sizes", "4"]) == 0
    assert checkout_state() == before
    written = {f.name.split("-")[0]: sorted(os.listdir(f)) for f in tmp_path.iterdir()}
    assert written == {"error_vs_runtime": ["error_vs_runtime.csv", "error_vs_runtime.png"],
                       "energies": ["energies.csv"], "speed": ["speed.csv"]}
    assert str(tmp_path) in capsys.readouterr().err                 # each says where it wrote
    assert tables.output_folder(None, True, "speed") == tables.RESULTS
    mine = str(tmp_path / "mine")
    assert tables.output_folder(mine, False, "speed") == mine


@pytest.mark.parametrize("module", [energies, error_vs_runtime, reading_path, speed])
def test_each_benchmarks_help_is_whole_sentences(module, capsys):
    """--help names the command as it is run and says its purpose to the end, not cut at a line
    of the docstring (issue 40: energies' stopped at "against one")."""
    with pytest.raises(SystemExit) as ended:
        module.main(["--help"])
    assert ended.value.code == 0
    said = capsys.readouterr().out
    assert said.startswith(f"usage: python -m benchmarks.{module.__name__.split('.')[-1]} ")
    description = " ".join(said.split("\n\n")[1].split())
    assert description == " ".join(module.__doc__.split("\n\n")[0].split())
    assert description.endswith(".")


def test_a_file_named_output_is_one_line_not_a_traceback(tmp_path, monkeypatch):
    """tables.scratch where output/ cannot be made: SystemExit with one line naming it."""
    (tmp_path / "output").write_text("the user's own")
    monkeypatch.setattr(tables, "SCRATCH", str(tmp_path / "output"))
    with pytest.raises(SystemExit) as ended:
        tables.scratch("waits-")
    said = str(ended.value.code)
    assert said.startswith(f"error: {tmp_path / 'output'} cannot hold") and "\n" not in said
    assert (tmp_path / "output").read_text() == "the user's own"
