"""The command line of `python -m figures [NAME ...] [--out DIR]`: which figures, where, and how it ends.

It writes only NAME.png for the figures asked for, each whole (a temporary file beside it, renamed
over it), never through a symlink: a target that exists as anything but a regular file is refused
before anything is computed. Bad input is one line on stderr, `figures: error: ...`, exit code 2;
Ctrl+C one line, exit code 130 (SIGTERM: 143); a failed write or step one line, exit code 1.
"""
import argparse
import contextlib
import importlib
import os
import signal
import sys
import tempfile
import time

import figures
import time_integrator

DEFAULT_OUT = os.path.join("output", "figures")


class UsageError(Exception):
    """Bad input: reported in one line, exit code 2."""


class Terminated(KeyboardInterrupt):
    """SIGTERM, ended as Ctrl+C is (exit code 143)."""


class Parser(argparse.ArgumentParser):
    def error(self, message):
        raise UsageError(message)


def parse(argv):
    """(the figure names asked for, in the order of figures.FIGURES; the output folder)."""
    parser = Parser(prog="python -m figures", description="Write the lecture's claims as pictures.")
    parser.add_argument("names", nargs="*", metavar="NAME",
                        help=f"a figure: {', '.join(figures.FIGURES)} (default: all of them)")
    parser.add_argument("--out", default=DEFAULT_OUT, help=f"the folder to write NAME.png into (default {DEFAULT_OUT})")
    args = parser.parse_args(argv)
    unknown = [name for name in args.names if name not in figures.FIGURES]
    if unknown:
        raise UsageError(f"unknown figure {unknown[0]!r}; choose from {', '.join(figures.FIGURES)}")
    return [name for name in figures.FIGURES if name in args.names or not args.names], args.out


def prepare(folder):
    """Create `folder` and prove a file can be created in it; UsageError otherwise."""
    try:
        os.makedirs(folder, exist_ok=True)
        with signals_held():
            fd, probe = tempfile.mkstemp(dir=folder, prefix=".tmp-probe-")
            os.close(fd)
            os.remove(probe)
    except OSError as err:
        raise UsageError(f"--out {folder!r} cannot be written: {err.strerror or err}") from None


def target(folder, name):
    """The path of NAME.png in `folder`; UsageError if something other than a regular file is there (a
    symlink, even to a regular file, or a folder): only files are replaced, never written through."""
    path = os.path.join(folder, f"{name}.png")
    if os.path.islink(path) or (os.path.lexists(path) and not os.path.isfile(path)):
        raise UsageError(f"{path} exists and is not a regular file; not replacing it")
    return path


@contextlib.contextmanager
def signals_held():
    """SIGINT and SIGTERM held (pending, not lost) while a temporary file exists: an interrupt lands
    before it is created or after it is renamed or removed, so none is ever left behind."""
    held = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, held)


def _terminate(signum, frame):
    raise Terminated()


def main(argv=None):
    """Write the figures asked for; returns the exit code."""
    previous = signal.signal(signal.SIGTERM, _terminate)
    try:
        names, out = parse(sys.argv[1:] if argv is None else argv)
        prepare(out)
        for name in names:
            target(out, name)
        for name in names:
            start = time.perf_counter()
            module = importlib.import_module(f"figures.{name}")
            page = module.draw(module.compute())
            path = target(out, name)
            with signals_held():
                page.save(path)
            print(f"figures: wrote {path} ({time.perf_counter() - start:.1f} s)")
        return 0
    except UsageError as err:
        print(f"figures: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as err:
        print("figures: stopped: " + ("terminated (SIGTERM)" if isinstance(err, Terminated) else "interrupted")
              + "; the figures written so far are whole", file=sys.stderr)
        return 143 if isinstance(err, Terminated) else 130
    except (OSError, time_integrator.SimulationError) as err:     # a failed write (a full disk), a failed step
        print(f"figures: error: {err}", file=sys.stderr)
        return 1
    finally:
        signal.signal(signal.SIGTERM, previous)
