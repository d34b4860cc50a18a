"""Shared test setup: import the flat modules from the project root and the shared helpers from
tests/ (whatever folder a test module is in); pygame draws off-screen. pytest.ini runs the tests
on every core (pytest-xdist, -n auto), each test module on one worker (--dist loadfile): a module's
fixtures are made once per module; each worker is a process of its own, with its own
tmp_path_factory; the runs the tests share (tests/helpers/runs.py) are stepped once per session,
for every worker (`shared_runs`)."""
import os
import sys

import pytest

# One BLAS thread, set before numpy loads: the Newton systems are small banded matrices, and a
# second OpenBLAS thread contending for 2 cores with other work made whole runs 10-25x slower.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))                     # helpers
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))    # the project


SLOW = pytest.StashKey()     # the (module, test) pairs marked slow, before -m deselects any


def pytest_itemcollected(item):
    """Each test marked slow, noted as collected, before -m or -k deselect any (the quick suite
    deselects them all)."""
    if item.get_closest_marker("slow"):
        item.config.stash.setdefault(SLOW, set()).add((item.path, item.originalname))


@pytest.hookimpl(trylast=True)          # after -m and -k have deselected
def pytest_collection_modifyitems(config, items):
    """A quick twin (a parameter marked quick_twin, the short form of a test's slow parameter)
    is left out where its slow form runs: the slow form checks the same, harder. Then the modules
    with long physics runs (a test marked slow, run or not) first, the rest as collected: --dist
    loadfile hands each worker whole modules in this order (pytest.ini keeps it with
    --no-loadscope-reorder), so the longest start early and the short ones even out the end."""
    running = {(item.path, item.originalname) for item in items if item.get_closest_marker("slow")}
    twins = [item for item in items if item.get_closest_marker("quick_twin")
             and (item.path, item.originalname) in running]
    if twins:
        config.hook.pytest_deselected(items=twins)
        items[:] = [item for item in items if item not in twins]
    slow_paths = {path for path, _ in config.stash.get(SLOW, set())}
    items.sort(key=lambda item: item.path not in slow_paths)


@pytest.fixture(autouse=True)
def frames_here(request):
    """A run in a test's process writes its frames in that process (frames.FrameWriter), where the
    tests' fakes of a full disk, a race or a signal reach them, and no run pays a second process's
    start-up. Tests marked `frame_process`, and runs as whole processes, write them as a user's
    run does (viewer/command/frame_process.py). Its own MonkeyPatch: the test's `monkeypatch`
    is then made after the test's other fixtures and undone before them (a chdir out of a disk
    before it is unmounted)."""
    with pytest.MonkeyPatch.context() as patch:
        if request.node.get_closest_marker("frame_process") is None:
            from viewer.command import frame_process
            from viewer.pictures import frames
            patch.setattr(frame_process, "frame_writer", frames.FrameWriter)
        yield


@pytest.fixture(scope="session")
def shared_runs(tmp_path_factory):
    """The runs of every scene the tests share (helpers/runs.py), kept in a folder every worker of
    this session shares: under pytest-xdist each worker's temporary folder is in the session's
    (popen-gw0, ...)."""
    from helpers import runs
    folder = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        folder = folder.parent
    (folder / "shared-runs").mkdir(exist_ok=True)
    return runs.Runs(str(folder / "shared-runs"))


@pytest.fixture(scope="session")
def chalk_runs(shared_runs):
    """The shared runs as the chalk's tests read them (Runs.states' scene is the chalk unless
    told)."""
    return shared_runs


@pytest.fixture(scope="module")
def shared_stepping(shared_runs):
    """simulator.simulate and time_integrator.step, for the runs a module's tests start in their
    process (viewer.main.main, the window), as the shared runs keep them where the scene is its
    builder's (Runs.built): simulate's StepRecords (Runs.simulate) and the steps a kept run took
    from the same state (Runs.taken), the same bits but for their wall times, each stepped once for
    every test. For the tests of what a run writes, says and draws, not of how it steps (a signal
    or a failure in a step): `pytestmark = pytest.mark.usefixtures("shared_stepping")`. A Newton
    iteration at a time (the window's n) is stepped as before."""
    import simulator
    import time_integrator
    simulating, stepping = simulator.simulate, time_integrator.step

    def simulate(scene, steps):
        return (shared_runs.simulate if shared_runs.built(scene) else simulating)(scene, steps)

    def step(scene, x, v, *, step_index=0):
        taken = shared_runs.taken(scene, x, v, step_index)
        return stepping(scene, x, v, step_index=step_index) if taken is None else taken
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(simulator, "simulate", simulate)
        patch.setattr(time_integrator, "step", step)
        yield
