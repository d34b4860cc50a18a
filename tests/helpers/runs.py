"""The runs the tests read, each stepped once per test session, whatever its scene (the square,
the chalk, the tablecloth, the grasp): a run's first steps are the shorter run (the same steps),
so every shorter run is cut from the longest kept. The states are kept as .npz, their StepReports
beside them, in a folder the session's pytest-xdist workers share (the `shared_runs` fixture,
tests/conftest.py): the first worker to need a run steps it while the others wait for it. A run
asked for longer than kept goes on from its last state (`stepped`), so whichever asks first, each
state is stepped once. A run is named by its builder and the parameters that differ from the
builder's defaults: the builders are deterministic, so the same name is the same scene, bit for
bit (helpers/chalk.py says which tests share the chalk's)."""
import contextlib
import copy
import dataclasses
import hashlib
import os
import pickle
import time
import types

import numpy as np

import simulator
import time_integrator
from helpers import chalk
from scenes import grasp

WAIT = 600          # s another worker may take to step a run before this one gives up on it
# a builder's name: (the builder, its defaults, the body its scenes say)
BUILDERS = {"chalk": (simulator.build_chalk_scene, simulator.CHALK, "the chalk"),
            "square": (simulator.build_scene, simulator.DEFAULTS, "the square"),
            "tablecloth": (simulator.build_tablecloth_scene, simulator.TABLECLOTH, "the dish"),
            "grasp": (grasp.build_grasp_scene, grasp.GRASP, "the block")}


class Runs:
    """The states after each step of the scenes built by BUILDERS[of](**params) (of="chalk",
    tilt=60.0 is the chalk's default run), in `folder` and in memory; their StepReports and wall
    times in `folder`."""

    def __init__(self, folder):
        self.folder, self.kept = folder, {}
        self.scenes = {}        # id(scene): (scene, its path; None: not its builder's)
        self.peeked = {}        # path: (the file's mtime, x, v, reports) as `taken` last read it

    def states(self, seconds, of="chalk", **params):
        """(scene, t, x, v) of the scene BUILDERS[of] builds from `params` after each of
        round(seconds / h) steps: t (S,), x and v (S, N, 2), read-only."""
        scene = BUILDERS[of][0](**params)
        return (scene, *self.scene_states(scene, int(round(seconds / scene.h))))

    def scene_states(self, scene, steps):
        """(t, x, v) of `steps` steps of `scene`, a scene as its builder made it (named by
        `path`)."""
        key = self.path(scene)
        if key not in self.kept or len(self.kept[key][0]) < steps:
            self.kept[key] = self.shared(key, scene, steps)[:3]
        return tuple(a[:steps] for a in self.kept[key])

    def records(self, seconds, of="chalk", **params):
        """(scene, the simulator.StepRecords of its round(seconds / h) steps), as simulate yields
        them but for the wall times, those of the steps where they were taken."""
        scene = BUILDERS[of][0](**params)
        return scene, self.scene_records(scene, int(round(seconds / scene.h)))

    def scene_records(self, scene, steps):
        """The simulator.StepRecords of `steps` steps of `scene` (as `scene_states` names it)."""
        t, x, v = self.scene_states(scene, steps)
        *_, wall = read(self.path(scene))
        with open(self.path(scene) + ".reports", "rb") as f:
            reports = pickle.load(f)
        return [simulator.StepRecord(i, *record) for i, record in
                enumerate(zip(t.tolist(), x, v, reports, wall.tolist()))]

    def simulate(self, scene, steps):
        """simulator.simulate(scene, steps) as `scene_records` keeps it: an iterator of its
        StepRecords."""
        records = self.scene_records(scene, steps)
        assert len(records) == steps
        return iter(records)

    def built(self, scene):
        """Whether `scene` is what its builder makes of its parameters, pickled byte for byte but
        for the solver's scratch arrays (a stepped scene's hold its last Newton system): a scene
        `path` may name by them (a command line's, say, as a test's)."""
        (builder, _, _), = (b for b in BUILDERS.values() if b[2] == scene.body)
        return without_scratch(scene) == without_scratch(builder(**scene.params))

    def taken(self, scene, x, v, step_index):
        """(x^{n+1}, v^{n+1}, StepReport) of time_integrator.step(scene, x, v, step_index=...)
        where a run kept in the folder took that step from that state, the same bits (so the same
        result: the step is deterministic); None where none did. Reads the folder, never steps."""
        if id(scene) not in self.scenes:
            self.scenes[id(scene)] = scene, self.path(scene) if self.built(scene) else None
        path = self.scenes[id(scene)][1]
        if path is None or not os.path.exists(path):
            return None
        mtime = os.stat(path).st_mtime_ns
        if self.peeked.get(path, (None,))[0] != mtime:
            _, xs, vs, _ = read(path)
            with open(path + ".reports", "rb") as f:
                self.peeked[path] = mtime, xs, vs, pickle.load(f)
        _, xs, vs, reports = self.peeked[path]
        if step_index >= len(xs):
            return None
        x_n, v_n = (scene.x0, scene.v0) if step_index == 0 else (xs[step_index - 1],
                                                                 vs[step_index - 1])
        if x.tobytes() != x_n.tobytes() or v.tobytes() != v_n.tobytes():
            return None
        return xs[step_index], vs[step_index], copy.deepcopy(reports[step_index])

    def run(self, seconds, **params):
        """The chalk.Track of the chalk built from `params`, stepped for `seconds`."""
        return chalk.track(*self.states(seconds, **params))

    def path(self, scene):
        """The file of `scene`'s run, named by its builder (known by its body) and the parameters
        that differ from the builder's defaults."""
        (name, (_, defaults, _)), = ((name, b) for name, b in BUILDERS.items()
                                     if b[2] == scene.body)
        key = ",".join(f"{param}={value!r}" for param, value in sorted(scene.params.items())
                       if param not in defaults or value != defaults[param])
        if len(key) > 150:          # a file's name has room for 255 bytes: a long key's digest
            key = hashlib.sha256(key.encode()).hexdigest()
        return os.path.join(self.folder, f"{name} {key or 'default'}.npz")

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
    """The simulator module as a figure's or recording's code reads it, but for its `simulate`:
    the StepRecords from `runs` (Runs.scene_records) of the scene it is given, a scene as its
    builder made it (BUILDERS: the same builder and parameters, the same scene)."""
    return types.SimpleNamespace(**{**vars(simulator), "simulate": runs.simulate})


def without_scratch(scene):
    """`scene` pickled but for its solver's band and edge_blocks (refilled each iteration)."""
    solver = dataclasses.replace(scene.solver, band=None, edge_blocks=None)
    return pickle.dumps(dataclasses.replace(scene, solver=solver))


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
