"""Files created new and written whole, never through a symbolic link, never blocking on a FIFO.

A new file is created with O_EXCL, which never opens an existing name, a symbolic link included
(POSIX and Windows alike), and its descriptor is compared with an lstat of the name; an existing
file is lstat-ed first, opened with O_NONBLOCK (where the platform has it) and its descriptor compared
with that, so a FIFO or a link swapped in is refused, never followed or waited on. Where O_NOFOLLOW
is missing (Windows) these comparisons keep the promise. A file's identity is (device, inode, size,
mtime in ns): what tells the file a run wrote from any other.
"""
import errno
import os
import secrets
import stat

NO_FOLLOW = getattr(os, "O_NOFOLLOW", 0)        # not on Windows: there the descriptor is compared instead
NON_BLOCK = getattr(os, "O_NONBLOCK", 0)
BINARY = getattr(os, "O_BINARY", 0)             # Windows: no newline translation
HAS_OWNERS = hasattr(os, "geteuid")             # POSIX: files have an owner and mode bits that mean it


def identity(st):
    """What tells the file a run wrote from any other: (device, inode, size, mtime in ns)."""
    return st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns


def lstat(path):
    try:
        return os.lstat(path)
    except FileNotFoundError:
        return None


def open_existing(path, flags=os.O_RDONLY):
    """A descriptor of the regular file at `path` (None where there is none), opened without following a
    symbolic link or blocking on a FIFO; OSError (ELOOP) for anything but a regular file."""
    before = lstat(path)
    if before is None:
        return None
    if not stat.S_ISREG(before.st_mode):
        raise OSError(errno.ELOOP if stat.S_ISLNK(before.st_mode) else errno.EINVAL, "not a regular file", path)
    fd = os.open(path, flags | NO_FOLLOW | NON_BLOCK | BINARY)
    st = os.fstat(fd)
    if not stat.S_ISREG(st.st_mode) or (st.st_dev, st.st_ino) != (before.st_dev, before.st_ino):
        os.close(fd)            # swapped for something else between the two looks
        raise OSError(errno.EINVAL, "not a regular file", path)
    return fd


def create_new(path, mode=0o666):
    """A descriptor of a new file at `path`: O_EXCL never opens an existing name, a symbolic link
    included (POSIX and Windows alike); the new file is checked to be the one at `path`."""
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | NO_FOLLOW | BINARY, mode)
    st, at = os.fstat(fd), lstat(path)
    if at is None or (st.st_dev, st.st_ino) != (at.st_dev, at.st_ino):
        os.close(fd)
        raise OSError(errno.EEXIST, "a file of that name appeared", path)
    return fd


class LineFile:
    """A text file created new (O_EXCL: never over another file, never through a symbolic link), then
    written one whole line at a time, each at once: a write that fails part way (a full disk, a signal)
    is cut back to the last whole line. `after(identity)` is told the file's (device, inode, size,
    mtime_ns) after each line (OutputFolder keeps it in the manifest)."""

    def __init__(self, path, header, mode=0o666, after=None):
        self.path, self.after = path, after
        self.fd = create_new(path, mode)
        self.size = 0
        try:
            self.append(header)
        except BaseException:           # (a full disk) the file it created, empty: gone again
            self.close()
            os.remove(path)
            raise

    def append(self, line):
        data = (line + "\n").encode()
        try:
            written = 0
            while written < len(data):
                written += os.write(self.fd, data[written:])
        except BaseException as err:
            os.ftruncate(self.fd, self.size)
            if isinstance(err, OSError) and not err.filename:       # a failed write names no file: this one
                raise OSError(err.errno, err.strerror, self.path) from err
            raise
        self.size += len(data)
        if self.after is not None:
            self.after(identity(os.fstat(self.fd)))

    def close(self):
        os.close(self.fd)


def write_temporary(path, data):
    """Write text or bytes into the new file `path` (create_new); its identity once whole."""
    with os.fdopen(create_new(path), "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)
        f.flush()
        return identity(os.fstat(f.fileno()))


def write_atomic(path, data):
    """Write text or bytes to `path` whole, over what is there: into a temporary file beside it, then
    renamed over it (a benchmark's own table; a run's outputs go through OutputFolder.write)."""
    tmp = os.path.join(os.path.dirname(os.path.abspath(path)), f".tmp-{secrets.token_hex(4)}-{os.path.basename(path)}")
    try:
        write_temporary(tmp, data)
        os.replace(tmp, path)
    finally:
        if os.path.lexists(tmp):
            os.remove(tmp)


def _mine(st):
    """Whether the file of `st` is this user's and nobody else may write to it (POSIX; True elsewhere)."""
    return not HAS_OWNERS or (st.st_uid == os.geteuid() and not st.st_mode & (stat.S_IWGRP | stat.S_IWOTH))


def dev_ino(st):
    """(device, inode): which file a stat result is of."""
    return st.st_dev, st.st_ino


def mine(st):
    """Whether the file of `st` is this user's and nobody else may write to it (POSIX; True elsewhere)."""
    return not HAS_OWNERS or (st.st_uid == os.geteuid() and not st.st_mode & (stat.S_IWGRP | stat.S_IWOTH))
