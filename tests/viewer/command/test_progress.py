"""viewer/command/progress.py: what a run says as it goes. The warnings about a step are worded in
one place (step_warnings), for a run to files and the window alike; a run says each kind once."""
import csv
import io
import re
import types

import numpy as np
import pytest

import simulator
import time_integrator
from helpers.command import recorded, run_main, too_wide
from scenes import grasp
from viewer.command import progress
from analysis import closing, stick_slip

pytestmark = pytest.mark.usefixtures("shared_stepping")   # the runs' steps: helpers/runs.py


def test_step_warnings_name_the_step_and_what_to_do():
    scene = simulator.build_scene()
    calm = time_integrator.StepReport(residual=0.004)
    assert progress.step_warnings(scene, 12, 0.12, calm, 0) == {}
    stalled = time_integrator.StepReport(residual=1.3e-8, stalled=True)
    said = progress.step_warnings(scene, 30, 0.3, stalled, 4)
    assert list(said) == ["inverted", "stalled"]
    at = "at step 30 (t = 0.30 s)"
    assert said["inverted"].startswith(f"{at} 4 of 32 mesh triangles are inverted")
    assert "--k" in said["inverted"] and "--h" in said["inverted"]
    assert said["stalled"].startswith(f"{at} Newton stopped at float64's round-off floor, "
                                      "residual 1.3e-08 m/s above tol = 0.01 m/s")


@pytest.mark.parametrize("build, body", [(simulator.build_scene, "the square"),
                                         (simulator.build_chalk_scene, "the chalk"),
                                         (simulator.build_tablecloth_scene, "the dish"),
                                         (grasp.build_grasp_scene, "the block")])
def test_an_inverted_mesh_is_said_of_the_scene_s_own_body(build, body):
    """The grasp's block was 'the square folded over' (--scene grasp --k 1e-320)."""
    scene = build()
    said = progress.step_warnings(scene, 3, 0.01, time_integrator.StepReport(residual=0.0), 2)
    assert scene.body == body and f"are inverted ({body} folded over, docs" in said["inverted"]


def test_a_run_to_files_says_each_kind_of_warning_once(tmp_path):
    """Newton stalls at many steps of a run at tol 1e-8; the warning comes once, at the first."""
    scene = simulator.build_scene(tol=1e-8)
    tracks = recorded(tmp_path, [scene], 40)
    stalled = [s.step for s in tracks[0].samples.all() if s.report is not None and s.report.stalled]
    assert len(stalled) > 1 and tracks[0].warned == {"stalled"}


def chalk_track(label, speeds, **scene):
    """A chalk run's track as the closing words read it: its scene and its kept states, the tip at
    rest while the hand presses and holds, then at `speeds` (m/s), one a step (x^{n+1} = x^n + h
    u^{n+1})."""
    scene = simulator.build_chalk_scene(**scene)
    u = np.r_[np.zeros(int(round(stick_slip.drive_start(scene) / scene.h)) + 1), speeds]
    x = np.cumsum(scene.h * u)
    states = [types.SimpleNamespace(step=k, t=k * scene.h, tip_x=x[k], tip_speed=abs(u[k]))
              for k in range(len(u))]
    samples = types.SimpleNamespace(all=lambda: states)
    return types.SimpleNamespace(label=label, scene=scene, samples=samples)


def test_a_comparison_whose_chalks_all_stick_slip_says_each_figure_run_by_run():
    """Four grips' words, each run's about 100 characters, in one list per figure (issue 40: the
    closing within 3 lines of 100 columns), in the runs' order."""
    stick, slip = [1e-5] * 40, [0.1] * 6        # 40 ms stuck, a 0.6 mm slip
    longer = [1e-5] * 60                        # 60 ms stuck: a period of 66 ms
    runs = [chalk_track("a", (stick + slip) * 4 + stick), chalk_track("b", (longer + slip) * 3)]
    said = closing.closing_words(runs)
    assert said == (f"stick-slip: 4, 2 slips; mean slip 0.60, 0.60 mm; tip stuck "
                    f"{100 * 200 / 224:.0f}, {100 * 180 / 198:.0f} %; creeping 0.01 mm/s")  # 1e-5


def test_the_chalks_closing_words_are_its_stick_slip():
    """Not when the tip was last stuck (the hand moves on) but what the tip did: the pushed chalk's
    cycles, a sliding one's start-up, in each run's words for a comparison."""
    stick, slip = [1e-5] * 40, [0.1] * 6        # 40 ms stuck, a 0.6 mm slip
    drive = simulator.CHALK["drive"]
    pushed = chalk_track("mu-static = 0.5", (stick + slip) * 4 + stick)
    sliding = chalk_track("mu-static = 0.35", [drive] * 200, mu_s=0.35)
    said = closing.closing_words([pushed])
    assert said == (f"stick-slip: 4 slips, mean slip {6 * 1e-3 * 0.1 * 1e3:.2f} mm, period "
                    f"{46:.0f} ms, stuck {100 * 200 / 224:.0f} % of the drive, creeping "
                    f"{1e3 * 1e-5:.2g} mm/s")
    assert "rest" not in said
    slid = "the tip slid without a stick after its start-up at t = 0.20 s"
    assert closing.closing_words([sliding]) == slid
    assert closing.closing_words([sliding, pushed]) == (   # short, for the closing's 3 lines
        f"mu-static = 0.35: slides, no stick; mu-static = 0.5: 4 slips of "
        f"{6 * 1e-3 * 0.1 * 1e3:.2f} mm, creeping {1e3 * 1e-5:.2g} mm/s")
    note = closing.closing_note([pushed])
    first, second = stick_slip.definition(pushed.scene)
    assert note == f"{said} ({first} {second})" and "stick of at least 10 steps (10 ms)" in note


def test_progress_lines_come_every_tenth_of_the_run():
    log = io.StringIO()
    report = time_integrator.StepReport(residual=2e-3, alphas=[1.0, 1.0])
    last = types.SimpleNamespace(report=report, min_distance=0.5)
    tr = types.SimpleNamespace(label="run", steps=100, step=0, t=0.0, scene=simulator.build_scene(),
                               samples=types.SimpleNamespace(last=last))
    lines = progress.Progress([tr], log)
    for step in range(1, 101):
        tr.step, tr.t = step, step * 0.01
        lines.tick(tr)
    rows = log.getvalue().splitlines()
    first = "step 10/100  t=0.10s  newton=2  residual=2.0e-03  min_d=5.00e-01"
    assert len(rows) == 10 and rows[0] == first


def test_a_comparisons_progress_lines_give_each_runs_own_step_as_its_log(tmp_path):
    """Runs advance in turn, a frame's steps at a time: the line for step N waits until every run
    has logged step N, and gives each run's figures of that step, as its log.csv has them (runs of
    another h too: the h = 0.005 run's step N is its own, at another t)."""
    code, lines = run_main("--mu", "0.1,0.11", "--steps", "60", "--no-frames",
                           "--out", str(tmp_path))
    assert code == 0
    check_lines_against_logs(tmp_path, ["mu0.1", "mu0.11"], lines, expected=6)
    code, lines = run_main("--h", "0.01,0.005", "--duration", "0.6", "--no-frames",
                           "--out", str(tmp_path / "h"))
    assert code == 0
    check_lines_against_logs(tmp_path / "h", ["h0.01", "h0.005"], lines, expected=12)
    assert lines[-3].startswith("simulated 2 runs of 0.60 s: 60, 120 steps in ")


def check_lines_against_logs(folder, tags, lines, expected):
    """Each progress line's figures are the log rows of its step: each run's Newton iterations
    ('-': a run that had ended when the line was due, a timed one), the largest residual and the
    least min_d of the runs shown, and each run's t where their h differ (to 2 decimals)."""
    said = [line for line in lines if line.startswith("step ")]
    assert len(said) >= expected and all(len(line) <= 100 for line in said)
    logs = []
    for tag in tags:
        with open(folder / f"log_{tag}.csv", newline="") as f:
            logs.append({int(row["step"]): row for row in csv.DictReader(f)})
    for line in said:
        step = int(line.split()[1].split("/")[0])
        times, newton, residual, min_d = re.fullmatch(
            r"step \d+/\d+  t=(\S+)s  newton=(\S+)  residual<=(\S+)  min_d>=(\S+)", line).groups()
        rows = [log.get(step) for log in logs]
        shown = [row for row, n in zip(rows, newton.split(","), strict=True) if n != "-"]
        assert shown and all(row is not None for row in shown), line
        assert [row["newton_iterations"] for row in shown] == \
            [n for n in newton.split(",") if n != "-"], line
        assert residual == f"{max(float(row['residual']) for row in shown):.1e}", line
        assert min_d == f"{min(float(row['min_distance']) for row in shown):.2e}", line
        if len(times.split(",")) > 1:       # 0.205 may show as 0.20 or 0.21
            assert [abs(float(t) - float(row["t"])) <= 0.005 + 1e-9
                    for t, row in zip(times.split(","), rows) if t != "-"] == [True] * len(shown)


def test_a_comparison_of_many_runs_gives_the_least_to_the_most_within_100_columns(tmp_path):
    """30 runs: a Newton count each ran to 105 columns at 20 runs and 1061 at 500 (a tester's);
    where the run-by-run line would not fit, it gives the least to the most ('newton=0-1')."""
    mus = ",".join(f"{0.1 + 0.01 * k:.2f}" for k in range(30))
    code, lines = run_main("--mu", mus, "--steps", "3", "--no-frames", "--out", str(tmp_path))
    said = [line for line in lines if line.startswith("step ")]
    assert code == 0 and said and not too_wide(lines, tmp_path), lines
    for line in said:
        assert re.fullmatch(r"step \d+/3  t=0\.0\ds  newton=\d+(-\d+)?  residual<=\S+  "
                            r"min_d>=\S+", line), line
