"""A run's folder, new or the empty one --out names, claimed in one atomic step by the run that
writes it; its files created new and written whole; nothing outside it is touched (docs/output.md,
"A run writes only into its own new folder")."""
import contextlib
import datetime
import os
import pathlib
import secrets
import stat

import utils
from viewer.output import whole_files

OUTPUT = "output"       # where a run's folder is made without --out
CLAIM = ".claimed-by-a-run"     # created O_EXCL in the run's folder: one run only; gone at its end
TRIES = 5               # a parent removed by another run as this one made its folder: try again
MAX_LINKS = 40          # as the kernel's ELOOP


def shown(path):
    """`path` as a line may print it: each control character (a newline, a terminal's escape)
    written as Python writes it in a string, '\\n', '\\x1b'; the rest as it is."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in str(path))


def cannot_write(err, where):
    """'cannot write X: why' for the OSError `err` of a failed write: X its file, else `where`."""
    return f"cannot write {shown(err.filename or where)}: {err.strerror or err}"


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
    """Remove the folders this run made, innermost first, where still empty: one that another run
    has put its folder or claim in stays."""
    for at in reversed(made):
        with contextlib.suppress(OSError):
            os.rmdir(at)


def planted(link, folder):
    """True where `link` is another user's link in a sticky folder all may write to (/tmp), which
    the kernel itself would not follow (fs.protected_symlinks)."""
    held, mode = os.lstat(link).st_uid, os.stat(folder).st_mode
    shared = mode & stat.S_ISVTX and mode & stat.S_IWOTH
    return bool(shared) and held not in (os.geteuid(), os.stat(folder).st_uid)


def resolved(out):
    """The absolute folder `out` names, as the kernel finds it: each link followed where it stands,
    so with x/a a link to x/t1/t2, x/a/../b is x/t1/b (os.path.abspath says x/b). A ValueError
    naming --out for `out` itself a link, a link another user planted (`planted`) or a loop. On
    Windows '..' goes up as text before any link is followed: os.path.abspath is where it writes."""
    last = out.rstrip(os.sep + (os.altsep or "")) or out       # out/ too: the link, not in it
    if os.path.islink(last):
        raise refused(f"out folder {out!r} is a link to {os.readlink(last)!r}: give the folder "
                      f"itself")
    if not whole_files.HAS_OWNERS:
        return os.path.abspath(out)
    try:
        return walked(out)
    except OSError as err:          # a folder on the way that cannot be read
        raise refused(f"out folder {out!r} cannot be created: {err.strerror or err}") from None


def walked(out):
    """`resolved` on POSIX: the path walked one name at a time, each link's target put in its
    place, '..' going up from where the walk is."""
    parts = list(reversed(pathlib.PurePath(os.path.abspath(os.curdir), out).parts[1:]))
    here, links = os.sep, 0
    while parts:
        part = parts.pop()
        at = os.path.join(here, part)
        if part == "..":
            here = os.path.dirname(here)
        elif not os.path.islink(at):
            here = at
        elif planted(at, here) or links == MAX_LINKS:
            why = "another user's link" if links < MAX_LINKS else "too many links"
            raise refused(f"out folder {out!r} goes through {at!r}: {why}: give another --out")
        else:
            links, target = links + 1, pathlib.PurePath(os.readlink(at))
            parts.extend(reversed(target.parts[1:] if target.is_absolute() else target.parts))
            here = os.sep if target.is_absolute() else here
    return here


def make_parents(folder, out):
    """Make the missing parents of `folder`, outermost first; returns those made. A parent another
    run makes at the same moment is taken as found, as os.makedirs(exist_ok=True) does."""
    made = []
    for at in map(str, reversed(pathlib.PurePath(folder).parents)):
        try:
            if not os.path.lexists(at):
                os.mkdir(at)
                made.append(at)
        except FileExistsError:
            pass
        except OSError as err:
            remove(made)
            raise refused(f"out folder {out!r} cannot be created: {err.strerror or err}") from None
        if not os.path.isdir(at) or os.path.islink(at):     # a link put there since `resolved`
            remove(made)
            raise refused(f"out folder {out!r} cannot be created: {at!r} is not a folder")
    return made


def make_folders(folder, out):
    """Make `folder` by one os.mkdir, and its missing parents; returns those made, outermost first
    (`folder` last where this run made it; not there where it existed). A ValueError naming --out,
    nothing left made, where it cannot be made."""
    for _ in range(TRIES):
        made = make_parents(folder, out)
        try:
            os.mkdir(folder)
            return made + [folder]
        except FileExistsError:
            return made
        except FileNotFoundError:       # a parent removed by the run that made it: again
            remove(made)
        except OSError as err:
            remove(made)
            raise refused(f"out folder {out!r} cannot be created: {err.strerror or err}") from None
    raise refused(f"out folder {out!r} cannot be created: its parents keep disappearing")


def check_empty(path, out, given=True):
    """ValueError unless `path` is an empty folder of this user's that others cannot write to."""
    if not os.path.isdir(path):
        raise refused(f"{named(out, given)} is not a folder: choose a new one", given)
    st = os.stat(path)
    shared = st.st_mode & stat.S_IWOTH and not st.st_mode & stat.S_ISVTX
    if whole_files.HAS_OWNERS and (st.st_uid != os.geteuid() or shared):
        raise refused(f"{named(out, given)} is another user's or writable by others: choose a "
                      f"new one", given)
    if os.listdir(path):
        raise refused(f"{named(out, given)} is not empty: choose another --out, new or empty",
                      given)


def identity(path):
    """(device, inode) of `path` itself, or None where it is not there."""
    try:
        st = os.lstat(path)
    except OSError:
        return None
    return st.st_dev, st.st_ino


def claim(path, out, given=True):
    """Claim the folder `path` for this run: the file CLAIM created in it (O_EXCL: one run only
    can), then the folder found empty but for it. A ValueError naming --out (where `given`, else
    the folder) where another run claimed it first or it is not empty; returns its identity."""
    check_empty(path, out, given)
    name = os.path.join(path, CLAIM)
    try:
        fd = os.open(name, whole_files.NEW, 0o666)
    except FileExistsError:
        raise refused(f"{named(out, given)} was taken by a run started at once: choose another "
                      f"--out", given) from None
    except OSError as err:
        raise refused(f"{named(out, given)} cannot be written: {err.strerror or err}",
                      given) from None
    try:
        with os.fdopen(fd, "w") as f:
            f.write(f"the folder of the run of process {os.getpid()}, while it runs\n")
    except OSError as err:          # a full disk
        os.remove(name)
        raise refused(f"{named(out, given)} cannot be written: {err.strerror or err}",
                      given) from None
    if os.listdir(path) != [CLAIM]:
        os.remove(name)
        check_empty(path, out, given)
    return identity(name)


def new_folder(kind):
    """A new output/<kind>-<date>-<time> (-2, -3, ... where taken) made by one os.mkdir, output/
    made as os.makedirs(exist_ok=True) does and never removed; (the folder, its claim)."""
    base = os.path.join(OUTPUT, f"{kind}-{datetime.datetime.now():%Y%m%d-%H%M%S}")
    try:
        with contextlib.suppress(FileExistsError):      # a file named output: os.mkdir says so
            os.makedirs(OUTPUT, exist_ok=True)
        for out in [base] + [f"{base}-{k}" for k in range(2, 1000)]:
            with contextlib.suppress(FileExistsError):
                os.mkdir(out)
                return out, claim_made(out, [out], out, False)
    except OSError as err:
        raise refused(f"{named(base, False)} cannot be created: {err.strerror or err}",
                      False) from None
    raise refused(f"no new folder could be made as {base}-N: give --out", False)


def claim_made(folder, made, out, given=True):
    """`claim` the folder (the folders `made` for it); where it cannot, those are removed."""
    try:
        return claim(folder, out, given)
    except BaseException:
        remove(made)
        raise


def probe(folder, name):
    """Create `name` in `folder` as its temporary file is named, write a line, then remove it."""
    path = os.path.join(folder, f".tmp-{secrets.token_hex(4)}-{name}")
    try:
        with os.fdopen(os.open(path, whole_files.NEW), "w") as f:
            f.write("a probe: can a file be written here?\n")
    finally:
        if os.path.lexists(path):
            os.remove(path)


def take(out, kind):
    """(the run's folder, the folders made for it, its claim): a new_folder, or `out` where the
    kernel puts it (`resolved`), made where missing, and claimed."""
    if out is None:
        folder, claimed = new_folder(kind)
        return folder, [folder], claimed
    real = resolved(out)
    made = make_folders(real, out)
    claimed = claim_made(real, made, out)
    return (out if real == os.path.abspath(out) else real), made, claimed


class RunFolder:
    """The folder a run writes into; `written`, the names written so far; `lost`, set as the run
    ends (`release`) where its folder was deleted, moved or replaced while it ran."""

    def __init__(self, path, made, claimed, signals):
        self.folder, self.made, self.claimed, self.signals = path, made, claimed, signals
        self.written, self.lost = set(), False

    @classmethod
    def make(cls, out, kind, names, signals):
        """The run's folder (`take`): `out`, new or empty, or a new_folder; a ValueError naming
        --out, nothing made, where it cannot be or a probe or one of `names` cannot be written in
        it. Claimed until `release`."""
        folder = None
        try:
            with signals.held():
                folder = cls(*take(out, kind), signals)
                for name in ["probe", *names]:
                    try:
                        probe(folder.folder, name)
                    except OSError as err:
                        given = out is not None
                        raise refused(f"output name {name!r} in {named(folder.folder, given)} "
                                      f"cannot be written: {err.strerror}", given) from None
        except BaseException:           # refused, or a signal as it ended: nothing left made
            if folder is not None:
                folder.release()
                remove(folder.made)
            raise
        return folder

    def gone(self):
        """True where the folder holds no longer this run's claim: deleted, moved or replaced."""
        return identity(self.path(CLAIM)) != self.claimed

    def release(self):
        """The run ends: `lost` set where its folder is gone, else its claim removed."""
        if self.claimed is not None:
            self.lost = self.gone()
            if not self.lost:
                with contextlib.suppress(OSError):
                    os.remove(self.path(CLAIM))
            self.claimed = None

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
