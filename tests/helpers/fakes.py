"""Failures the tests stage on purpose, and runs fast-forwarded for them."""
import copy
import errno
import itertools
import os
import signal

import simulator
import time_integrator
from viewer.demo import live
from viewer.output import whole_files


def fill_disk_after(monkeypatch, writes):
    """Let `writes` whole-file writes (whole_files.write_temporary: frames, OBJs, pictures) through,
    then fail every later one with ENOSPC, as a full disk does (the folder's probe, written by
    files.RunFolder.make, goes through: the disk fills during the run)."""
    real, calls = whole_files.write_temporary, []

    def fill_up(path, data):
        if path.endswith("-probe"):
            return real(path, data)
        calls.append(path)
        if len(calls) > writes:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), path)
        return real(path, data)
    monkeypatch.setattr(whole_files, "write_temporary", fill_up)


_RUNS = {}      # a scene's key -> {index: its live.LiveRun after that many steps}


def own_copy(run):
    """A copy of the live.LiveRun `run` sharing nothing with it but its scene: its own x, v, marks
    and StepReport, so that what a test does to it in place never reaches a kept run."""
    return copy.deepcopy(run, {id(run.scene): run.scene})


def chalk_at(index, drag=False, steps=3000, runs=None):
    """A live.LiveRun of the chalk (pushed, or dragged) after `index` steps, marks and all, in a run
    of `steps`: a copy of its own (own_copy) of one stepped once per test session from the nearest
    state kept (a chalk step costs about 5 ms), to put in a window (`window.run = ...`; its scene is
    `run.scene`, the same each call). With `runs` (the chalk_runs fixture) a run far from the
    nearest kept state starts one step before `index` from the session's shared run instead
    (`from_shared`), and takes its last step here, for its StepReport."""
    kept = _RUNS.setdefault(("chalk", drag), {})
    if not kept:
        kept[0] = live.LiveRun(simulator.build_chalk_scene(drag=drag), steps)
    start = None            # a run far from the states kept starts from the shared one's
    if runs is not None and index - 1 > max(i for i in kept if i <= index):
        start = from_shared(kept[0], runs, index - 1, "chalk", **({"drag": True} if drag else {}))
    return stepped_to(kept, index, steps, start)


def square_at(index, steps=1000, runs=None, **overrides):
    """A live.LiveRun of simulator.build_scene(**overrides) after `index` steps in a run of
    `steps`, as chalk_at gives the chalk's: a copy of its own of one stepped once per session;
    with `runs` (the shared_runs fixture) a run far from the nearest kept state starts one step
    before `index` from the session's shared run (`from_shared`)."""
    kept = _RUNS.setdefault(("square", repr(sorted(overrides.items()))), {})
    if not kept:
        kept[0] = live.LiveRun(simulator.build_scene(**overrides), steps)
    start = None
    if runs is not None and index - 1 > max(i for i in kept if i <= index):
        start = from_shared(kept[0], runs, index - 1, "square", **overrides)
    return stepped_to(kept, index, steps, start)


def stepped_to(kept, index, steps, start=None):
    """A copy of its own of the run in `kept` ({index: LiveRun}) stepped on to `index` from `start`
    or else from the nearest state kept, and kept too; in a run of `steps`."""
    run = start if start is not None else own_copy(kept[max(i for i in kept if i <= index)])
    while run.index < index:
        run.step()
    kept[index] = own_copy(run)
    run.steps = steps
    return run


def from_shared(first, runs, index, of, **params):
    """A copy of the LiveRun `first` (at step 0) put at step `index` of the run of BUILDERS[of]
    (**params) kept in `runs` (helpers/runs.py: simulate's states, the same bits as
    LiveRun.step's), the chalk's mark added up over those states as LiveRun adds it; no
    StepReport (its last step was not taken here)."""
    run = own_copy(first)
    _, _, xs, vs = runs.states(index * run.scene.h, of, **params)
    assert len(xs) == index
    for before, after in itertools.pairwise([run.scene.x0, *xs] if run.marks is not None else []):
        run.marks.step(run.scene, before, after)
    run.index, run.x, run.v = index, xs[-1].copy(), vs[-1].copy()
    return run


class DropsTheHandlersRaise:
    """Sends this process `signum` from __del__, where CPython drops an exception (to
    sys.unraisablehook): the handler's Stopped is lost there, as the CI saw in an import's abc
    checks (a real run went on to step 2653 after Ctrl+C)."""

    def __init__(self, signum):
        self.signum = signum

    def __del__(self):
        os.kill(os.getpid(), self.signum)
        nothing()           # a Python call: the handler runs here, inside __del__


def nothing():
    pass


def signal_dropped_at_step(monkeypatch, index, signum=signal.SIGINT):
    """The signal sent, its raise dropped, as step `index` begins."""
    real = time_integrator.step

    def step(scene, x, v, step_index=0, **kw):
        if step_index == index:
            DropsTheHandlersRaise(signum)           # made and deleted at once: __del__ runs
        return real(scene, x, v, step_index=step_index, **kw)
    monkeypatch.setattr(time_integrator, "step", step)
