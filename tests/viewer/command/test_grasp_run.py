"""`--scene grasp` on the command line: its flags and lists, a run's closing words (held beside
u*, dropped beside the slip acceleration), log.csv's slip and finger forces, the pads drawn."""
import csv
import re
from pathlib import Path

import numpy as np
import pytest

from helpers.command import closing_text, run_main
from scenes import grasp
from viewer.command import cli, run
from viewer.pictures import draw

pytestmark = pytest.mark.usefixtures("shared_stepping")   # the runs' steps: helpers/runs.py


def test_grasp_flags_reach_the_scene_and_a_list_compares_squeezes():
    runs = cli.parse_command_line(["--scene", "grasp", "--squeeze", "1,2,4", "--lift-accel", "1",
                                   "--mu", "0.4", "--mass", "0.3", "--epsv", "2e-3"])
    plan = cli.plan_from_args(runs)
    assert [float(s.pushed.squeeze[0]) for s in plan.scenes] == [1.0, 2.0, 4.0]
    assert all(s.pushed.lift_accel == 1.0 and s.mu == 0.4 and s.params["mass"] == 0.3
               and s.epsv == 2e-3 for s in plan.scenes)
    assert plan.labels == ["squeeze = 1", "squeeze = 2", "squeeze = 4"]
    assert plan.steps == [round(grasp.DURATION / 0.005)] * 3 and plan.kind == "grasp"
    assert run.summary_header(plan)[1] == (
        "block 0.05 x 0.05 m, 0.3 kg   squeeze N = 1 N a finger   lift at a = 1 m/s^2 to 0.2 m/s "
        "from t = 0.1 s   mu = 0.4")
    (one,) = cli.parse_command_line(["--scene", "grasp"])
    assert cli.plan_from_args([one]).labels == ["squeeze = 2.616 N, mu = 0.5"]


def test_a_grasp_run_says_held_or_dropped_logs_the_slip_and_draws_the_pads(tmp_path):
    """0.3 s: squeeze 1 N drops the block (2 mu N / m = 5 m/s^2 < g: it slides 0.5 (g - 5) t^2,
    then faster in the lift, past the pads' 5 cm at about 0.14 s, as the Coulomb block does: 0.1 +
    0.0519 / (0.481 + sqrt(0.481^2 + 10.62 * 0.02595)) = 0.1435 s); 4 N holds it, each finger
    pressing with 4 N (the first steps off by up to 0.12 % while the block's springs take the
    squeeze up; measured)."""
    code, lines = run_main("--scene", "grasp", "--squeeze", "1,4", "--duration", "0.3",
                           "--frame-stride", "30", "--out", str(tmp_path))
    assert code == 0, lines
    last = closing_text(lines)
    assert all(len(line.replace(str(tmp_path), "")) <= 100 for line in lines), lines
    assert "squeeze = 1: dropped at 0.14 s (Coulomb 0.14); squeeze = 4: held, creeps " in last
    assert "(u* " in last
    with open(tmp_path / "log_squeeze4.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert float(rows[0]["slip"]) == 0.0 and 0.0 < float(rows[-1]["slip"]) < 1e-3
    forces = [float(r[k]) for r in rows for k in ("normal_force_left", "normal_force_right")]
    assert np.allclose(forces, 4.0, rtol=1e-2)       # the springs take the squeeze up: 0.12 %
    assert np.allclose(forces[-2:], 4.0, rtol=1e-4)     # settled
    pygame = draw.load_pygame()
    frame = pygame.surfarray.array3d(pygame.image.load(str(tmp_path / "frame_00000.png")))
    assert np.all(frame == draw.PUSHED_COLOR, axis=2).sum() > 500      # the pads, and the legend
    summary = pygame.surfarray.array3d(pygame.image.load(str(tmp_path / "summary.png")))
    assert np.all(summary == draw.PUSHED_COLOR, axis=2).sum() > 100    # each run's pads
    page = (tmp_path / "index.html").read_text(encoding="utf-8")
    title = "Block lifted between fingers: squeeze = 1, squeeze = 4"
    assert f"<title>{title}</title>" in page and f"<h2>{title}</h2>" in page


def test_a_run_too_short_to_fit_says_so_without_nan(tmp_path):
    """1 step, and a comparison of 2: too few states to fit a speed (test_grasp_words.py)."""
    code, lines = run_main("--scene", "grasp", "--steps", "1", "--no-frames",
                           "--out", str(tmp_path / "one"))
    assert code == 0, lines
    assert "the block is on the pads at 0.01 s (slid 0.00 mm, Coulomb 0); too short a run to fit " \
        "its speed" in closing_text(lines)
    code, lines = run_main("--scene", "grasp", "--squeeze", "1,4", "--steps", "2", "--no-frames",
                           "--out", str(tmp_path / "two"))
    last = closing_text(lines)
    assert code == 0 and "nan" not in last and "slips" not in last, lines
    assert "squeeze = 4: on the pads at 0.01 s, too short to fit its speed" in last


@pytest.mark.slow
def test_the_comparison_in_command_line_md_says_what_the_run_says(tmp_path):
    """docs/command-line.md's `--squeeze 1,2,4` block, its wall time and folder aside: it said
    'wrote 395 files' where the run writes 210 (51 frames of a PNG and 3 OBJs, 3 logs, 3
    pictures)."""
    doc = (Path(__file__).parents[3] / "docs" / "command-line.md").read_text(encoding="utf-8")
    block = doc.split("python simulator.py --scene grasp --squeeze 1,2,4\n```\n\n```\n")[1]
    said = block.split("\n```")[0].splitlines()
    code, lines = run_main("--scene", "grasp", "--squeeze", "1,2,4", "--out", str(tmp_path))
    assert code == 0, lines
    ran = [re.sub(r"in [0-9.]+ s wall", "in … s wall", line) for line in lines[-len(said):]]
    ran[-1] = ran[-1].replace(tmp_path.as_uri(), "file:///…/output/grasp-20261204-134500")
    assert ran == said
