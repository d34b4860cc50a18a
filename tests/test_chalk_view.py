"""`python simulator.py --scene chalk`: its flags, what it writes, its log's budget, the tip's marks."""
import csv
import os
import subprocess
import sys

import numpy as np
import pytest

import simulator
from helpers.command import run_main
from viewer import cli, diagnostics, log

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run_cli(*args):
    env = {**os.environ, "SDL_VIDEODRIVER": "dummy"}
    return subprocess.run([sys.executable, os.path.join(ROOT, "simulator.py"), *args], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=300)


@pytest.mark.parametrize("argv, flag", [
    (["--scene", "chalk", "--n-seg", "3"], "--n-seg"), (["--scene", "chalk", "--no-slope"], "--no-slope"),
    (["--scene", "chalk", "--slope-angle", "10"], "--slope-angle"), (["--tilt", "30"], "--tilt"),
    (["--grip", "1000"], "--grip"), (["--drag"], "--drag"), (["--mu-static", "0.5"], "--mu-static")])
def test_a_flag_of_the_other_scene_is_refused_in_one_line_before_anything_is_written(tmp_path, argv, flag):
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
    result = run_cli("--scene", "chalk", "--steps", "300", "--out", str(out))
    assert result.returncode == 0, result.stderr
    files = os.listdir(out)
    assert {"log.csv", "plots.png", "summary.png", "index.html", "frame_00000.png", "frame_00000.obj"} <= set(files)
    with open(out / "log.csv") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == log.columns(simulator.build_chalk_scene()) and len(rows) == 301
    assert {"E_hand", "W_hand", "tip_speed", "normal_force"} <= set(rows[0])
    E = {k: np.array([float(r[k]) for r in rows]) for k in ("E_kinetic", "E_gravity", "E_spring", "E_barrier",
                                                               "E_hand", "E_total", "W_friction", "W_hand", "D_numerical")}
    parts = E["E_kinetic"] + E["E_gravity"] + E["E_spring"] + E["E_barrier"] + E["E_hand"]
    assert np.abs(parts - E["E_total"]).max() < 1e-8
    assert np.abs(E["E_total"][0] + E["W_friction"] + E["W_hand"] - E["D_numerical"] - E["E_total"]).max() < 1e-8
    assert E["D_numerical"].min() > -1e-8       # implicit Euler only takes energy out, once the hand's work is in


def test_the_squares_log_columns_are_unchanged():
    scene = simulator.build_scene()
    assert log.columns(scene) == log.COLUMNS and "E_hand" not in log.COLUMNS
    assert log.COLUMNS[17:] == ["E_kinetic", "E_gravity", "E_spring", "E_barrier", "E_total", "W_friction",
                                "D_numerical"]
    assert list(diagnostics.energies(scene, scene.x0, scene.v0)) == ["kinetic", "gravity", "spring", "barrier", "total"]


def test_a_mark_is_stuck_below_eps_v_slipping_above_and_none_off_the_board():
    scene = simulator.build_chalk_scene()
    x = np.array(scene.x0, dtype=float)
    k, d = diagnostics.tip(scene, x)
    assert d == pytest.approx(scene.dhat) and k == int(np.argmin(x[:, 1]))
    x[k, 1] = 0.5 * scene.dhat
    v = np.zeros_like(x)
    v[k, 0] = 0.5 * scene.epsv
    assert diagnostics.tip_mark(scene, x, v) == (pytest.approx(x[k, 0]), True)
    v[k, 0] = -2.0 * scene.epsv
    assert diagnostics.tip_mark(scene, x, v) == (pytest.approx(x[k, 0]), False)
    x[:, 1] += scene.dhat
    assert diagnostics.tip_mark(scene, x, v) is None
