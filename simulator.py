"""The lecture's case study, an elastic mass-spring square dropped onto a slope with friction
(scenes/square.py), and its closing remark, Rabinowicz's chalk pushed or dragged across a board by a
hand (scenes/chalk.py), and the tablecloth trick, friction against a moving surface
(scenes/tablecloth.py), and the scenes under scenes/ (scenes.UNITS), stepped by implicit Euler:

    scene = build_scene(mu=0.2)                 # the lecture's numbers (DEFAULTS), one changed
    for record in simulate(scene, steps=300):   # one time_integrator.step at a time
        print(record.t, record.x.mean(axis=0))
    chalk = build_chalk_scene(k_hand=4000.0)    # the chalk's numbers (CHALK), one changed
    cloth = build_tablecloth_scene(pull_speed=8.0)  # the tablecloth's numbers (TABLECLOTH)

`python simulator.py` runs the scene and writes what it shows (frames, a page, plots, a log): the
command line lives in viewer/command/cli.py (`python simulator.py --help`), the drawing in viewer/.
"""
if __name__ == "__main__":      # python simulator.py [flags]: the command line, before numpy loads
    from viewer.command import startup
    raise SystemExit(startup.run_command_line())

from dataclasses import dataclass
from time import perf_counter

import numpy as np

import time_integrator
import utils
from scenes.chalk import CHALK, build_chalk_scene  # noqa: F401 (the chalk's scene, here by name)
from scenes.scene import Scene  # noqa: F401 (what a scene is)
from scenes.square import ALIASES, DEFAULTS, build_scene  # noqa: F401 (the lecture's scene)
from scenes.tablecloth import TABLECLOTH, build_tablecloth_scene  # noqa: F401 (moving surface)


@dataclass
class StepRecord:
    """One step of a run: its index, the time after it, the new state, its report and wall time."""
    index: int
    t: float
    x: np.ndarray
    v: np.ndarray
    report: time_integrator.StepReport
    wall: float


def simulate(scene, steps):
    """Yield a StepRecord for each of `steps` time steps from the scene's start (x0, v0)."""
    x, v = scene.x0, scene.v0           # read-only: each step returns new arrays
    for i in range(utils.check_whole("steps", steps, 1)):
        t0 = perf_counter()             # the wall clock
        x, v, report = time_integrator.step(scene, x, v, step_index=i)
        yield StepRecord(i, time_integrator.step_time(scene, i), x, v, report, perf_counter() - t0)
