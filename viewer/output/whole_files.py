"""Files created new and written whole: O_EXCL never opens an existing name, a link included; a
finished temporary file gets its name by a hard link, which fails where the name is taken."""
import errno
import os
import secrets

NO_FOLLOW = getattr(os, "O_NOFOLLOW", 0)        # not on Windows, where O_EXCL suffices
NEW = os.O_WRONLY | os.O_CREAT | os.O_EXCL | NO_FOLLOW | getattr(os, "O_BINARY", 0)
HAS_OWNERS = hasattr(os, "geteuid")             # POSIX: files have an owner and mode bits
NO_LINKS = (errno.EPERM, errno.ENOTSUP, errno.EXDEV, errno.ENOSYS)    # FAT, some shares


def write_temporary(path, data):
    """Write text or bytes into the new file `path`."""
    with os.fdopen(os.open(path, NEW, 0o666), "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)


def link_new(tmp, path):
    """Give the finished file `tmp` the new name `path`: a hard link, which fails where the name is
    taken; without hard links, the name is reserved (O_EXCL), then replaced."""
    try:
        os.link(tmp, path)
    except FileExistsError:
        raise OSError(errno.EEXIST, "a file of that name appeared, not written by this run",
                      path) from None
    except (OSError, AttributeError) as err:
        if getattr(err, "errno", errno.ENOSYS) not in NO_LINKS:
            raise
        os.close(os.open(path, NEW))
        os.replace(tmp, path)


def write_whole(path, data, replace=False):
    """Write `path` whole: a new temporary file beside it, then linked (link_new) or, `replace`,
    renamed to `path`. An OSError names `path`, never the temporary file."""
    head, name = os.path.split(path)
    tmp = os.path.join(head, f".tmp-{secrets.token_hex(4)}-{name}")
    try:
        write_temporary(tmp, data)
        if replace:
            os.replace(tmp, path)
        else:
            link_new(tmp, path)
    except OSError as err:
        raise OSError(err.errno, err.strerror, path) from err
    finally:
        if os.path.lexists(tmp):
            os.remove(tmp)


class LineFile:
    """A text file created new, then written one whole line at a time: a write that fails part way
    (a full disk, a signal) is cut back to the last whole line."""

    def __init__(self, path, header):
        self.path, self.fd, self.size = path, os.open(path, NEW, 0o666), 0
        try:
            self.append(header)
        except BaseException:           # (a full disk) the file it created: gone again
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
            if isinstance(err, OSError) and not err.filename:
                raise OSError(err.errno, err.strerror, self.path) from err
            raise
        self.size += len(data)

    def close(self):
        os.close(self.fd)
