"""The output folder: the names a run writes, and which files there this program owns.

A run (or `python -m figures`) owns its folder while it is on and the files it wrote, and nothing else:
- **One run per folder.** `OutputFolder.claim` first locks the folder (viewer.folder_lock); a second
  run into a held folder is refused, naming the holder's pid.
- **Ownership by identity.** The manifest (viewer.manifest) records for each file a run wrote its
  device, inode, size and mtime (ns), before the file's name appears. A listed file that no longer
  matches (a user's new content, a user's file under that name) is the user's: the claim refuses it,
  naming it. A manifest that is not a regular file, is another user's, or others may write to, is
  refused.
- **Create, never replace.** Every file is written into a new temporary file beside it, then linked
  to its name, which fails if the name is taken (`os.link`); only a file this run wrote earlier in
  the same run is replaced. Logs are created with O_EXCL and written one whole line at a time.
- **Refused before claimed.** Names too long for the folder, a folder that cannot be made or written:
  refused before anything is created or removed, and what the claim created is removed again.
Nothing here follows a symbolic link or blocks on a FIFO (viewer.whole_files).
"""
import errno
import os
import re
import secrets
import stat

import utils
from viewer import folder_lock, manifest, whole_files
from viewer.folder_lock import LOCK
from viewer.manifest import MANIFEST

OWN = (MANIFEST, LOCK)             # the folder's own bookkeeping, never an output
TEMPORARY = re.compile(r"^\.tmp-[0-9a-f]{8}-(.+)$")      # the temporary file of an output's name
TEMPORARY_EXTRA = len(".tmp-12345678-")


def frame_png(index):
    return f"frame_{index:05d}.png"


def frame_obj(index, tag=""):
    """frame_00012.obj, or frame_00012_mu0.2.obj for one run of a comparison."""
    return f"frame_{index:05d}{'_' + tag if tag else ''}.obj"


def log_csv(tag=""):
    return f"log{'_' + tag if tag else ''}.csv"


def marks_csv(tag=""):
    """The chalk's mark (viewer.marks.csv_text): marks.csv, or marks_grip1000.csv for one run of a
    comparison."""
    return f"marks{'_' + tag if tag else ''}.csv"


class RunNames:
    """The names one run writes: a log per run (`tags`), summary.png and plots.png, with `marks`
    (the chalk) a marks.csv per run; with frames, also index.html and, for each frame j < n_frames,
    its PNG and each run's OBJ. n_frames may be huge (`--steps 1e308`), so the names are tested,
    never listed."""

    def __init__(self, tags, n_frames, frames, marks=False):
        self.tags, self.n_frames, self.frames = list(tags), n_frames, frames
        self.fixed = {log_csv(tag) for tag in self.tags} | {"summary.png", "plots.png"} | set(["index.html"] * frames)
        self.fixed |= {marks_csv(tag) for tag in self.tags} if marks else set()

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
            raise utils.ParameterError("out", f"out folder {folder!r} has a name longer than the {name_max} bytes its file "
                             f"system allows: {part[:40]}...")
    for name in names:
        size = len(os.fsencode(name)) + TEMPORARY_EXTRA
        if size > name_max:
            raise utils.ParameterError("out", f"output name {name!r} is too long: {size - TEMPORARY_EXTRA} bytes, the folder "
                             f"allows {name_max - TEMPORARY_EXTRA} (shorten the list value it is named after)")
        if len(os.fsencode(os.path.join(top, name))) + TEMPORARY_EXTRA >= path_max:
            raise utils.ParameterError("out", f"out folder {folder!r} is too deep: its files' paths would be longer than "
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
            raise utils.ParameterError("out", f"out folder {folder!r} cannot be written: {os.strerror(errno.EACCES)}")
        try:
            self.lock = folder_lock.Lock(folder)
        except OSError as err:
            raise utils.ParameterError("out", f"out folder {folder!r} cannot be written: creating a file in it failed "
                             f"({err.strerror or err})") from None
        owned = manifest.read_manifest(folder)
        entries = sorted(set(os.listdir(folder)) - set(OWN))
        mine = {name for name in entries if self._is_owned(name, owned.get(name))}
        for name in entries:
            if name in self.names and name not in mine:
                at = self.path(name)
                what = ("a symbolic link" if os.path.islink(at) else "changed since this simulator wrote it"
                        if name in owned else "not written by this simulator")
                raise utils.ParameterError("out", f"out folder {folder!r} already holds {name}, {what}: move it away or "
                                 f"choose another --out")
            if name in owned and name not in mine and not keep and owned[name] is not None:
                raise utils.ParameterError("out", f"out folder {folder!r} holds {name}, changed since this simulator wrote it: "
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
            raise utils.ParameterError("out", f"out folder {folder!r} cannot be written: creating a file in it failed "
                             f"({err.strerror or err})") from None

    def _is_owned(self, name, ident):
        st = whole_files.lstat(self.path(name))
        return (ident is not None and st is not None and stat.S_ISREG(st.st_mode)
                and whole_files.identity(st) == ident)

    def _is_temporary(self, name):
        st = whole_files.lstat(self.path(name))
        return st is not None and stat.S_ISREG(st.st_mode) and whole_files.mine(st)

    def _new_manifest(self):
        """The new manifest, listing the kept files: written whole beside the old one, then moved over
        it (the old one was checked to be this program's)."""
        path, tmp = self.path(MANIFEST), self.path(f".tmp-{secrets.token_hex(4)}-{MANIFEST}")
        new = manifest.Manifest(tmp, self.kept)
        try:
            os.replace(tmp, path)
        except BaseException:
            new.close()
            os.remove(tmp)
            raise
        new.path = path
        return new

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
            raise utils.ParameterError("out", f"out folder {self.folder!r} cannot be created: {err.strerror or err}") from None
        return made

    def path(self, name):
        return os.path.join(self.folder, name)

    def _check(self, name):
        if name not in self.names:
            raise ValueError(f"{name} is not one of this run's names")
        st = whole_files.lstat(self.path(MANIFEST))
        if st is None:          # removed during the run: written again, whole, from what this run knows
            self.manifest.close()
            self.manifest = self._new_manifest()
            for written, ident in self.written.items():
                self.manifest.record(written, ident, grows=written in self.growing)
        elif whole_files.dev_ino(st) != whole_files.dev_ino(os.fstat(self.manifest.fd)):
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
                    ident = whole_files.write_temporary(tmp, data)
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
        earlier = self.written[name] if name in self.written else self.kept.pop(name, None)
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
            os.close(whole_files.create_new(path))
            os.replace(tmp, path)

    def open_log(self, name, header):
        """A new LineFile `name`, starting with `header`, its identity kept in the manifest as it grows."""
        with self.signals.held():
            self._check(name)
            self.manifest.record(name, (), grows=True)      # listed before it exists, its identity to come
            self.growing.add(name)
            log = whole_files.LineFile(self.path(name), header, after=lambda ident: self._grew(name, ident))
            return log

    def _grew(self, name, ident):
        self.written[name] = ident
        self.manifest.record(name, ident)

    def close(self):
        if self.manifest is not None:
            self.manifest.close()
        if self.lock is not None:
            self.lock.close()
