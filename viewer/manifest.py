"""The output folder's manifest, MANIFEST: each file its runs wrote, and its identity.

A line per file, `name<TAB>device<TAB>inode<TAB>size<TAB>mtime_ns`, written before the file's name
appears; a file that grows (a log) keeps one line of fixed width, rewritten in place as it grows. Only
the user who wrote it may write to it (mode 0600); one that is another user's, or that others may
write to, or that is not a regular file, was not written by this program (viewer.files refuses it).
"""
import os

import utils
from viewer import whole_files

MANIFEST = ".simulator-files"
HEADER = "# simulator outputs v2: name, device, inode, size, mtime_ns of each file its runs wrote"


def read_manifest(folder):
    """{name: identity} of the files the manifest in `folder` lists (empty without one); ValueError for
    a manifest this program did not write, or that another user could have written."""
    path = os.path.join(folder, MANIFEST)
    refused = (f"out folder {folder!r} holds {MANIFEST}, which this simulator did not write or which another "
               f"user could have written; move it away or choose another --out")
    try:
        fd = whole_files.open_existing(path)
    except OSError:
        raise utils.ParameterError("out", refused) from None
    if fd is None:
        return {}
    with os.fdopen(fd, "rb") as f:
        ok = whole_files.mine(os.fstat(fd))
        try:
            lines = f.read().decode().splitlines()
        except (OSError, UnicodeDecodeError):
            lines = []
    if not ok or not lines or lines[0] != HEADER:
        raise utils.ParameterError("out", refused)
    records = {}
    for line in lines[1:]:
        name, *fields = line.rstrip(" ").split("\t")
        records[name] = tuple(int(v) for v in fields) if len(fields) == 4 and all(
            v.isdigit() for v in fields) else None          # None: listed, never completed
    return records


class Manifest(whole_files.LineFile):
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
