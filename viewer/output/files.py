"""A run's folder, new or the empty one --out names, its files created new and written whole;
nothing outside it is touched (docs/output.md, "A run writes only into its own new folder")."""
import datetime
import os
import pathlib
import secrets
import stat

import utils
from viewer.output import whole_files

OUTPUT = "output"       # where a run's folder is made without --out


def refused(text, given=True):
    """The ValueError that refuses a run's folder: about --out where it was `given`, else about the
    folder tried under output/ (its parameter "output" has no flag to blame)."""
    return utils.ParameterError("out" if given else "output", text)


def named(path, given=True):
    """The folder in a refusal's words: the --out given, or the one tried for a run without it."""
    return f"out folder {path!r}" if given else f"folder {path!r}"


def tagged(stem, tag, extension):
    """log.csv, or log_mu0.2.csv for one run of a comparison."""
    return f"{stem}_{tag}.{extension}" if tag else f"{stem}.{extension}"


def frame_png(index):
    return f"frame_{index:05d}.png"


def frame_obj(index, tag=""):
    return tagged(f"frame_{index:05d}", tag, "obj")


def log_csv(tag=""):
    return tagged("log", tag, "csv")


def marks_csv(tag=""):
    return tagged("marks", tag, "csv")


def remove(made):
    for at in reversed(made):
        os.rmdir(at)


def make_folders(path, given=True):
    """Make the folder `path` and its missing parents; returns those made, outermost first.
    FileExistsError where `path` exists; a ValueError, nothing left made, where it cannot be (about
    --out where it was `given`)."""
    parents = pathlib.Path(os.path.abspath(path)).parents
    missing = [str(at) for at in reversed(parents) if not os.path.lexists(at)]
    made = []
    try:
        for at in missing + [os.path.abspath(path)]:
            os.mkdir(at)
            made.append(at)
    except OSError as err:
        remove(made)
        if isinstance(err, FileExistsError) and len(made) == len(missing):
            raise                           # `path` itself exists: the caller decides
        raise refused(f"{named(path, given)} cannot be created: {err.strerror or err}",
                      given) from None
    return made


def check_empty(path):
    """ValueError unless `path` is an empty folder of this user's that others cannot write to."""
    if not os.path.isdir(path):
        raise refused(f"out folder {path!r} is not a folder: choose a new one")
    st = os.stat(path)
    shared = st.st_mode & stat.S_IWOTH and not st.st_mode & stat.S_ISVTX
    if whole_files.HAS_OWNERS and (st.st_uid != os.geteuid() or shared):
        raise refused(f"out folder {path!r} is another user's or others may write to it: choose "
                      f"a new folder")
    if os.listdir(path):
        raise refused(f"out folder {path!r} is not empty: a run writes only into a new or empty "
                      f"folder, so choose another --out (or leave it out: each run then makes "
                      f"its own under {OUTPUT}/)")


def new_folder(kind):
    """A new output/<kind>-<date>-<time> (-2, -3, ... where taken); the folder, the folders made."""
    base = os.path.join(OUTPUT, f"{kind}-{datetime.datetime.now():%Y%m%d-%H%M%S}")
    for out in [base] + [f"{base}-{k}" for k in range(2, 1000)]:
        try:
            return out, make_folders(out, given=False)
        except FileExistsError:
            continue
    raise refused(f"no new folder could be made as {base}-N: give --out", given=False)


def probe(folder, name):
    """Create `name` in `folder` as its temporary file is named, write a line, then remove it."""
    path = os.path.join(folder, f".tmp-{secrets.token_hex(4)}-{name}")
    try:
        with os.fdopen(os.open(path, whole_files.NEW), "w") as f:
            f.write("a probe: can a file be written here?\n")
    finally:
        if os.path.lexists(path):
            os.remove(path)


class RunFolder:
    """The folder a run writes into; `written`, the names written so far."""

    def __init__(self, path, signals):
        self.folder, self.signals, self.written = path, signals, set()

    @classmethod
    def make(cls, out, kind, names, signals):
        """The run's folder: `out`, new or empty, or a new_folder; a ValueError naming --out,
        nothing made, where it cannot be or a probe or one of `names` cannot be written in it."""
        with signals.held():
            given = out is not None
            if out is None:
                out, made = new_folder(kind)
            else:
                try:
                    made = make_folders(out)
                except FileExistsError:
                    made = []
                    check_empty(out)
            for name in ["probe", *names]:
                try:
                    probe(out, name)
                except OSError as err:
                    remove(made)
                    raise refused(f"output name {name!r} in {named(out, given)} cannot be "
                                  f"written: {err.strerror}", given) from None
            return cls(out, signals)

    def path(self, name):
        return os.path.join(self.folder, name)

    def url(self, name):
        return pathlib.Path(os.path.abspath(self.path(name))).as_uri()

    def write(self, name, data):
        """Write the file `name` whole (replacing only this run's own), signals held until it is."""
        with self.signals.held():
            whole_files.write_whole(self.path(name), data, replace=name in self.written)
            self.written.add(name)

    def open_log(self, name, header):
        """A new whole_files.LineFile `name`, starting with `header`."""
        with self.signals.held():
            self.written.add(name)
            return whole_files.LineFile(self.path(name), header)
