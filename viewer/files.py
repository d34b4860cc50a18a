"""The output folder: the names a run writes, and which files there this program owns.

A run (or `python -m figures`) owns its folder while it is on and the files it wrote, and nothing else:
- **One run per folder.** `OutputFolder.claim` first locks the folder (LOCK, held by the operating
  system: fcntl's flock, or msvcrt's byte lock on Windows, so a run killed with kill -9 holds nothing);
  a second run into a held folder is refused, naming the holder's pid.
- **Ownership by identity.** The manifest (MANIFEST, readable and writable by its owner only) records
  for each file a run wrote its device, inode, size and mtime (ns), written before the file's name
  appears. A listed file that no longer matches (a user's new content, a user's file under that name)
  is the user's: the claim refuses it, naming it. A manifest that is not a regular file, is another
  user's, or others may write to, is refused.
- **Create, never replace.** Every file is written into a new temporary file beside it, then linked
  to its name, which fails if the name is taken (`os.link`); only a file this run wrote earlier in
  the same run is replaced. Logs are created with O_EXCL and written one whole line at a time.
- **Refused before claimed.** Names too long for the folder, a folder that cannot be made or written:
  refused before anything is created or removed, and what the claim created is removed again.
Nothing here follows a symbolic link (an O_EXCL create refuses one; an existing file is lstat-ed and
its opened descriptor compared with it where os.O_NOFOLLOW is missing, as on Windows) or blocks on a
FIFO (O_NONBLOCK where the platform has it, then a regular-file check on the descriptor).
"""
import errno
import os
import re
import secrets
import stat
import time

MANIFEST = ".simulator-files"
LOCK = ".simulator-lock"
OWN = (MANIFEST, LOCK)             # the folder's own bookkeeping, never an output
HEADER = "# simulator outputs v2: name, device, inode, size, mtime_ns of each file its runs wrote"
TEMPORARY = re.compile(r"^\.tmp-[0-9a-f]{8}-(.+)$")      # the temporary file of an output's name
TEMPORARY_EXTRA = len(".tmp-12345678-")
NO_FOLLOW = getattr(os, "O_NOFOLLOW", 0)        # not on Windows: there the descriptor is compared instead
NON_BLOCK = getattr(os, "O_NONBLOCK", 0)
BINARY = getattr(os, "O_BINARY", 0)             # Windows: no newline translation
HAS_OWNERS = hasattr(os, "geteuid")             # POSIX: files have an owner and mode bits that mean it


def frame_png(index):
    return f"frame_{index:05d}.png"


def frame_obj(index, tag=""):
    """frame_00012.obj, or frame_00012_mu0.2.obj for one run of a comparison."""
    return f"frame_{index:05d}{'_' + tag if tag else ''}.obj"


def log_csv(tag=""):
    return f"log{'_' + tag if tag else ''}.csv"


class RunNames:
    """The names one run writes: a log per run (`tags`), summary.png and plots.png; with frames, also
    index.html and, for each frame j < n_frames, its PNG and each run's OBJ. n_frames may be huge
    (`--steps 1e308`), so the names are tested, never listed."""

    def __init__(self, tags, n_frames, frames):
        self.tags, self.n_frames, self.frames = list(tags), n_frames, frames
        self.fixed = {log_csv(tag) for tag in self.tags} | {"summary.png", "plots.png"} | set(["index.html"] * frames)

    def __contains__(self, name):
        if name in self.fixed:
            return True
        match = re.fullmatch(r"frame_(\d{5,})(_.+)?\.(png|obj)", name)
        if not (self.frames and match and int(match[1]) < self.n_frames):
            return False
        j = int(match[1])
        return name == frame_png(j) or any(name == frame_obj(j, tag) for tag in self.tags)

    def longest(self):
        """The longest names of each kind (the last frame's are the longest frames')."""
        last = self.n_frames - 1
        return sorted(self.fixed) + ([frame_png(last)] + [frame_obj(last, tag) for tag in self.tags]
                                     if self.frames else [])


def identity(st):
    """What tells the file a run wrote from any other: (device, inode, size, mtime in ns)."""
    return st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns


def _lstat(path):
    try:
        return os.lstat(path)
    except FileNotFoundError:
        return None


def open_existing(path, flags=os.O_RDONLY):
    """A descriptor of the regular file at `path` (None where there is none), opened without following a
    symbolic link or blocking on a FIFO; OSError (ELOOP) for anything but a regular file."""
    before = _lstat(path)
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
    st, at = os.fstat(fd), _lstat(path)
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


def read_manifest(folder):
    """{name: identity} of the files the manifest in `folder` lists (empty without one); ValueError for
    a manifest this program did not write, or that another user could have written."""
    path = os.path.join(folder, MANIFEST)
    refused = (f"out folder {folder!r} holds {MANIFEST}, which this simulator did not write or which another "
               f"user could have written; move it away or choose another --out")
    try:
        fd = open_existing(path)
    except OSError:
        raise ValueError(refused) from None
    if fd is None:
        return {}
    with os.fdopen(fd, "rb") as f:
        ok = _mine(os.fstat(fd))
        try:
            lines = f.read().decode().splitlines()
        except (OSError, UnicodeDecodeError):
            lines = []
    if not ok or not lines or lines[0] != HEADER:
        raise ValueError(refused)
    records = {}
    for line in lines[1:]:
        name, *fields = line.rstrip(" ").split("\t")
        records[name] = tuple(int(v) for v in fields) if len(fields) == 4 and all(
            v.isdigit() for v in fields) else None          # None: listed, never completed
    return records


class Manifest(LineFile):
    """The manifest being written: a line per file, `name<TAB>dev<TAB>ino<TAB>size<TAB>mtime_ns`. A file
    that grows (a log) keeps one line of fixed width, rewritten in place each time it grows."""
    WIDTH = 4 * 21          # four int64s and their tabs

    def __init__(self, path, records):
        super().__init__(path, "\n".join([HEADER] + [self.line(name, ident, False) for name, ident in records.items()]),
                         mode=0o600)
        if hasattr(os, "fchmod"):
            os.fchmod(self.fd, 0o600)       # whatever the umask: this user's alone, and readable by the next run
        self.slots = {}

    @classmethod
    def line(cls, name, ident, slot):
        text = name + "".join(f"\t{v}" for v in ident)
        return text.ljust(len(name) + cls.WIDTH) if slot else text

    def record(self, name, ident, grows=False):
        """Record the file `name`'s identity: a new line, or its slot's line rewritten."""
        if name in self.slots:
            os.lseek(self.fd, self.slots[name], os.SEEK_SET)
            os.write(self.fd, self.line(name, ident, True).encode())
            os.lseek(self.fd, self.size, os.SEEK_SET)
            return
        if grows:
            self.slots[name] = self.size
        self.append(self.line(name, ident, grows))


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
                    raise ValueError(f"out folder {folder!r} is in use by another run (pid {self._holder()}): "
                                     f"wait until it ends or choose another --out")
            except BaseException:
                os.close(self.fd)
                raise
            at = _lstat(self.path)
            if at is not None and _dev_ino(at) == _dev_ino(os.fstat(self.fd)):
                break
            os.close(self.fd)               # its holder removed it as we took it: again
        else:
            raise ValueError(f"out folder {folder!r}: its lock keeps changing hands; choose another --out")
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
            fd = open_existing(self.path, os.O_RDWR)
            new = fd is None
            if new:
                fd = create_new(self.path, 0o600)
        except FileExistsError:
            return self._open(folder)
        except OSError as err:
            raise ValueError(f"out folder {folder!r} holds {LOCK}, not a lock file of this simulator "
                             f"({err.strerror}): move it away or choose another --out") from None
        if not _mine(os.fstat(fd)):
            os.close(fd)
            raise ValueError(f"out folder {folder!r} holds {LOCK}, another user's: choose another --out")
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


def check_names(folder, names):
    """ValueError, before anything is created, when `folder` or an output name (with its temporary
    file's prefix) is longer than the file system allows."""
    top = os.path.abspath(folder)
    existing = top
    while not os.path.isdir(existing) and existing != os.path.dirname(existing):
        existing = os.path.dirname(existing)
    name_max, path_max = 255, 4096
    if hasattr(os, "pathconf"):
        try:
            name_max = os.pathconf(existing, "PC_NAME_MAX")
            path_max = os.pathconf(existing, "PC_PATH_MAX")
        except (OSError, ValueError):
            pass
    for part in os.path.relpath(top, existing).split(os.sep):
        if len(os.fsencode(part)) > name_max:
            raise ValueError(f"out folder {folder!r} has a name longer than the {name_max} bytes its file "
                             f"system allows: {part[:40]}...")
    for name in names:
        size = len(os.fsencode(name)) + TEMPORARY_EXTRA
        if size > name_max:
            raise ValueError(f"output name {name!r} is too long: {size - TEMPORARY_EXTRA} bytes, the folder "
                             f"allows {name_max - TEMPORARY_EXTRA} (shorten the list value it is named after)")
        if len(os.fsencode(os.path.join(top, name))) + TEMPORARY_EXTRA >= path_max:
            raise ValueError(f"out folder {folder!r} is too deep: its files' paths would be longer than "
                             f"the {path_max} bytes the file system allows")


class OutputFolder:
    """The folder a run writes into, and the files it has written there (see the module's text)."""

    def __init__(self, folder, names, signals):
        self.folder, self.names, self.signals = folder, names, signals
        self.written, self.kept = {}, {}        # name: identity, this run's and (keep) earlier runs'
        self.growing = set()                    # this run's logs
        self.manifest = self.lock = None

    @classmethod
    def claim(cls, folder, names, signals, keep=False):
        """The folder, locked and made ready for a run that writes `names` (RunNames, or a set);
        ValueError, before anything is written or removed, where it cannot be. `keep`: the earlier
        runs' files stay (and stay owned), replaced only where this run writes the same name (python
        -m figures writing one figure); otherwise they are removed."""
        self = cls(folder, names, signals)
        with signals.held():
            check_names(folder, names.longest() if isinstance(names, RunNames) else sorted(names))
            created = self._make_folder()
            try:
                self._claim(keep)
            except BaseException:
                if self.lock is not None:
                    self.lock.close()
                for path in reversed(created):
                    os.rmdir(path)
                raise
        return self

    def _claim(self, keep):
        folder = self.folder
        if not os.access(folder, os.W_OK | os.X_OK):        # e.g. read-only: refused before removing anything
            raise ValueError(f"out folder {folder!r} cannot be written: {os.strerror(errno.EACCES)}")
        try:
            self.lock = Lock(folder)
        except OSError as err:
            raise ValueError(f"out folder {folder!r} cannot be written: creating a file in it failed "
                             f"({err.strerror or err})") from None
        owned = read_manifest(folder)
        entries = sorted(set(os.listdir(folder)) - set(OWN))
        mine = {name for name in entries if self._is_owned(name, owned.get(name))}
        for name in entries:
            if name in self.names and name not in mine:
                at = self.path(name)
                what = ("a symbolic link" if os.path.islink(at) else "changed since this simulator wrote it"
                        if name in owned else "not written by this simulator")
                raise ValueError(f"out folder {folder!r} already holds {name}, {what}: move it away or "
                                 f"choose another --out")
            if name in owned and name not in mine and not keep and owned[name] is not None:
                raise ValueError(f"out folder {folder!r} holds {name}, changed since this simulator wrote it: "
                                 f"move it away or choose another --out")
        try:
            for name in entries:
                temporary = TEMPORARY.match(name)
                if temporary and (temporary[1] in owned or temporary[1] in OWN) and self._is_temporary(name):
                    os.remove(self.path(name))
                elif name in mine and keep:
                    self.kept[name] = owned[name]
                elif name in mine:
                    os.remove(self.path(name))
            self.manifest = self._new_manifest()
        except OSError as err:
            raise ValueError(f"out folder {folder!r} cannot be written: creating a file in it failed "
                             f"({err.strerror or err})") from None

    def _is_owned(self, name, ident):
        st = _lstat(self.path(name))
        return ident is not None and st is not None and stat.S_ISREG(st.st_mode) and identity(st) == ident

    def _is_temporary(self, name):
        st = _lstat(self.path(name))
        return st is not None and stat.S_ISREG(st.st_mode) and _mine(st)

    def _new_manifest(self):
        """The new manifest, listing the kept files: written whole beside the old one, then moved over
        it (the old one was checked to be this program's)."""
        path, tmp = self.path(MANIFEST), self.path(f".tmp-{secrets.token_hex(4)}-{MANIFEST}")
        manifest = Manifest(tmp, self.kept)
        try:
            os.replace(tmp, path)
        except BaseException:
            manifest.close()
            os.remove(tmp)
            raise
        manifest.path = path
        return manifest

    def _make_folder(self):
        """Create the folder and its missing parents; the ones created, outermost first (none on
        failure: what was made is removed again)."""
        missing, path = [], os.path.abspath(self.folder)
        while not os.path.isdir(path) and path != os.path.dirname(path):
            missing.insert(0, path)
            path = os.path.dirname(path)
        made = []
        try:
            for path in missing:
                os.mkdir(path)
                made.append(path)
        except OSError as err:
            for path in reversed(made):
                os.rmdir(path)
            raise ValueError(f"out folder {self.folder!r} cannot be created: {err.strerror or err}") from None
        return made

    def path(self, name):
        return os.path.join(self.folder, name)

    def _check(self, name):
        if name not in self.names:
            raise ValueError(f"{name} is not one of this run's names")
        st = _lstat(self.path(MANIFEST))
        if st is None:          # removed during the run: written again, whole, from what this run knows
            self.manifest.close()
            self.manifest = self._new_manifest()
            for written, ident in self.written.items():
                self.manifest.record(written, ident, grows=written in self.growing)
        elif _dev_ino(st) != _dev_ino(os.fstat(self.manifest.fd)):
            raise OSError(errno.EEXIST, "the run's manifest was replaced by another file", self.path(MANIFEST))

    def write(self, name, data):
        """Write the file `name` whole (text or bytes), its signals held until it is: into a new
        temporary file, recorded in the manifest, then linked to its name (never over another file)."""
        with self.signals.held():
            self._check(name)
            path = self.path(name)
            tmp = self.path(f".tmp-{secrets.token_hex(4)}-{name}")
            try:
                try:
                    ident = write_temporary(tmp, data)
                    self.manifest.record(name, ident)
                    self._put(tmp, path, name)
                finally:
                    if os.path.lexists(tmp):
                        os.remove(tmp)
            except OSError as err:        # name the output, never the temporary file
                raise OSError(err.errno, err.strerror, path) from err
            self.written[name] = ident

    def _put(self, tmp, path, name):
        """Give the finished temporary file its name: linked, so it fails if the name is taken; replaced
        only over this run's own file (or, with keep, an earlier run's, which it removes first)."""
        earlier = self.written.get(name, self.kept.pop(name, None))
        if earlier is not None:
            if not self._is_owned(name, earlier):
                raise OSError(errno.EEXIST, "changed since this simulator wrote it", path)
            if name in self.written:
                os.replace(tmp, path)
                return
            os.remove(path)
        try:
            os.link(tmp, path)
        except FileExistsError:
            raise OSError(errno.EEXIST, "a file of that name appeared, not written by this run", path) from None
        except (OSError, AttributeError) as err:         # no hard links here (FAT, some shares): reserve, then replace
            if isinstance(err, OSError) and err.errno not in (errno.EPERM, errno.ENOTSUP, errno.EXDEV, errno.ENOSYS):
                raise
            os.close(create_new(path))
            os.replace(tmp, path)

    def open_log(self, name, header):
        """A new LineFile `name`, starting with `header`, its identity kept in the manifest as it grows."""
        with self.signals.held():
            self._check(name)
            self.manifest.record(name, (), grows=True)      # listed before it exists, its identity to come
            self.growing.add(name)
            log = LineFile(self.path(name), header, after=lambda ident: self._grew(name, ident))
            return log

    def _grew(self, name, ident):
        self.written[name] = ident
        self.manifest.record(name, ident)

    def close(self):
        if self.manifest is not None:
            self.manifest.close()
        if self.lock is not None:
            self.lock.close()


def _dev_ino(st):
    return st.st_dev, st.st_ino
