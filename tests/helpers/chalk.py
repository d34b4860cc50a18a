"""The chalk's runs as the scene tests read them, each stepped once per test session: a run's first
seconds are the shorter run (the same steps), so every shorter run is cut from the longest kept."""
import dataclasses

import numpy as np

import BarrierEnergy
import simulator
from analysis import stick_slip as cycles

_LONGEST = {}       # the chalk's parameters -> the longest Track stepped with them


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

    def first(self, steps):
        """The run's first `steps` steps."""
        arrays = {f.name: getattr(self, f.name)[:steps] for f in dataclasses.fields(self)
                  if f.name != "scene"}
        return dataclasses.replace(self, **arrays)


def stepped(scene, steps):
    """The Track of `steps` steps of the chalk `scene`; the tip is its lowest node at the start."""
    tip = int(np.argmin(scene.x0[:, 1]))
    tip_end = np.arange(scene.cells[1] + 1)                         # column 0: the tip's end
    rows = []
    for rec in simulator.simulate(scene, steps):
        lam = BarrierEnergy.compute_mu_lambda_kernel(rec.x, scene.n, scene.o, scene.contact_area,
                                                     1.0, scene.dhat, scene.kappa)
        lean = rec.x[scene.hand.nodes, 0].mean() - rec.x[tip_end, 0].mean()
        hand_x = scene.hand.targets(rec.t)[:, 0].mean()
        rows.append((rec.t, rec.x[tip, 0], rec.v[tip, 0], lam.sum(), hand_x,
                     np.argmin(rec.x[:, 1]), lean))
    t, x_tip, u_tip, normal_force, hand_x, lowest, lean = map(np.array, zip(*rows))
    return Track(scene, t, x_tip, u_tip, normal_force, hand_x, lowest.astype(int), lean)


def run(seconds, **params):
    """The chalk built from `params`, stepped for `seconds`: cut from the longest run kept."""
    scene = simulator.build_chalk_scene(**params)
    steps = int(round(seconds / scene.h))
    key = tuple(sorted(params.items()))
    if key not in _LONGEST or len(_LONGEST[key].t) < steps:
        _LONGEST[key] = stepped(scene, steps)
    return _LONGEST[key].first(steps)


def stick_slip(track, start=0.2):
    """The cycles after `start` (the drive's start), as analysis/stick_slip.py counts them: (the
    fraction of the states stuck, the slips as (start time, length, peak speed))."""
    scene = track.scene
    counted = cycles.measure(track.t, track.x_tip, track.u_tip, scene.epsv, scene.params["drive"],
                             start)
    return counted.stuck, counted.slips
