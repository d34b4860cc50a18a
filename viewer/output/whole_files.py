"""Files created new and written whole, never through a symbolic link.

A new file is created with O_EXCL, which never opens an existing name, a symbolic link included
(POSIX and Windows alike), and its descriptor is compared with an lstat of the name. A finished
temporary file gets its name by a hard link, which fails where the name is taken.
"""
import errno
import os
import secrets

NO_FOLLOW = getattr(os, "O_NOFOLLOW", 0)        # not on Windows: there the descriptor is compared
BINARY = getattr(os, "O_BINARY", 0)             # Windows: no newline translation
HAS_OWNERS = hasattr(os, "geteuid")             # POSIX: files have an owner and mode bits


def create_new(path, mode=0o666):
    """A descriptor of a new file at `path`: O_EXCL never opens an existing name, a symbolic link
    included (POSIX and Windows alike); the new file is checked to be the one at `path`."""
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | NO_FOLLOW | BINARY, mode)
    st = os.fstat(fd)
    try:
        at = os.lstat(path)
    except FileNotFoundError:
        at = None
    if at is None or (st.st_dev, st.st_ino) != (at.st_dev, at.st_ino):
        os.close(fd)
        raise OSError(errno.EEXIST, "a file of that name appeared", path)
    return fd


def link_new(tmp, path):
    """Give the finished file `tmp` the new name `path`: a hard link, which fails where the name is
    taken; where the file system has none (FAT, some shares), the name is reserved, then replaced.
    """
    try:
        os.link(tmp, path)
    except FileExistsError:
        raise OSError(errno.EEXIST, "a file of that name appeared, not written by this run",
                      path) from None
    except (OSError, AttributeError) as err:
        if isinstance(err, OSError) and err.errno not in (errno.EPERM, errno.ENOTSUP, errno.EXDEV,
                                                          errno.ENOSYS):
            raise
        os.close(create_new(path))
        os.replace(tmp, path)


class LineFile:
    """A text file created new (O_EXCL: never over another file, never through a symbolic link),
    then written one whole line at a time, each at once: a write that fails part way (a full disk, a
    signal) is cut back to the last whole line."""

    def __init__(self, path, header, mode=0o666):
        self.path = path
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
            if isinstance(err, OSError) and not err.filename:   # a failed write names no file
                raise OSError(err.errno, err.strerror, self.path) from err
            raise
        self.size += len(data)

    def close(self):
        os.close(self.fd)


def write_temporary(path, data):
    """Write text or bytes into the new file `path` (create_new), whole."""
    with os.fdopen(create_new(path), "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)
        f.flush()


def write_atomic(path, data):
    """Write text or bytes to `path` whole, over what is there: into a temporary file beside it,
    then renamed over it (a benchmark's own table; a run's outputs go through
    files.RunFolder.write)."""
    tmp = os.path.join(os.path.dirname(os.path.abspath(path)),
                       f".tmp-{secrets.token_hex(4)}-{os.path.basename(path)}")
    try:
        write_temporary(tmp, data)
        os.replace(tmp, path)
    finally:
        if os.path.lexists(tmp):
            os.remove(tmp)
