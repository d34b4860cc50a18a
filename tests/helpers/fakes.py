"""Failures the tests stage on purpose."""
import errno
import os

from viewer import whole_files


def fill_disk_after(monkeypatch, writes):
    """Let `writes` whole-file writes (whole_files.write_temporary: frames, OBJs, pictures) through, then
    fail every later one with ENOSPC, as a full disk does."""
    real, calls = whole_files.write_temporary, []

    def fill_up(path, data):
        calls.append(path)
        if len(calls) > writes:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), path)
        return real(path, data)
    monkeypatch.setattr(whole_files, "write_temporary", fill_up)
