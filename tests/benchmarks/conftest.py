"""The benchmarks' runs write into the test's tmp_path, not the checkout's output/."""
import pytest

from benchmarks import tables


@pytest.fixture(autouse=True)
def scratch_in_tmp_path(tmp_path, monkeypatch):
    """tables.SCRATCH (where `tables.scratch` folders go) in tmp_path/output."""
    monkeypatch.setattr(tables, "SCRATCH", str(tmp_path / "output"))
