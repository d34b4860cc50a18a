"""`python simulator.py --scene chalk`: its flags, what it writes, its log's budget, the tip stuck
or not, and what a run says it showed: its stick-slip, per run, in the closing line, the page and
summary.png."""
import csv
import html
import os
import re

import numpy as np
import pytest

import simulator
from helpers import legibility
from helpers.command import closing_lines, closing_text, page_data, run_main, too_wide
from viewer.command import cli
from analysis import diagnostics, log, stick_slip

pytestmark = pytest.mark.usefixtures("shared_stepping")   # the runs' steps: helpers/runs.py


@pytest.mark.parametrize("argv, flag", [
    (["--scene", "chalk", "--n-seg", "3"], "--n-seg"),
    (["--scene", "chalk", "--no-slope"], "--no-slope"),
    (["--scene", "chalk", "--slope-angle", "10"], "--slope-angle"), (["--tilt", "30"], "--tilt"),
    (["--grip", "1000"], "--grip"), (["--drag"], "--drag"),
    (["--mu-static", "0.5"], "--mu-static")])
def test_a_flag_of_the_other_scene_is_refused_in_one_line_before_anything_is_written(
        tmp_path, argv, flag):
    out = tmp_path / "out"
    code, err = run_main(*argv, "--out", str(out))
    assert code == 2 and len(err) == 1 and flag in err[0] and not out.exists()


@pytest.mark.parametrize("argv, flag", [(["--tilt", "200"], "--tilt"), (["--grip", "-1"], "--grip"),
                                        (["--mu-static", "-0.5"], "--mu-static")])
def test_a_bad_chalk_value_names_its_flag(tmp_path, argv, flag):
    code, err = run_main("--scene", "chalk", *argv, "--out", str(tmp_path / "out"))
    assert code == 2 and len(err) == 1 and err[0].startswith(f"simulator.py: error: {flag}: ")


def test_a_grip_list_is_a_comparison_labelled_and_tagged_like_the_squares():
    runs = cli.parse_command_line(["--scene", "chalk", "--grip", "1000,2000,4000,8000"])
    assert [r.label for r in runs] == [f"grip = {g}" for g in (1000, 2000, 4000, 8000)]
    assert [r.tag for r in runs] == [f"grip{g}" for g in (1000, 2000, 4000, 8000)]
    plan = cli.plan_from_args(runs)
    assert [s.hand.k_hand for s in plan.scenes] == [1000.0, 2000.0, 4000.0, 8000.0]
    assert plan.steps == [3000] * 4 and plan.stride == 33       # 3 s, 30 frames a simulated second


def test_the_chalk_runs_3_s_and_its_log_has_the_hand_and_a_closed_budget(tmp_path):
    out = tmp_path / "run"
    code, lines = run_main("--scene", "chalk", "--steps", "300", "--out", str(out))
    assert code == 0, lines
    files = os.listdir(out)
    written = {"log.csv", "plots.png", "summary.png", "index.html", "frame_00000.png",
               "frame_00000.obj"}
    assert written <= set(files)
    with open(out / "log.csv") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == log.columns(simulator.build_chalk_scene()) and len(rows) == 301
    assert {"E_hand", "W_hand", "tip_speed", "normal_force"} <= set(rows[0])
    E = {k: np.array([float(r[k]) for r in rows]) for k in (
        "E_kinetic", "E_gravity", "E_spring", "E_barrier", "E_hand", "E_total", "W_friction",
        "W_hand", "D_numerical")}
    parts = E["E_kinetic"] + E["E_gravity"] + E["E_spring"] + E["E_barrier"] + E["E_hand"]
    assert np.abs(parts - E["E_total"]).max() < 1e-8
    budget = E["E_total"][0] + E["W_friction"] + E["W_hand"] - E["D_numerical"]
    assert np.abs(budget - E["E_total"]).max() < 1e-8
    assert E["D_numerical"].min() > -1e-8       # implicit Euler only takes out (the hand's work in)


def test_the_squares_log_columns_are_unchanged():
    scene = simulator.build_scene()
    assert log.columns(scene) == log.COLUMNS and "E_hand" not in log.COLUMNS
    assert log.COLUMNS[17:] == ["E_kinetic", "E_gravity", "E_spring", "E_barrier", "E_total",
                                "W_friction", "D_numerical"]
    terms = list(diagnostics.energies(scene, scene.x0, scene.v0))
    assert terms == ["kinetic", "gravity", "spring", "barrier", "total"]


def test_the_tip_is_stuck_below_eps_v_slipping_above_and_neither_off_the_board():
    scene = simulator.build_chalk_scene()
    x = np.array(scene.x0, dtype=float)
    k, d = diagnostics.tip(scene, x)
    assert d == pytest.approx(scene.dhat) and k == int(np.argmin(x[:, 1]))
    x[k, 1] = 0.5 * scene.dhat
    v = np.zeros_like(x)
    v[k, 0] = 0.5 * scene.epsv
    assert diagnostics.tip_stuck(scene, x, v) is True
    v[k, 0] = -2.0 * scene.epsv
    assert diagnostics.tip_stuck(scene, x, v) is False
    x[:, 1] += scene.dhat
    assert diagnostics.tip_stuck(scene, x, v) is None


# --- what a chalk run showed: its stick-slip, per run --------------------------------------------

@pytest.fixture(scope="module")
def compared(tmp_path_factory):
    """`--scene chalk --mu-static 0.35,0.5 --duration 0.6`, in this process, into its default
    folder under output/: one coefficient (it slides with the hand) against the default's mu_s 0.5
    (stick-slip: 3 cycles of 107 ms after the drive starts at 0.2 s, measured: slips at 0.313,
    0.420, 0.527 s); its stderr lines, its working folder, its folder and every text its pictures
    rendered."""
    here = tmp_path_factory.mktemp("compared")
    with pytest.MonkeyPatch.context() as monkeypatch:
        monkeypatch.chdir(here)
        texts = legibility.record_text(monkeypatch)
        code, lines = run_main("--scene", "chalk", "--mu-static", "0.35,0.5", "--duration", "0.6")
    assert code == 0, lines
    (name,) = os.listdir(here / "output")
    return lines, here, here / "output" / name, [text for text, _, _ in texts]


def test_a_mixed_chalk_comparison_fits_and_closes_in_3_lines(compared):
    """One run slides, one stick-slips (stick_slip.short_words): every line fits in 100 columns,
    the default folder's name counted (tests/viewer/command/test_line_width.py, the other runs)."""
    lines, here, _, _ = compared
    assert len(lines) > 3 and not too_wide(lines, here)
    assert len(closing_lines(lines)) <= 3, lines


def counted_from_log(path):
    """The stick-slip of a chalk run as its log.csv has it: the count of analysis/stick_slip.py on
    the columns t, tip_x, tip_speed and step, with the chalk's eps_v, drive and drive start."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    column = {k: np.array([float(r[k]) for r in rows]) for k in ("t", "tip_x", "tip_speed", "step")}
    chalk = simulator.CHALK
    return stick_slip.measure(column["t"], column["tip_x"], column["tip_speed"], chalk["epsv"],
                              chalk["drive"], chalk["t_press"] + chalk["t_hold"],
                              column["step"].astype(int))


RUNS = {"mu-static = 0.35": "log_mu-static0.35.csv", "mu-static = 0.5": "log_mu-static0.5.csv"}


def test_a_chalk_comparison_closes_with_each_runs_stick_slip(compared):
    """Not when the tip was last stuck: each run's stick-slip, counted on the whole of its log. The
    default chalk stick-slips, each slip about catching up with the hand (slip = drive x period);
    with one coefficient the tip slides with the hand from the drive's start."""
    lines, _, out, _ = compared
    line = closing_text(lines)
    counted = {label: counted_from_log(out / name) for label, name in RUNS.items()}
    said = "; ".join(f"{label}: {stick_slip.short_words(r)}" for label, r in counted.items())
    assert line.startswith("simulated 600 steps (0.60 s) x 2 runs in ")
    assert f" wall; {said}; wrote " in line
    assert not re.search(r"\brest\b", line)
    pushed, sliding = counted["mu-static = 0.5"], counted["mu-static = 0.35"]
    catch_up = simulator.CHALK["drive"] * pushed.period
    assert len(pushed.slips) >= 2 and pushed.length == pytest.approx(catch_up, rel=0.2)
    assert sliding.slips == [] and sliding.stuck_after == 0
    assert " slips of " in line and "slides, no stick" in line


def test_the_page_and_summary_say_each_runs_stick_slip_and_no_rest(compared):
    _, _, out, texts = compared
    page, data = (out / "index.html").read_text(), page_data(out)
    counted = [counted_from_log(out / name) for name in RUNS.values()]
    rows = {row["header"]: row["cells"] for row in data["rows"]}
    assert data["labels"] == list(RUNS) and data["rest"] is None            # no "came to rest" row
    assert rows["stick-slip cycles"] == [str(len(r.slips)) for r in counted]
    assert rows["mean slip (mm)"] == ["-", f"{1e3 * counted[1].length:.2f}"]
    assert rows["period (ms)"] == ["-", f"{1e3 * counted[1].period:.0f}"]
    assert rows["tip stuck (% of the drive)"] == [f"{100 * r.stuck:.0f}" for r in counted]
    assert rows["tip creeps while stuck (mm/s)"] == [f"{1e3 * r.creep_speed:.2g}" for r in counted]
    assert rows["tip first slips at t (s)"] == [f"{r.start_up:.2f}" for r in counted]
    for label, r in zip(RUNS, counted):
        assert html.escape(f"{label}: {stick_slip.words(r)}") in page    # the note under the table
        assert stick_slip.words(r) in texts                               # summary.png's run panel
    first, second = stick_slip.definition(simulator.build_chalk_scene())
    assert {"stick-slip, " + first, second} <= set(texts)
    assert not [text for text in texts if re.search(r"\brest\b", text)]


def test_one_chalk_run_closes_with_its_stick_slip(tmp_path):
    """0.35 s: one slip (measured at 0.313 s), the next would start at 0.420 s."""
    code, lines = run_main("--scene", "chalk", "--duration", "0.35", "--no-frames",
                           "--out", str(tmp_path))
    assert code == 0, lines
    r = counted_from_log(tmp_path / "log.csv")
    assert len(r.slips) == 1 and f"wall; {stick_slip.words(r)}; wrote " in closing_text(lines)
    assert stick_slip.words(r).startswith("stick-slip: 1 slip, slip ")
