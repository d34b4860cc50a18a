"""Scenes at the edge of float64 and of the machine on the command line: one line naming the flag
and the value, exit code 2, nothing written (the library's refusals: tests/physics/
test_bad_input_limits.py)."""
import csv
import os

import numpy as np
import pytest

from helpers.command import refused, run_main
from viewer.command import cli


def scene_of(argv):
    (args,) = cli.parse_command_line(argv)
    return cli.scene_from_args(args)


def test_the_lectures_45_degree_start_touches_the_slope_and_is_refused(tmp_path):
    """At 45 degrees the lecture's placement puts corner 0 on the slope up to round-off (1.1e-16 m
    computed): refused like a start below it, naming --center and a centre that works."""
    words = r"node 0 touches the slope \(1e-16 m\): try --center "
    with pytest.raises(ValueError, match=words) as info:
        scene_of(["--slope-angle", "45"])
    suggested = str(info.value).split("try --center ")[1].split(",")[:2]
    center = (float(suggested[0]), float(suggested[1].split()[0]))
    scene = scene_of(["--slope-angle", "45", "--center", f"{center[0]!r},{center[1]!r}"])
    d = (scene.x0 - scene.o) @ scene.n
    assert d.min() == pytest.approx(scene.dhat, rel=1e-5)      # dhat above, as said (6 digits)
    line = refused(["--slope-angle", "45"], tmp_path / "out")
    assert line.startswith("simulator.py: error: --center: node 0 touches the slope")


def test_center_flag_reaches_the_scene():
    scene = scene_of(["--center", "1.5,-0.25", "--no-slope"])
    assert np.average(scene.x0, axis=0, weights=scene.m) == pytest.approx([1.5, -0.25], abs=1e-12)
    assert "--center" in cli.make_parser().format_help()


CLI = [
    (["--h", "1e200"], "--h: h = 1e+200: first inertia term"),
    (["--dt", "1e300"], "--h: h = 1e+300: first inertia term"),
    (["--side", "1e200"],
     "--side: side_len = 1e+200: total mass"),
    (["--side", "1e100", "--mass", "1", "--k", "1e-190"],
     "--side: side_len = 1e+100: dhat 0.01 m is below round-off at "),
    (["--side", "1e200", "--no-slope", "--mass", "1"],
     "--side: side_len = 1e+200: "),
    (["--duration", "1e308"],
     "--duration: duration = 1e+308 s: inf steps of h = 0.01 s (at most 1e+08)"),
    (["--steps", "1e30"],
     "--steps: steps = 1e+30: 1e+30 steps of h = 0.01 s (at most 1e+08)"),
    (["--scene", "chalk", "--steps", "100000001"],
     "--steps: steps = 100000001: 100000001 steps of h = 0.001 s (at most 1e+08)"),
    (["--scene", "grasp", "--duration", "1e6"],
     "--duration: duration = 1e+06 s: 200000000 steps of h = 0.005 s (at most 1e+08)"),
    (["--n-seg", "1e5"], "--n-seg: n_seg = 100000: 1.00e+10 nodes"),
    (["--n-seg", "1e308"], "--n-seg: n_seg = 1e+308: "),
    (["--v0", "1e308,0"], "--v0: v0 = 1e+308, 0: kinetic energy inf > 1e+150 (float64)"),
    (["--dhat", "1e308"], "--dhat: dhat = 1e+308: "),
    (["--k", "1e30"], "--k: k = 1e+30: h^2 k / m = 2.5e+24 > 0.1/eps (m lost in float64)"),
    (["--h", "1e10"], "--h: h = 1e+10"),
    (["--mu", "-inf"], "--mu: mu must be finite, got -inf"),
    (["--k", "-inf"], "--k: k must be a finite number > 0, got -inf"),
    (["--v0", "-inf,0"], "--v0: v0 must be finite, got [-inf, 0.0]"),
    (["--center", "1e16,0"], "--center: center = 1e+16, 0: spacing 0.25 m is below round-off at "),
    (["--epsv", "1e-300"], "--epsv: epsv must be in [1e-150, 1e+150] m/s"),
    *[(["--scene", scene, "--epsv", "1e308"], "--epsv: epsv must be in [1e-150, 1e+150] m/s")
      for scene in ("square", "chalk", "tablecloth", "grasp")],
]


@pytest.mark.parametrize("args, message", CLI, ids=[" ".join(a) for a, _ in CLI])
def test_absurd_value_is_one_line_naming_flag_and_value(args, message, tmp_path):
    line = refused(args, tmp_path / "out")
    assert line.startswith(f"simulator.py: error: {message}"), line


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs Linux's /proc")
def test_out_folder_that_cannot_be_made():
    """/proc holds no folder a run can make: refused in one line, naming --out."""
    code, lines = run_main("--steps", "2", "--out", "/proc/self/run")
    assert code == 2 and len(lines) == 1
    said = "simulator.py: error: --out: out folder '/proc/self/run' cannot be created: "
    assert lines[0].startswith(said)


def test_cli_subnormal_slope_normal_runs_as_the_lectures(tmp_path):
    """--slope-normal 1e-320,1e-319 is the lecture's slope, (0.1, 1) in other units: the same run,
    bit for bit, where it used to be refused."""
    rows = []
    for k, slope in enumerate(("1e-320,1e-319", "0.1,1")):
        out = tmp_path / str(k)
        code, lines = run_main("--slope-normal", slope, "--out", str(out), "--steps", "3",
                               "--no-frames")
        assert code == 0, lines
        with open(out / "log.csv", newline="") as f:
            rows.append([{**row, "wall_s": None} for row in csv.DictReader(f)])
    assert rows[0] == rows[1] and len(rows[0]) == 4
