"""Shared test setup: import the flat modules from the project root and the shared helpers from
tests/ (whatever folder a test module is in); pygame draws off-screen; under pytest-xdist
(pytest.ini runs `-n auto`), the tests that share runs kept in their process go to one worker."""
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

# The helpers that keep runs in their process for the whole session, so that every test after the
# first reads them for free: (module, function) -> the xdist group of every test module using it.
KEPT_RUNS = {("helpers.chalk", "run"): "chalk runs", ("helpers.fakes", "chalk_at"): "live chalk"}
SHARED_SCOPES = ("class", "module", "package", "session")


def shared_group(item):
    """The xdist group of a test that shares a run with other tests (None if it shares none): the
    helper's group if its module calls a KEPT_RUNS helper; its module if it takes a fixture of its
    own module set up once per module or session, or if its module keeps a functools.cache. Each
    worker is a process with its own tmp_path_factory: grouping only saves making a run twice."""
    globals_ = vars(item.module).values()
    for value in globals_:
        key = (getattr(value, "__module__", None), getattr(value, "__name__", None))
        if key in KEPT_RUNS:
            return KEPT_RUNS[key]
    defs = item._fixtureinfo.name2fixturedefs.values()      # pytest's record of the fixtures
    own = [d for chain in defs for d in chain if d.func.__module__ == item.module.__name__]
    if any(d.scope in SHARED_SCOPES for d in own) or any(
            callable(value) and hasattr(value, "cache_info") for value in globals_):
        return item.module.__name__
    return None


def pytest_collection_modifyitems(config, items):
    """With --dist loadgroup, the tests of one group run on one worker, in one process; every other
    test goes, one at a time, to whichever worker is free."""
    for item in items:
        group = shared_group(item) if isinstance(item, pytest.Function) else None
        if group is not None:
            item.add_marker(pytest.mark.xdist_group(group))
