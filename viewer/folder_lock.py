"""The output folder's lock: one run (or `python -m figures`) per folder at a time.

The file LOCK holds its run's pid and start time and is locked by the operating system (fcntl's
flock; msvcrt's byte lock on Windows), which lets go when the process ends however it ends: a run
killed with kill -9 holds nothing, and the next run takes the folder over. Where the platform has no
such lock, the file itself is the lock, taken over once its pid no longer runs.
"""
import errno
import os
import time

import utils
from viewer import whole_files

LOCK = ".simulator-lock"


class Lock:
    """The folder's lock, held from the claim to close(): the file LOCK, holding its run's pid and start
    time, locked by the operating system (fcntl's flock; msvcrt's byte lock on Windows), which lets go
    when the process ends however it ends: a run killed with kill -9 holds nothing. The holder removes
    the file as it lets go; a run that locked a file since removed tries again. Where no such lock
    exists, the file itself is the lock, taken over when its pid no longer runs."""

    def __init__(self, folder):
        self.path = os.path.join(folder, LOCK)
        for attempt in range(10):
            new, self.fd = self._open(folder)
            try:
                held = lock(self.fd)
                if held is None:            # no lock of the operating system's: the file's existence is one
                    held = new or not _running(self._holder())
                    if not new and held:    # its run is gone: taken over
                        os.remove(self.path)
                        os.close(self.fd)
                        continue
                if not held:
                    raise utils.ParameterError("out", f"out folder {folder!r} is in use by another run (pid {self._holder()}): "
                                     f"wait until it ends or choose another --out")
            except BaseException:
                os.close(self.fd)
                raise
            at = whole_files.lstat(self.path)
            if at is not None and whole_files.dev_ino(at) == whole_files.dev_ino(os.fstat(self.fd)):
                break
            os.close(self.fd)               # its holder removed it as we took it: again
        else:
            raise utils.ParameterError("out", f"out folder {folder!r}: its lock keeps changing hands; choose another --out")
        try:
            os.ftruncate(self.fd, 0)
            os.lseek(self.fd, 0, os.SEEK_SET)
            os.write(self.fd, f"{os.getpid()} {time.strftime('%Y-%m-%dT%H:%M:%S')}\n".encode())
        except BaseException:           # a full disk: let go again
            self.close()
            raise

    def _open(self, folder):
        """(whether it is new, a descriptor of the lock file, read-write)."""
        try:
            fd = whole_files.open_existing(self.path, os.O_RDWR)
            new = fd is None
            if new:
                fd = whole_files.create_new(self.path, 0o600)
        except FileExistsError:
            return self._open(folder)
        except OSError as err:
            raise utils.ParameterError("out", f"out folder {folder!r} holds {LOCK}, not a lock file of this simulator "
                             f"({err.strerror}): move it away or choose another --out") from None
        if not whole_files.mine(os.fstat(fd)):
            os.close(fd)
            raise utils.ParameterError("out", f"out folder {folder!r} holds {LOCK}, another user's: choose another --out")
        return new, fd

    def _holder(self):
        """The pid the lock file names ('unknown' before its run has written it)."""
        os.lseek(self.fd, 0, os.SEEK_SET)
        words = os.read(self.fd, 64).decode(errors="replace").split()
        return words[0] if words and words[0].isdigit() else "unknown"

    def close(self):
        """Let go: the file removed first, so that a run that opened it meanwhile sees it changed."""
        try:
            os.remove(self.path)
        except OSError:
            pass
        os.close(self.fd)


def _running(pid):
    """Whether the process `pid` (a string from a lock file) still runs; True where that is unknown."""
    if not pid.isdigit():
        return True
    try:
        os.kill(int(pid), 0)
    except ProcessLookupError:
        return False
    except (OSError, ValueError, OverflowError):
        return True
    return True


def lock(fd):
    """Lock the open file `fd` for this process without waiting: True, or False where another holds it;
    None where the platform has no such lock. flock where fcntl exists; on Windows, msvcrt's lock of one
    byte past the text (so others may still read the pid)."""
    try:
        import fcntl
    except ImportError:
        fcntl = None
    if fcntl is not None:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return True
        except OSError as err:
            if err.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                return False
            raise
    try:
        import msvcrt
    except ImportError:
        return None
    os.lseek(fd, 1 << 20, os.SEEK_SET)
    try:
        msvcrt.locking(fd, msvcrt.LK_NBLCK, 1)
        return True
    except OSError:
        return False
