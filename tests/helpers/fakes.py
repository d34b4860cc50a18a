"""Failures the tests stage on purpose, and runs fast-forwarded for them."""
import copy
import errno
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


_RUNS = {}      # drag -> {index: the chalk's live.LiveRun after that many steps}


def own_copy(run):
    """A copy of the live.LiveRun `run` sharing nothing with it but its scene: its own x, v, marks
    and StepReport, so that what a test does to it in place never reaches a kept run."""
    return copy.deepcopy(run, {id(run.scene): run.scene})


def chalk_at(index, drag=False, steps=3000):
    """A live.LiveRun of the chalk (pushed, or dragged) after `index` steps, marks and all, in a run
    of `steps`: a copy of its own (own_copy) of one stepped once per test session from the nearest
    state kept (a chalk step costs about 5 ms), to put in a window (`window.run = ...`; its scene is
    `run.scene`, the same each call)."""
    kept = _RUNS.setdefault(drag, {})
    if not kept:
        kept[0] = live.LiveRun(simulator.build_chalk_scene(drag=drag), steps)
    run = own_copy(kept[max(i for i in kept if i <= index)])
    while run.index < index:
        run.step()
    kept[index] = own_copy(run)
    run.steps = steps
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
