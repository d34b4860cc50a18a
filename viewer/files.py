"""The output folder: the names a run writes, and which files there this program owns.

A run owns only what it wrote, and the folder's manifest (MANIFEST, a text file) lists those names,
each added before its file is created. `OutputFolder.claim` starts a run: it refuses, before writing
anything, when a name the run is about to write is taken by a file this program did not write or by a
symbolic link (it never writes through one); then it removes its earlier run's files, so no stale
frame stays beside the new ones, and starts a new manifest. Every file is written whole: a picture or
OBJ into a temporary file beside it, then renamed over the name; a log one whole line at a time.
"""
import errno
import os
import re
import stat

import square_mesh
from viewer.log import LineFile

MANIFEST = ".simulator-files"
HEADER = "# written by this simulator's runs: a run into this folder removes or replaces these files and no others"
TEMPORARY = re.compile(r"^\.tmp-.{8}(.+)$")      # square_mesh.write_atomic's temporary file of a name


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


def _regular_file(path):
    try:
        return stat.S_ISREG(os.lstat(path).st_mode)
    except FileNotFoundError:
        return False


def _read_manifest(folder):
    """The names the manifest in `folder` lists (empty without one); ValueError for a file of that name
    this program did not write."""
    path = os.path.join(folder, MANIFEST)
    if not os.path.lexists(path):
        return set()
    try:
        with open(path, "rb") as f:
            lines = f.read().decode().splitlines() if _regular_file(path) else []
    except (OSError, UnicodeDecodeError):
        lines = []
    if not lines or lines[0] != HEADER:
        raise ValueError(f"out folder {folder!r} holds {MANIFEST}, which this simulator did not write; move it "
                         f"away or choose another --out")
    return set(lines[1:])


class OutputFolder:
    """The folder a run writes into, and the files it has written there (see the module's text)."""

    def __init__(self, folder, names, signals):
        self.folder, self.names, self.signals = folder, names, signals
        self.written, self.kept, self.manifest = set(), set(), None

    @classmethod
    def claim(cls, folder, names, signals, keep=False):
        """The folder, made ready for a run that writes `names` (RunNames, or a set); ValueError, before
        anything is written, where it cannot be. `keep`: the earlier runs' files stay (and stay owned),
        replaced only where this run writes the same name (python -m figures writing one figure)."""
        self = cls(folder, names, signals)
        with signals.held():
            created = self._make_folder()
            if not os.access(folder, os.W_OK | os.X_OK):        # e.g. read-only: refused before removing anything
                raise ValueError(f"out folder {folder!r} cannot be written: {os.strerror(errno.EACCES)}")
            owned = _read_manifest(folder)
            entries = os.listdir(folder)
            for name in sorted(entries):
                if name in names and not (name in owned and _regular_file(self.path(name))):
                    what = "a symbolic link" if os.path.islink(self.path(name)) else "not written by this simulator"
                    raise ValueError(f"out folder {folder!r} already holds {name}, {what}: move it away or "
                                     f"choose another --out")
            try:
                for name in entries:
                    temporary = TEMPORARY.match(name)
                    if (name in owned or (temporary and temporary[1] in owned)) and _regular_file(self.path(name)):
                        if keep and not temporary:
                            self.kept.add(name)
                        else:
                            os.remove(self.path(name))
                if os.path.lexists(self.path(MANIFEST)):
                    os.remove(self.path(MANIFEST))
                self.manifest = LineFile(self.path(MANIFEST), "\n".join([HEADER, *sorted(self.kept)]))
            except OSError as err:
                for path in reversed(created):
                    os.rmdir(path)
                raise ValueError(f"out folder {folder!r} cannot be written: creating a file in it failed "
                                 f"({err.strerror or err})") from None
        return self

    def _make_folder(self):
        """Create the folder and its missing parents; the ones created, outermost first."""
        missing, path = [], os.path.abspath(self.folder)
        while not os.path.isdir(path) and path != os.path.dirname(path):
            missing.insert(0, path)
            path = os.path.dirname(path)
        try:
            os.makedirs(self.folder, exist_ok=True)
        except OSError as err:
            raise ValueError(f"out folder {self.folder!r} cannot be created: {err.strerror or err}") from None
        return missing

    def path(self, name):
        return os.path.join(self.folder, name)

    def _own(self, name):
        """Add `name` to the manifest before its file is created; OSError (EEXIST) when a file of that
        name appeared since the claim."""
        if name not in self.names:
            raise ValueError(f"{name} is not one of this run's names")
        if name not in self.written:
            if os.path.lexists(self.path(name)) and name not in self.kept:
                raise OSError(errno.EEXIST, "a file of that name appeared, not written by this run", self.path(name))
            if name not in self.kept:
                self.manifest.append(name)
            self.written.add(name)

    def write(self, name, data):
        """Write the file `name` whole (text or bytes), its signals held until it is."""
        with self.signals.held():
            self._own(name)
            square_mesh.write_atomic(self.path(name), data)

    def open_log(self, name, header):
        """A new LineFile `name`, starting with `header`."""
        with self.signals.held():
            self._own(name)
            return LineFile(self.path(name), header)

    def close(self):
        if self.manifest is not None:
            self.manifest.close()
