"""Failures the tests stage on purpose."""
import errno
import os

import square_mesh


def fill_disk_after(monkeypatch, writes):
    """Let `writes` whole-file writes (square_mesh.write_atomic: frames, OBJs, pictures) through, then
    fail every later one with ENOSPC, as a full disk does."""
    real, calls = square_mesh.write_atomic, []

    def fill_up(path, data):
        calls.append(path)
        if len(calls) > writes:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), path)
        real(path, data)
    monkeypatch.setattr(square_mesh, "write_atomic", fill_up)
