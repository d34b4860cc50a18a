"""log.csv's friction columns read the same way for lagged friction and for Algorithm 5:
friction_updates counts the fixed-point updates that re-solved the step (0 when lagged, at most
--friction-iterations), friction_converged says whether the step ended at the fixed point (always 1
when lagged, which does not iterate)."""
import csv

import pytest

import simulator
import time_integrator
from helpers.command import recorded
from analysis import log


def logged_rows(tmp_path, scene, steps):
    """log.csv of `steps` steps of `scene`, as a run writes it, as dicts (without the t = 0 row)."""
    recorded(tmp_path, [scene], steps)
    with open(tmp_path / "log.csv") as f:
        return list(csv.DictReader(f))[1:]


def test_the_columns_are_named_for_what_they_count():
    assert "friction_updates" in log.COLUMNS and "friction_iterations" not in log.COLUMNS
    assert log.COLUMNS.index("friction_converged") == log.COLUMNS.index("friction_updates") + 1


@pytest.mark.parametrize("overrides", [{}, {"mu": 0.0, "friction_updates": 3}])
def test_lagged_friction_makes_no_updates(tmp_path, overrides):
    """The lecture's lagged friction (and a scene without friction, whatever the cap) re-solves
    nothing."""
    rows = logged_rows(tmp_path, simulator.build_scene(**overrides), 40)
    assert {(r["friction_updates"], r["friction_converged"]) for r in rows} == {("0", "1")}


def test_algorithm_5_counts_its_updates_up_to_the_cap(tmp_path):
    """With a cap of one update at tol 1e-6 (the lagged solve is sometimes at the fixed point,
    sometimes not): 0 or 1 updates a step; a step that ends off the fixed point has used the cap;
    the count is the last friction_update label of the step's Newton iterates, the solves the
    window shows."""
    scene = simulator.build_scene(friction_updates=1, tol=1e-6)
    rows = logged_rows(tmp_path, scene, 45)
    updates = [int(r["friction_updates"]) for r in rows]
    assert set(updates) == {0, 1}
    assert all(u == 1 for u, r in zip(updates, rows) if r["friction_converged"] == "0")
    assert "0" in {r["friction_converged"] for r in rows}
    x, v = scene.x0, scene.v0
    for index, expected in enumerate(updates):
        iterates = time_integrator.newton_iterates(scene, x, v, step_index=index)
        labels = []
        while True:
            try:
                labels.append(next(iterates).friction_update)
            except StopIteration as done:
                x, v, report = done.value
                break
        assert report.friction_updates == max(labels) == expected, f"step {index + 1}"
