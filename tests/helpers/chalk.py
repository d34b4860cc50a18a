"""The chalk's runs as the tests read them, each stepped once per test session: a run's first
seconds are the shorter run (the same steps), so every shorter run is cut from the longest kept.
The states are kept as .npz, their StepReports beside them, in a folder the session's
pytest-xdist workers share (the `chalk_runs` fixture, tests/conftest.py): the first worker to need
a run steps it while the others wait for it. So test_chalk, test_wear, test_integrator's Newton
starts, the stick-slip figure's test (`replaying`), the frames' marks, the window's chalk
(helpers/fakes.py chalk_at), and the plots' and summary's chalk Tracks (Runs.records) step the
pushed and the dragged chalk once between them. A run asked for longer than kept goes on from its
last state (`stepped`), so whichever asks first, each state is stepped once."""
import contextlib
import dataclasses
import os
import pickle
import time
import types

import numpy as np

import simulator
import time_integrator
from analysis import stick_slip as cycles

WAIT = 600          # s another worker may take to step a run before this one gives up on it


class Runs:
    """The chalk's states after each step, keyed by its parameters that differ from
    simulator.CHALK (tilt=60.0 is the default's run), in `folder` and in memory; their
    StepReports and wall times in `folder`."""

    def __init__(self, folder):
        self.folder, self.kept = folder, {}

    def states(self, seconds, **params):
        """(scene, t, x, v) of the chalk built from `params` after each of round(seconds / h)
        steps: t (S,), x and v (S, N, 2), read-only."""
        scene = simulator.build_chalk_scene(**params)
        steps = int(round(seconds / scene.h))
        key = self.path(scene)
        if key not in self.kept or len(self.kept[key][0]) < steps:
            self.kept[key] = self.shared(key, scene, steps)[:3]
        return (scene, *(a[:steps] for a in self.kept[key]))

    def records(self, seconds, **params):
        """(scene, the simulator.StepRecords of its round(seconds / h) steps), as simulate yields
        them but for the wall times, those of the steps where they were taken."""
        scene, t, x, v = self.states(seconds, **params)
        *_, wall = read(self.path(scene))
        with open(self.path(scene) + ".reports", "rb") as f:
            reports = pickle.load(f)
        return scene, [simulator.StepRecord(i, *record) for i, record in
                       enumerate(zip(t.tolist(), x, v, reports, wall.tolist()))]

    def run(self, seconds, **params):
        """The Track of the chalk built from `params`, stepped for `seconds`."""
        return track(*self.states(seconds, **params))

    def path(self, scene):
        """The file of `scene`'s run, named by the parameters that differ from simulator.CHALK."""
        key = ",".join(f"{name}={value!r}" for name, value in sorted(scene.params.items())
                       if value != simulator.CHALK[name])
        return os.path.join(self.folder, f"chalk {key or 'default'}.npz")

    def shared(self, path, scene, steps):
        """(t, x, v, wall) of at least `steps` steps: read from the folder, or stepped here (on
        from what the folder keeps) and written there with the reports (a temporary name, then a
        rename, the reports first) while a lock file keeps other workers waiting."""
        deadline = time.monotonic() + WAIT
        while True:
            if kept_steps(path) >= steps:
                return read_only(*read(path))
            try:
                lock = os.open(path + ".lock", os.O_CREAT | os.O_EXCL | os.O_WRONLY)
                break
            except FileExistsError:             # another worker steps it: wait for its file
                assert time.monotonic() < deadline, f"{path}.lock held for {WAIT} s"
                time.sleep(0.05)
        try:
            kept = read(path)                   # again: it may have grown
            reports = []
            if len(kept[0]):
                with open(path + ".reports", "rb") as f:
                    reports = pickle.load(f)
            t, x, v, wall = stepped(scene, kept, reports, steps)
            for name, data in ((".reports", pickle.dumps(reports)), ("", None)):
                with open(path + name + ".tmp", "wb") as f:
                    if data is None:
                        np.savez(f, t=t, x=x, v=v, wall=wall)
                    else:
                        f.write(data)
                os.replace(path + name + ".tmp", path + name)
        finally:
            os.close(lock)
            with contextlib.suppress(OSError):
                os.remove(path + ".lock")
        return read_only(t, x, v, wall)


def replaying(runs):
    """The simulator module as a figure's code reads it, but for its `simulate` of a chalk scene:
    the StepRecords from `runs`, the chalk of the same parameters (Runs.records)."""
    def simulate(scene, steps):
        built, records = runs.records(steps * scene.h, **scene.params)
        assert dict(built.params) == dict(scene.params) and len(records) == steps
        return iter(records)
    return types.SimpleNamespace(**{**vars(simulator), "simulate": simulate})


def kept_steps(path):
    """How many steps the file at `path` keeps (reading its times alone), 0 if there is none."""
    if not os.path.exists(path):
        return 0
    with np.load(path) as kept:
        return len(kept["t"])


def read(path):
    """(t, x, v, wall) kept at `path`, or none (empty arrays) if there is no file."""
    if not os.path.exists(path):
        return np.empty(0), np.empty((0, 0, 2)), np.empty((0, 0, 2)), np.empty(0)
    with np.load(path) as kept:
        return kept["t"], kept["x"], kept["v"], kept["wall"]


def stepped(scene, kept, reports, steps):
    """(t, x, v, wall) of `steps` steps of `scene`: those `kept`, then simulator.simulate's steps
    after them, their StepReports added to `reports` (simulate's step i is time_integrator.step
    from state i at step_index i, so the states are the same bits as a run from the start:
    test_shared_runs_go_on_bit_for_bit)."""
    t, x, v, wall = (list(a) for a in kept)
    x_n, v_n = (x[-1], v[-1]) if t else (scene.x0, scene.v0)
    for i in range(len(t), steps):
        t0 = time.perf_counter()
        x_n, v_n, report = time_integrator.step(scene, x_n, v_n, step_index=i)
        wall.append(time.perf_counter() - t0)
        t.append(time_integrator.step_time(scene, i))
        x.append(x_n)
        v.append(v_n)
        reports.append(report)
    return np.array(t), np.array(x), np.array(v), np.array(wall)


def read_only(*arrays):
    for a in arrays:
        a.setflags(write=False)
    return arrays


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
