"""A run's folder: a new one the run made itself, and every file in it created new and written
whole.

- **The folder.** `RunFolder.make`: by default `output/<kind>-<date>-<time>/`, with `-2`, `-3`, ...
  where that name is taken (`os.mkdir` is atomic: two runs started in the same second get two
  folders); or the folder `--out` names, made with its missing parents, or one that exists and is
  empty. Anything else (a folder that holds files, a file, another user's folder or one others may
  write to) is refused with a ValueError naming --out, before anything is made.
- **Its files.** Each is written into a new temporary file beside its name (O_EXCL), then linked to
  that name, which fails if the name is taken: never over another file, never through a link. A log
  is created new and written one whole line at a time (whole_files.LineFile).
Nothing outside the folder is written, replaced or deleted, so a run needs no lock and no record of
what it wrote: nothing in its folder can be anyone else's. Ctrl+C and SIGTERM wait while a file is
written (`signals.held()`), so every file is whole and no temporary is left.
"""
import datetime
import errno
import os
import pathlib
import secrets
import stat

import utils
from viewer.output import whole_files

OUTPUT = "output"       # where a run's folder is made without --out
TEMPORARY_EXTRA = len(".tmp-12345678-")


def refused(text):
    """The ValueError that refuses a run's folder, naming --out (utils.ParameterError)."""
    return utils.ParameterError("out", text)


def frame_png(index):
    return f"frame_{index:05d}.png"


def frame_obj(index, tag=""):
    """frame_00012.obj, or frame_00012_mu0.2.obj for one run of a comparison."""
    return f"frame_{index:05d}{'_' + tag if tag else ''}.obj"


def log_csv(tag=""):
    return f"log{'_' + tag if tag else ''}.csv"


def marks_csv(tag=""):
    """The chalk's mark (analysis.wear.csv_text): marks.csv, or marks_grip1000.csv for one run of a
    comparison."""
    return f"marks{'_' + tag if tag else ''}.csv"


def run_names(tags, n_frames, frames, marks=False):
    """The longest names of each kind a run writes (a log per run, summary.png, plots.png; with
    `marks`, the chalk's, a marks.csv per run; with frames index.html and the last frame's PNG and
    OBJs): what `check_names` measures. n_frames may be huge (`--steps 1e308`), so the names are
    never listed."""
    fixed = [log_csv(tag) for tag in tags] + ["summary.png", "plots.png"] + ["index.html"] * frames
    fixed += [marks_csv(tag) for tag in tags] if marks else []
    return fixed + ([frame_png(n_frames - 1)] + [frame_obj(n_frames - 1, tag) for tag in tags]
                    if frames else [])


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
            raise refused(f"out folder {folder!r} has a name longer than the "
                          f"{name_max} bytes its file system allows: {part[:40]}...")
    for name in names:
        size = len(os.fsencode(name)) + TEMPORARY_EXTRA
        if size > name_max:
            raise refused(f"output name {name!r} is too long: "
                          f"{size - TEMPORARY_EXTRA} bytes, the folder allows "
                          f"{name_max - TEMPORARY_EXTRA} (shorten the list value "
                          f"it is named after)")
        if len(os.fsencode(os.path.join(top, name))) + TEMPORARY_EXTRA >= path_max:
            raise refused(f"out folder {folder!r} is too deep: its files' paths "
                          f"would be longer than the {path_max} bytes the file "
                          f"system allows")


def make_folders(path):
    """Create the folder `path` and its missing parents, and return those made, outermost first;
    FileExistsError where `path` exists. What was made is removed again when a later part fails
    (then a ValueError naming --out)."""
    missing, at = [], os.path.abspath(path)
    while not os.path.lexists(at) and at != os.path.dirname(at):
        missing.insert(0, at)
        at = os.path.dirname(at)
    if not missing:
        raise FileExistsError(errno.EEXIST, "exists", path)
    made = []
    try:
        for at in missing:
            os.mkdir(at)
            made.append(at)
    except OSError as err:
        for at in reversed(made):
            os.rmdir(at)
        if isinstance(err, FileExistsError) and len(made) == len(missing) - 1:
            raise                           # made meanwhile (another run): the caller decides
        raise refused(f"out folder {path!r} cannot be created: "
                      f"{err.strerror or err}") from None
    return made


def check_writable(path, made):
    """ValueError naming --out where a file cannot be written in the folder `path` (a full disk, a
    read-only one): a probe written and removed; the folders `made` for the run are removed again.
    """
    probe = os.path.join(path, f".tmp-{secrets.token_hex(4)}-probe")
    try:
        whole_files.write_temporary(probe, "a probe: can a file be written here?\n")
        os.remove(probe)
    except OSError as err:
        if os.path.lexists(probe):
            os.remove(probe)
        for at in reversed(made):
            os.rmdir(at)
        raise refused(f"out folder {path!r} cannot be written: "
                      f"{err.strerror or err}") from None


def check_empty(path):
    """ValueError naming --out unless the existing `path` is an empty folder of this user's in which
    nobody else may remove or replace files (POSIX: not writable by others, or sticky as /tmp)."""
    if not os.path.isdir(path):
        raise refused(f"out folder {path!r} is not a folder: choose a new one")
    st = os.stat(path)
    shared = st.st_mode & stat.S_IWOTH and not st.st_mode & stat.S_ISVTX  # others may remove files
    if whole_files.HAS_OWNERS and (st.st_uid != os.geteuid() or shared):
        raise refused(f"out folder {path!r} is another user's or others may write "
                      f"to it: choose a new folder")
    if os.listdir(path):
        raise refused(f"out folder {path!r} is not empty: a run writes only into "
                      f"a new or empty folder, so choose another --out (or leave "
                      f"it out: each run then makes its own under {OUTPUT}/)")


class RunFolder:
    """The folder a run writes into (see the module's text); `written`, the names written so far."""

    def __init__(self, path, signals):
        self.folder, self.signals, self.written = path, signals, set()

    @classmethod
    def make(cls, out, kind, names, signals):
        """The run's folder: `out`, new or empty; without it, a new `output/<kind>-<date>-<time>`.
        ValueError naming --out, before anything is made, where it cannot be."""
        with signals.held():
            if out is not None:
                check_names(out, names)
                try:
                    made = make_folders(out)
                except FileExistsError:
                    made = []
                    check_empty(out)
            else:
                base = os.path.join(OUTPUT, f"{kind}-{datetime.datetime.now():%Y%m%d-%H%M%S}")
                check_names(base + "-999", names)
                for out in [base] + [f"{base}-{k}" for k in range(2, 1000)]:
                    try:
                        made = make_folders(out)
                        break
                    except FileExistsError:
                        continue
                else:
                    raise refused(f"no new folder could be made as {base}-N: "
                                  f"give --out")
            check_writable(out, made)
            return cls(out, signals)

    def path(self, name):
        return os.path.join(self.folder, name)

    def url(self, name):
        """A file:// URL of `name` in the folder, which most terminals open with a click."""
        return pathlib.Path(os.path.abspath(self.path(name))).as_uri()

    def write(self, name, data):
        """Write the file `name` whole (text or bytes), signals held until it is: into a new
        temporary file, then linked to its name (never over another file; over this run's own,
        replaced)."""
        with self.signals.held():
            path, tmp = self.path(name), self.path(f".tmp-{secrets.token_hex(4)}-{name}")
            try:
                try:
                    whole_files.write_temporary(tmp, data)
                    if name in self.written:
                        os.replace(tmp, path)
                    else:
                        whole_files.link_new(tmp, path)
                finally:
                    if os.path.lexists(tmp):
                        os.remove(tmp)
            except OSError as err:        # name the output, never the temporary file
                raise OSError(err.errno, err.strerror, path) from err
            self.written.add(name)

    def open_log(self, name, header):
        """A new LineFile `name`, starting with `header`."""
        with self.signals.held():
            log = whole_files.LineFile(self.path(name), header)
            self.written.add(name)
            return log
