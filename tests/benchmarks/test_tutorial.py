"""benchmarks/tutorial.py: its arguments, and tutorial_driver.py on a tiny fake of the tutorial's
4_friction (its loop's shape: poll the events, draw, step, wait, write an OBJ). No timing."""
import os

import pytest

from benchmarks import tables, tutorial
from helpers.checkout import checkout_state

FAKE_SIMULATOR = """\
import os
import numpy as np
import pygame
pygame.init()
import time_integrator
side_len, rho, k, n_seg, h, mu = 1, 1000, 2e4, 4, 0.01, 0.2
ground_n = np.array([0.1, 1.0])
ground_n /= np.linalg.norm(ground_n)
ground_o = np.array([0.0, -1.0])
k = [k] * 3
screen = pygame.display.set_mode((8, 8))
running, time_step = True, 0
while running:
    for event in pygame.event.get():
        if event.type == pygame.QUIT:
            running = False
    screen.fill((255, 255, 255))
    pygame.display.flip()
    time_integrator.step_forward(None, None, None, None, None, k, ground_n, ground_o, None, mu,
                                 None, h, 1e-2)
    time_step += 1
    if time_step > 50:
        raise SystemExit("the loop did not end")
    pygame.time.wait(int(h * 1000))
    os.makedirs("output", exist_ok=True)
    open(f"output/{time_step}.obj", "w").close()
pygame.quit()
"""
FAKE_MODULES = {
    "simulator.py": FAKE_SIMULATOR,
    "time_integrator.py": ("def step_forward(*args):\n"
                           "    for i in range(3):      # a first direction, then 2 more\n"
                           "        search_dir()\n\n\n"
                           "def search_dir():\n    pass\n"),
    "BarrierEnergy.py": "dhat = 0.01\nkappa = 1e5\n",
    "FrictionEnergy.py": "epsv = 1e-3\n",
    "GravityEnergy.py": "gravity = [0.0, -9.81]\n"}


@pytest.fixture
def fake_tutorial(tmp_path):
    """A folder like a clone of the tutorial, with the fake 4_friction."""
    chapter = tmp_path / "clone" / tutorial.CHAPTER
    chapter.mkdir(parents=True)
    for name, text in FAKE_MODULES.items():
        (chapter / name).write_text(text)
    return tmp_path / "clone"


def test_without_the_tutorial_it_says_where_to_get_it_in_one_line(capsys):
    assert tutorial.main([]) == 2
    said = capsys.readouterr()
    assert said.out == "" and said.err.count("\n") == 1 and len(said.err) <= 101
    assert "--tutorial PATH" in said.err and tutorial.SOURCE in said.err


@pytest.mark.parametrize("args, named", [(["--tutorial", "{tmp}"], "--tutorial"),
                                         (["--tutorial", "{clone}", "--rounds", "0"], "--rounds")])
def test_bad_arguments_end_in_one_line_before_anything_runs(args, named, fake_tutorial, tmp_path,
                                                            monkeypatch, capsys):
    """A folder without 4_friction/simulator.py, or no round: exit status 2, nothing run."""
    monkeypatch.setattr(tutorial, "table", lambda *a: pytest.fail("ran"))
    args = [a.format(tmp=tmp_path, clone=fake_tutorial) for a in args]
    assert tutorial.main(args) == 2
    said = capsys.readouterr()
    assert said.out == "" and said.err.count("\n") == 1 and named in said.err


def test_the_driver_ends_the_tutorials_loop_after_the_steps_asked(fake_tutorial):
    """The fake's loop ends after 4 steps (its guard would stop it at 51), 2 directions a step after
    the first, its OBJs written in a scratch folder (tables.SCRATCH: output/ in a real benchmark,
    here conftest's), removed after, not in the tutorial or the checkout."""
    before = checkout_state()
    chapter = tutorial.chapter_folder(str(fake_tutorial))
    done = tutorial.run_tutorial(chapter, 4)
    assert done["steps"] == 4 and done["newton"] == 2 * 4
    assert done["cpu_s"] >= done["step_cpu_s"] >= 0 and done["wall_s"] > 0
    assert done["numbers"]["mu"] == 0.2 and done["numbers"]["tol"] == 1e-2
    assert tutorial.differences(done["numbers"]) == ["mu 0.11 against 0.2"]
    assert not (fake_tutorial / tutorial.CHAPTER / "output").exists()
    assert checkout_state() == before and os.listdir(tables.SCRATCH) == []


def test_the_table_has_the_three_runs_and_does_not_judge_a_short_run(fake_tutorial, monkeypatch):
    """The fake tutorial run for real, ours stubbed (the frames' tests run simulator.py): each
    row's ratios are the tutorial's medians over its own; 3 steps are not the default run."""
    def run_ours(flags, steps):
        return {"wall_s": 2.0 if flags else 4.0, "cpu_s": 0.01 if flags else 0.02, "newton": 7}
    monkeypatch.setattr(tutorial, "run_ours", run_ours)
    rows, runs = tutorial.table(tutorial.chapter_folder(str(fake_tutorial)), 1, 3)
    assert [r["run"] for r in rows] == ["tutorial 4_friction/simulator.py", "python simulator.py",
                                        "python simulator.py --no-frames"]
    assert [r["newton"] for r in rows] == [2 * 3, 7, 7]
    assert rows[2]["times_cpu"] == rows[0]["cpu_s"] / 0.01
    assert rows[1]["times_wall"] == rows[0]["wall_s"] / 4.0
    lines = tutorial.report(rows, runs, 1, 3)
    assert "mu 0.11 against 0.2" in " ".join(lines)
    assert "(target >= 8x: not judged: 3 steps, not the default run's 600)" in " ".join(lines)
    assert all(len(line) <= 100 for line in lines)
