"""A run takes every step it says it simulated: the closing line's count is log.csv's last step,
whatever the time step or the frame stride (issue 40, item 4)."""
import csv

import pytest

from helpers.command import closing_text, run_main


@pytest.mark.parametrize("flags, steps", [
    (["--frame-stride", "1e11", "--steps", "30"], 30),
    (["--h", "1e-12", "--steps", "3"], 3),
    (["--scene", "tablecloth", "--h", "1e-150", "--steps", "30"], 30)])
def test_the_steps_said_are_the_steps_logged(tmp_path, flags, steps):
    code, lines = run_main(*flags, "--no-frames", "--out", str(tmp_path / "run"))
    with open(tmp_path / "run" / "log.csv", newline="") as f:
        logged = [int(row["step"]) for row in csv.DictReader(f)]
    assert code == 0 and closing_text(lines).startswith(f"simulated {steps} steps ")
    assert logged == list(range(steps + 1))
