"""The chalk's runs as the tests read them: their Tracks and stick-slip cycles. The runs are
helpers/runs.py's, each stepped once per test session (the `chalk_runs` fixture,
tests/conftest.py): test_chalk, test_wear, test_integrator's Newton starts, the stick-slip
figure's test (runs.replaying), the frames' marks, the window's chalk (helpers/fakes.py chalk_at),
and the plots' and summary's chalk Tracks (Runs.records) step the pushed and the dragged chalk
once between them."""
import dataclasses

import numpy as np

import simulator
from analysis import stick_slip as cycles


@dataclasses.dataclass(frozen=True)
class Track:
    """One run of the chalk, per step: the time, the tip's x and tangential velocity, the normal
    force on the chalk (sum of lambda_k), the hand's x (its targets'), the lowest node, and the
    lean: the held end's mean x minus the tip end's (< 0 pushed, leaning back over the tip)."""
    scene: simulator.Scene
    t: np.ndarray
    x_tip: np.ndarray
    u_tip: np.ndarray
    normal_force: np.ndarray
    hand_x: np.ndarray
    lowest: np.ndarray
    lean: np.ndarray


def track(scene, t, x, v):
    """The Track of the chalk `scene`'s states (t, x, v); the tip is its lowest node at the
    start."""
    tip = int(np.argmin(scene.x0[:, 1]))
    tip_end = np.arange(scene.cells[1] + 1)                         # column 0: the tip's end
    normal_force = [scene.contact.lambdas(scene, x_n).sum() for x_n in x]
    hand_x = [scene.hand.targets(t_n)[:, 0].mean() for t_n in t]
    lean = x[:, scene.hand.nodes, 0].mean(axis=1) - x[:, tip_end, 0].mean(axis=1)
    return Track(scene, t, x[:, tip, 0], v[:, tip, 0], np.array(normal_force), np.array(hand_x),
                 np.argmin(x[:, :, 1], axis=1), lean)


def stick_slip(track, start=0.2):
    """The cycles after `start` (the drive's start), as analysis/stick_slip.py counts them: (the
    fraction of the states stuck, the slips as (start time, length, peak speed))."""
    scene = track.scene
    counted = cycles.measure(track.t, track.x_tip, track.u_tip, scene.epsv, scene.params["drive"],
                             start)
    return counted.stuck, counted.slips
