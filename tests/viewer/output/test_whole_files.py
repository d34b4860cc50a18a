"""viewer/output/whole_files.py: files written whole."""
import os

import pytest

from viewer.output import whole_files


def test_atomic_write_leaves_old_file_on_failure(tmp_path):
    path = tmp_path / "a.txt"
    whole_files.write_whole(str(path), "old", replace=True)

    class Boom:
        def encode(self):
            raise RuntimeError("boom")
    with pytest.raises((RuntimeError, TypeError)):
        whole_files.write_whole(str(path), Boom(), replace=True)
    assert path.read_text() == "old" and os.listdir(tmp_path) == ["a.txt"]
