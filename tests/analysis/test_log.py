"""analysis/log.py: the one definition of a state's per-step figures (log.COLUMN). log.csv writes
them, the page and plots.png read them by name, docs/output.md's table is them as written."""
import os
import re

import numpy as np

import time_integrator
from analysis import log
from helpers import ROOT
from viewer.command.recording import Sample
from viewer.pictures import page

SOLVER = ("newton_iterations", "residual", "newton_stalled", "alpha_min", "line_search_steps")


def sample(report=None):
    energies = {"kinetic": 1.0, "gravity": -2.0, "spring": 0.5, "barrier": 0.25, "total": -0.25}
    return Sample(step=3, t=0.03, wall=0.001, com=np.array([0.25, -0.5]), v_tangential=0.125,
                  report=report, min_distance=0.0123456789, energies=energies,
                  friction_work=-0.125, numerical_dissipation=0.0625, speeds=np.zeros(0),
                  sticking=2, sliding=3, inverted=0)


def test_docs_output_md_lists_every_column_as_defined():
    """The table under "log.csv's columns" is log.COLUMN, row by row: name, unit and meaning (a
    '|' in a meaning written '\\|', as markdown needs)."""
    text = open(os.path.join(ROOT, "docs", "output.md"), encoding="utf-8").read()
    section = text.split("## log.csv's columns", 1)[1].split("\n## ", 1)[0]
    rows = [line for line in section.splitlines() if line.startswith("| `")]
    assert rows == [f"| `{c.name}` | {c.unit} | {c.meaning.replace('|', chr(92) + '|')} |"
                    for c in log.COLUMN.values()]
    assert log.COLUMNS == [n for n, c in log.COLUMN.items() if c.applies is None]
    assert len(set(log.COLUMNS)) == len(log.COLUMNS) == 24


def test_a_line_writes_each_column_as_defined_and_the_start_leaves_the_solver_empty():
    start = log.line(log.values(sample())).split(",")
    assert len(start) == len(log.COLUMNS)
    fields = dict(zip(log.COLUMNS, start))
    names = SOLVER + ("friction_updates", "friction_converged")
    assert [fields[name] for name in names] == ["0", "", "0", "", "0", "0", "1"]
    assert fields["step"] == "3" and fields["t"] == "0.030000" and fields["com_y"] == "-0.500000000"
    assert fields["min_distance"] == "0.0123456789" and fields["E_total"] == "-0.25"
    report = time_integrator.StepReport(residual=0.0042, alphas=[1.0, 0.5], stalled=True)
    fields = dict(zip(log.COLUMNS, log.line(log.values(sample(report))).split(",")))
    assert [fields[name] for name in SOLVER] == ["2", "4.200e-03", "1", "0.5", "2"]


def test_the_page_picks_its_figures_by_name():
    """page.FIGURES names log.csv's columns; each is shown as log.csv writes it (min_distance to
    fewer digits), null where there is none, with the column's label and unit as its header."""
    assert set(page.FIGURES) <= set(log.COLUMNS)
    shown = page.figures(log.values(sample()))
    assert list(shown) == list(page.FIGURES)
    assert shown == {"step": 3, "t": 0.03, "newton_iterations": 0, "residual": None,
                     "min_distance": 0.012346, "contacts_sticking": 2, "contacts_sliding": 3}
    assert [page.header(name) for name in page.FIGURES] == [
        "step", "t (s)", "Newton iterations", "residual (m/s)", "min distance (m)",
        "contacts sticking", "contacts sliding"]
    no_slope = log.values(sample())
    no_slope["min_distance"] = float("inf")
    assert page.figures(no_slope)["min_distance"] is None


def test_the_page_script_reads_the_figures_by_name():
    """No list of figures agreed by position between Python and the page's script: it takes each
    figure's name and header from the data, and reads a run's figures and a frame's time by name."""
    script = page.TEMPLATE.split("<script>", 1)[1]
    assert "r[figure.name]" in script and "figure.header" in script and "frame.t" in script
    assert not re.search(r"frame\[\d\]|f\[\d\]|r\[f\]|axis\[\d\]", script)
