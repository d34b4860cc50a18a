"""`python simulator.py` as a user runs it: files written, flags, one-line errors, exit code 2."""
import csv
import os
import subprocess
import sys

import numpy as np
import pytest

import analysis.log
import simulator
import utils
from scenes import grasp
from helpers import ROOT
from helpers.command import closing_text, run_main
import viewer.main
from viewer.command import cli, run

SIMULATOR = os.path.join(ROOT, "simulator.py")


def run_cli(*args, env=None):
    """python simulator.py ARGS as a child process (a display-less SDL unless `env` says)."""
    env = env or {**os.environ, "SDL_VIDEODRIVER": "dummy"}
    return subprocess.run([sys.executable, SIMULATOR, *args], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=300, umask=0o022)


@pytest.fixture(scope="module")
def twenty_steps(tmp_path_factory):
    """A fresh shell with no DISPLAY and no SDL_VIDEODRIVER, umask 022: 20 steps, every frame."""
    out = tmp_path_factory.mktemp("run")
    env = {k: v for k, v in os.environ.items()
           if k not in ("DISPLAY", "SDL_VIDEODRIVER", "WAYLAND_DISPLAY")}
    return out, run_cli("--steps", "20", "--frame-stride", "1", "--out", str(out), env=env)


def test_twenty_steps_write_frames_objs_csv_and_summary(twenty_steps):
    out, result = twenty_steps
    assert result.returncode == 0, result.stderr
    files = sorted(os.listdir(out))
    frames = [f"frame_{i:05d}.png" for i in range(21)]
    assert [f for f in files if f.endswith(".png") and f.startswith("frame")] == frames
    assert len([f for f in files if f.endswith(".obj")]) == 21
    assert "summary.png" in files and "log.csv" in files
    assert not [f for f in files if f.startswith(".")]     # no temporaries left
    with open(out / "log.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 21 and set(analysis.log.COLUMNS) <= set(rows[0])   # t = 0 and 20 steps
    com_y = [float(r["com_y"]) for r in rows]
    assert all(b < a for a, b in zip(com_y, com_y[1:]))                  # falling
    assert all(int(r["newton_iterations"]) >= 1 for r in rows[1:])
    assert closing_text(result.stderr.splitlines()).startswith("simulated 20 steps")
    obj = (out / "frame_00020.obj").read_text().splitlines()
    last = np.array([line.split()[1:3] for line in obj if line.startswith("v ")], dtype=float)
    assert last.shape == (25, 2) and last[:, 1].mean() == pytest.approx(com_y[-1], abs=1e-6)


def test_runs_without_display_settings_and_files_have_the_usual_permissions(twenty_steps):
    """Without DISPLAY or SDL_VIDEODRIVER simulator.py draws off-screen by itself; written whole via
    a temporary file, yet readable by others as with a plain open() (umask 022)."""
    out, result = twenty_steps
    assert result.returncode == 0, result.stderr
    for name in ("frame_00001.png", "frame_00001.obj", "log.csv", "summary.png", "index.html"):
        assert (out / name).stat().st_mode & 0o777 == 0o644, name


def test_frame_looks_like_the_lecture(twenty_steps):
    """White background, blue springs and nodes, the slope drawn as a line, time and mu written in
    the top-left corner: check pixel colours where each should be."""
    import pygame
    out, _ = twenty_steps
    image = pygame.surfarray.array3d(pygame.image.load(str(out / "frame_00000.png")))  # [x, y, rgb]
    assert image.shape == (900, 900, 3)
    pixels = image.reshape(-1, 3)
    assert (pixels == 255).all(axis=1).mean() > 0.8                           # white
    assert image[450, 450, 2] > 200 and image[450, 450, 0] < 100        # node 12 at the origin

    def bluish(px):
        return px[2] > 150 and px[0] < 200 and px[2] > px[0] + 50

    # the slope through (0, -1) with normal (0.1, 1): y = -1 - 0.1 x, at 200 px/m about the centre
    for x_m in (-2.0, -1.0, 1.0, 2.0):
        col, row = int(450 + 200 * x_m), 450 + 200 * (1 + 0.1 * x_m)
        assert any(bluish(image[col, int(row) + dr]) for dr in (-1, 0, 1)), f"slope at {x_m} m"
    corner = image[:400, :44].reshape(-1, 3)                                   # the title's rows
    assert (corner.sum(axis=1) < 200).any() and (image[400:, :44] == 255).all()  # text top-left


def test_flags_reach_the_scene():
    (args,) = cli.parse_command_line(
        ["--mu", "0.2", "--h", "0.005", "--n-seg", "3", "--k", "3e4", "--density", "500",
         "--slope-angle", "10", "--v0", "1,-2", "--dhat", "0.02", "--kappa", "1e6",
         "--epsv", "1e-4", "--tol", "1e-3", "--friction-iterations", "3"])
    scene = cli.scene_from_args(args)
    # == where the value is the parsed flag itself, passed through unchanged (exact by construction)
    assert scene.mu == 0.2 and scene.h == 0.005 and scene.params["n_seg"] == 3
    assert scene.k[0] == 3e4 and scene.m.sum() == pytest.approx(500.0)
    assert scene.dhat == 0.02 and scene.kappa == 1e6
    assert scene.epsv == 1e-4 and scene.tol == 1e-3 and scene.friction_updates == 3
    assert np.allclose(scene.n, [np.sin(np.radians(10)), np.cos(np.radians(10))])
    assert np.allclose(scene.v0, [1.0, -2.0])
    assert cli.steps_from_args(args, scene, cli.DURATION) == round(cli.DURATION / 0.005)
    assert scene.newton_start == "x_n"          # the lecture's, unless asked
    for argv, start in ((["--newton-start", "x_tilde"], "x_tilde"),
                        (["--scene", "chalk"], "x_tilde"),
                        (["--scene", "chalk", "--newton-start", "x_n"], "x_n")):
        assert cli.scene_from_args(cli.parse_command_line(argv)[0]).newton_start == start
    compared = cli.parse_command_line(["--scene", "chalk", "--newton-start", "x_n,x_tilde"])
    assert [a.label for a in compared] == ["newton-start = x_n", "newton-start = x_tilde"]
    assert [cli.scene_from_args(a).newton_start for a in compared] == ["x_n", "x_tilde"]
    no_slope = cli.scene_from_args(cli.parse_command_line(["--no-slope"])[0])
    assert no_slope.n is None and "barrier" not in no_slope.terms


@pytest.mark.parametrize("args, message", [
    (["--mu", "-1"], "mu must be >= 0, got -1.0"),
    (["--h", "0"], "h must be a finite number > 0, got 0.0"),
    (["--n-seg", "2.5"], "n_seg must be a whole number >= 1, got 2.5"),
    (["--k", "nan"], "k must be a finite number > 0, got nan"),
    (["--slope-normal", "0,0"], "slope normal must be non-zero, got [0.0, 0.0]"),
    (["--v0", "1"], "expected two numbers"),
    (["--steps", "0"], "steps must be a whole number >= 1, got 0"),
    (["--duration", "-3"], "duration must be a finite number > 0, got -3.0"),
    (["--slope-point", "0,0.2"], "touches the slope"),
    (["--bogus"], "unrecognized arguments: --bogus"),
])
def test_bad_command_line_is_one_line_and_exit_2(args, message, tmp_path):
    code, lines = run_main(*args, "--out", str(tmp_path / "o"))
    assert code == 2 and len(lines) == 1, lines
    assert lines[0].startswith("simulator.py: error:") and message in lines[0]
    assert not (tmp_path / "o").exists()


def test_help_documents_every_flag(capsys):
    with pytest.raises(SystemExit) as ended:            # argparse's --help: printed, exit 0
        viewer.main.main(["--help"])
    assert ended.value.code == 0
    text = capsys.readouterr().out
    for flag in ("--mu", "--h", "--duration", "--steps", "--n-seg", "--k", "--density",
                 "--slope-normal", "--slope-angle", "--v0", "--dhat", "--kappa", "--epsv", "--tol",
                 "--friction-iterations", "--newton-start", "--out", "--frame-stride", "--window",
                 "--scene", "--tilt", "--grip", "--mu-static", "--drag", "--no-frames",
                 "--pull-speed", "--pull-length", "--squeeze", "--lift-accel"):
        assert flag in text


def test_help_gives_each_scenes_own_defaults():
    """Issue 40: --help said 6 s for every scene. Each scene's default is in its help, where it
    differs from the square's: the duration, and each scene flag's value in the scene's table."""
    helps = {action.dest: " ".join(action.help.split()) for action in cli.make_parser()._actions}
    assert helps["duration"] == (f"simulated seconds (default: the square {cli.DURATION:g}, the "
                                 f"chalk {cli.CHALK_DURATION:g}, the grasp "
                                 f"{grasp.DURATION:g}, the tablecloth until its "
                                 f"closed-form dish stops, +{cli.STOP_MARGIN:g})")
    tables = {kind: table for kind, (table, _) in cli.scene_kinds().items()}
    for _, param, _, _ in cli.FLAGS:
        default = helps[param].rsplit("(default ", 1)[1]
        for kind, table in tables.items():
            if param in table and table[param] != simulator.DEFAULTS.get(param, table[param]):
                assert f"{kind} {cli.shown(table[param])}" in default, (param, default)
    assert helps["h"].endswith("(default 0.01; chalk 0.001, tablecloth 0.005, grasp 0.005)")
    assert helps["newton_start"].endswith("(default x_n; chalk x_tilde)")


def test_tablecloth_flags_compare_and_the_run_lasts_until_the_dishes_stop():
    """A flag reaches the tablecloth where TABLECLOTH has its parameter; a list compares pulls, all
    run until the slowest closed-form dish has stopped, plus STOP_MARGIN: U 1 m/s stops at
    0.05 + 1 + 1 / (0.2 * 9.81) s, U 4 m/s at 0.05 + 0.25 + 0.25 s."""
    runs = cli.parse_command_line(["--scene", "tablecloth", "--pull-speed", "1,2,4,8",
                                   "--pull-length", "1", "--mu", "0.2", "--k", "3e5"])
    plan = cli.plan_from_args(runs)
    assert [s.surface.pull_speed for s in plan.scenes] == [1.0, 2.0, 4.0, 8.0]
    assert all(s.mu == 0.2 and s.k[0] == 3e5 and s.surface.pull_length == 1.0
               for s in plan.scenes)
    assert plan.labels == ["pull-speed = 1", "pull-speed = 2", "pull-speed = 4", "pull-speed = 8"]
    slowest = 0.05 + 1.0 + 1.0 / (0.2 * 9.81) + cli.STOP_MARGIN
    assert plan.steps == [round(slowest / 0.005)] * 4 and plan.kind == "tablecloth"
    assert run.summary_header(plan)[1:] == [
        "dish 20 x 5 cm, 0.5 kg   cloth pulled L = 1 m at U = 1 m/s from t = 0.05 s   mu = 0.2",
        "h = 0.005 s   k = 300000 N/m   dhat = 0.001 m   kappa = 100000   eps_v = 0.001 m/s   "
        "tol = 1e-06 m/s"]
    (fast,) = cli.parse_command_line(["--scene", "tablecloth"])
    assert cli.plan_from_args([fast]).steps == [round(0.6 / 0.005)]
    (given,) = cli.parse_command_line(["--scene", "tablecloth", "--duration", "2"])
    assert cli.plan_from_args([given]).steps == [400]


def test_tolerance_below_round_off_warns_and_finishes(tmp_path):
    """Issue 13: --tol 1e-8 used to fail at step 32 after 1000 Newton iterations. It is warned
    about when the scene is built (below the floor resolution_warnings estimates), the run ends
    with exit 0, the steps that stopped at the floor are flagged in log.csv (residual above tol,
    few iterations), and stderr says so once."""
    scene = simulator.build_scene(tol=1e-8)
    assert any("below the residual float64 can resolve" in w for w in scene.warnings)
    assert not simulator.build_scene().warnings         # the lecture's tol is far above the floor
    code, lines = run_main("--tol", "1e-8", "--no-frames", "--duration", "0.6", "--out",
                           str(tmp_path))
    assert code == 0, lines
    with open(tmp_path / "log.csv") as f:
        rows = list(csv.DictReader(f))[1:]
    stalled = [r for r in rows if r["newton_stalled"] == "1"]
    assert stalled and all(float(r["residual"]) > 1e-8 for r in stalled)
    assert all(float(r["residual"]) <= 1e-8 for r in rows if r["newton_stalled"] == "0")
    assert max(int(r["newton_iterations"]) for r in rows) < 50
    assert sum(line.count("round-off floor") for line in lines) == 1


def test_an_errors_flag_comes_from_its_parameter_not_its_words(monkeypatch):
    """A ValueError carries its parameter (utils.ParameterError): the command line names the flag
    from its flag table whatever the message says; a message that starts with a flag's words but
    carries no parameter gets no flag."""
    def refuse(parameter, words):
        def build(**params):
            raise utils.ParameterError(parameter, words) if parameter else ValueError(words)
        return build
    for parameter, words, shown in (
            ("mu", "reworded: no flag's name in front", "--mu: reworded"),
            ("slope", "a slope this run cannot take", "--slope-normal: a slope"),
            (None, "mu must be >= 0, yet no parameter", "mu must")):
        monkeypatch.setattr(simulator, "build_scene", refuse(parameter, words))
        code, lines = run_main("--steps", "3")
        assert code == 2 and len(lines) == 1 and f"simulator.py: error: {shown}" in lines[0], lines


@pytest.mark.parametrize("args, said", [
    (["--mu", "0,11"], "comparing mu = 0 and mu = 11 (a list; a decimal is written 0.11)"),
    (["--pull-speed", "3,05", "--scene", "tablecloth"],
     "comparing pull-speed = 3 and pull-speed = 05 (a list; a decimal is written 3.05)"),
])
def test_a_list_that_reads_like_a_decimal_comma_is_said_first(args, said, tmp_path):
    """Two whole numbers to a flag of decimals, a list unlikely as written (its first 0, its second
    with a leading 0), may be a decimal comma: the run's first line says what it compares, and the
    run goes on."""
    code, lines = run_main(*args, "--steps", "2", "--no-frames", "--out", str(tmp_path))
    assert code == 0 and lines[0] == said


@pytest.mark.parametrize("args", [["--mu", "0.1,0.11"], ["--mu", "0,0.11,1"], ["--n-seg", "4,8"],
                                  ["--k", "2e4,4e4"], ["--v0", "1,0;2,0"],
                                  ["--pull-speed", "3,6", "--scene", "tablecloth"],
                                  ["--tilt", "60,70", "--scene", "chalk"]])
def test_other_lists_say_nothing_about_decimals(args, tmp_path):
    """Two speeds or two angles are a comparison as written: no note (issue 40)."""
    code, lines = run_main(*args, "--steps", "2", "--no-frames", "--out", str(tmp_path))
    assert code == 0 and not [line for line in lines if "decimal" in line]


def test_cli_prints_the_warning(tmp_path):
    code, lines = run_main("--h", "1", "--steps", "2", "--out", str(tmp_path), "--no-frames")
    said = "simulator.py: warning: time step h = 1 s moves the square 9.81 m per step"
    assert code == 0 and any(line.startswith(said) for line in lines), lines
