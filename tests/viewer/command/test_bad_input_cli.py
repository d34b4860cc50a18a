"""Bad scene parameters on the command line: one line and exit code 2 naming the flag and the value,
before anything is written; nothing already on disk is touched (the library's refusals:
tests/scenes/test_bad_input_scene.py)."""
import os
import subprocess
import sys

import pytest

from helpers import ROOT
from helpers.command import ending, refused, run_main


def cli(*args, python=()):
    """python simulator.py ARGS as a child process: the whole path, start-up included; `python`:
    options to the interpreter."""
    return subprocess.run([sys.executable, *python, os.path.join(ROOT, "simulator.py"), *args],
                          capture_output=True, text=True, timeout=120,
                          env={**os.environ, "SDL_VIDEODRIVER": "dummy"})


CLI = [
    (["--side", "0"], "--side: side_len must be a finite number > 0, got 0.0"),
    (["--n-seg", "0"], "--n-seg: n_seg must be a whole number >= 1, got 0"),
    (["--density", "-1"], "--density: rho must be a finite number > 0, got -1.0"),
    (["--mass", "0"], "--mass: mass must be a finite number > 0, got 0.0"),
    (["--k", "-2e4"], "--k: k must be a finite number > 0, got -20000.0"),
    (["--h", "0"], "--h: h must be a finite number > 0, got 0.0"),
    (["--duration", "0"], "--duration: duration must be a finite number > 0, got 0.0"),
    (["--duration", "0.001"],
     "--duration: duration 0.001 s is shorter than one time step h = 0.01 s"),
    (["--steps", "-5"], "--steps: steps must be a whole number >= 1, got -5.0"),
    (["--dhat", "0"], "--dhat: dhat must be a finite number > 0, got 0.0"),
    (["--kappa", "0"], "--kappa: kappa must be a finite number > 0, got 0.0"),
    (["--epsv", "-1e-3"], "--epsv: epsv must be a finite number > 0, got -0.001"),
    (["--tol", "0"], "--tol: tol must be a finite number > 0, got 0.0"),
    (["--mu", "-0.5"], "--mu: mu must be >= 0, got -0.5"),
    (["--slope-normal", "0,0"], "--slope-normal: slope normal must be non-zero, got [0.0, 0.0]"),
    (["--slope-angle", "90"], "--slope-angle: slope-angle must be in (-90, 90) degrees, got 90.0"),
    (["--slope-point", "0,-0.4"], "touches the slope"),
    (["--frame-stride", "0"], "--frame-stride: frame-stride must be a whole number >= 1, got 0.0"),
    (["--friction-iterations", "-1"], "friction_updates must be a whole number >= 0, got -1.0"),
    (["--mu", "abc"], "argument --mu: invalid float value: 'abc'"),
    (["--steps", "abc"], "argument --steps: invalid int value: 'abc'"),
    (["--n-seg", "four"], "argument --n-seg: invalid int value: 'four'"),
    (["--frame-stride", "x"], "argument --frame-stride: invalid int value: 'x'"),
    (["--max-newton", "1,x"], "argument --max-newton: invalid int value: 'x'"),
    (["--newton-start", "x0"], "argument --newton-start: invalid choice: 'x0'"),
    (["--scene", "tablecloth", "--pull-speed", "0"],
     "--pull-speed: pull_speed must be a finite number > 0, got 0.0"),
    (["--scene", "tablecloth", "--pull-length", "-1,2"],
     "--pull-length: pull_length must be a finite number > 0, got -1.0"),
    (["--scene", "tablecloth", "--pull-speed", "inf"], "--pull-speed: pull_speed must be"),
    (["--scene", "tablecloth", "--mu", "-0.1"], "--mu: mu must be a finite number >= 0"),
    (["--pull-speed", "2"],
     "--pull-speed applies only to --scene tablecloth (not square)"),
    (["--scene", "chalk", "--pull-length", "2"],
     "--pull-length applies only to --scene tablecloth"),
    (["--scene", "tablecloth", "--tilt", "60"],
     "--tilt applies only to --scene chalk (not tablecloth)"),
    (["--scene", "tablecloth", "--slope-angle", "10"],
     "--slope-angle applies only to --scene square (not tablecloth)"),
    (["--scene", "grasp", "--squeeze", "0"], "--squeeze: squeeze must be a finite number > 0"),
    (["--scene", "grasp", "--lift-accel", "1,-1"],
     "--lift-accel: lift_accel must be a finite number > 0, got -1.0"),
    (["--squeeze", "2"],
     "--squeeze applies only to --scene grasp (not square)"),
    (["--scene", "grasp", "--gravity", "1,-9.81"],
     "--gravity: gravity must point down the fingers"),
]
SCALARS = ("--mu", "--h", "--side", "--k", "--density", "--mass", "--dhat", "--kappa", "--epsv",
           "--tol", "--n-seg", "--duration", "--steps", "--frame-stride", "--slope-angle",
           "--friction-iterations", "--max-newton")
CLI += [([flag, value], "must be") for flag in SCALARS for value in ("nan", "inf")]
CLI += [([flag, value], "must be") for flag in ("--slope-normal", "--slope-point", "--v0",
                                                 "--gravity") for value in ("nan,1", "0,inf")]


@pytest.mark.parametrize("args, message", CLI, ids=[" ".join(a) for a, _ in CLI])
def test_cli_refuses_in_one_line_with_exit_2_and_touches_nothing(args, message, tmp_path):
    assert message in refused(args, tmp_path / "out")


@pytest.mark.parametrize("args, message", [(["--mu", "-0.5"], "--mu: mu must be >= 0"),
                                           (["--steps", "abc"], "invalid int value: 'abc'")])
def test_simulator_py_refuses_in_one_line_with_exit_2(args, message, tmp_path):
    """The same refusals from `python simulator.py`, start-up and all: nothing made, and said
    before scipy (the Newton solve's LAPACK, 0.25 s of CPU) or pygame (the drawing) is loaded:
    -X importtime lists on stderr every module the process imported."""
    result = cli(*args, "--out", str(tmp_path / "o"), python=("-X", "importtime"))
    imported = [line.split("|")[-1].strip() for line in result.stderr.splitlines()
                if line.startswith("import time:")]
    lines = [line for line in result.stderr.splitlines() if not line.startswith("import time:")]
    assert result.returncode == 2 and len(lines) == 1, result.stderr
    assert lines[0].startswith("simulator.py: error: ") and message in lines[0]
    assert not (tmp_path / "o").exists()
    assert "numpy" in imported and "viewer.command.cli" in imported     # what it did load
    assert not [name for name in imported if name.split(".")[0] in ("scipy", "pygame")]


def test_cli_refuses_unwritable_output_folder(tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    code, lines = run_main("--steps", "2", "--out", str(blocker / "sub"))
    assert code == 2 and len(lines) == 1
    said = f"simulator.py: error: --out: out folder '{blocker / 'sub'}' cannot be created"
    assert lines[0].startswith(said) and blocker.read_text() == "not a folder"


def test_failure_mid_run_keeps_every_file_whole(tmp_path):
    """Newton capped at one iteration fails at the impact: its ending (at most 3 lines of at most
    100 columns, its figures after the failure), exit 1, and every frame, OBJ and CSV row written
    before it stays, whole; no temporary file is left."""
    out = tmp_path / "out"
    code, lines = run_main("--max-newton", "1", "--tol", "1e-6", "--steps", "60",
                           "--frame-stride", "1", "--out", str(out))
    failure = ending(lines)
    assert code == 1 and failure.startswith("simulator.py: stopped: simulation failed: "), lines
    rows = (out / "log.csv").read_text().splitlines()
    completed = len(rows) - 2                       # the header and the t = 0 row
    assert 0 < completed < 60 and f"; {completed} steps kept in {out}/" in failure
    assert f"step {completed + 1}: Newton did not converge; residual=" in failure  # log.csv's n
    assert all(len(r.split(",")) == len(rows[0].split(",")) for r in rows)
    files = set(os.listdir(out))
    assert {f"frame_{i:05d}.png" for i in range(completed + 1)} <= files
    assert {f"frame_{i:05d}.obj" for i in range(completed + 1)} <= files
    assert f"frame_{completed + 1:05d}.png" not in files and "summary.png" in files
    assert not [f for f in files if f.startswith(".")]
