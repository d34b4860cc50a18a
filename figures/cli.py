"""The command line of `python -m figures [NAME ...] [--out DIR]`: which figures, where, and how it ends.

It writes NAME.png for the figures asked for into a new folder, output/figures-<date>-<time>/ or
the new or empty one --out names, as a run of simulator.py writes its files (viewer.output.files.RunFolder):
each whole, never over another file nor through a symbolic link. Bad input is one line on stderr, `figures: error: ...`, exit code 2; Ctrl+C one line, exit code 130
(SIGTERM: 143); a failed write or step one line, exit code 1.
"""
import argparse
import importlib
import sys
import time

import figures
import time_integrator
from viewer.output import files
from viewer.command import run



class UsageError(Exception):
    """Bad input: reported in one line, exit code 2."""


class Parser(argparse.ArgumentParser):
    def error(self, message):
        raise UsageError(message)


def parse(argv):
    """(the figure names asked for, in the order of figures.FIGURES; the output folder)."""
    parser = Parser(prog="python -m figures", description="Write the lecture's claims as pictures.")
    parser.add_argument("names", nargs="*", metavar="NAME",
                        help=f"a figure: {', '.join(figures.FIGURES)} (default: all of them)")
    parser.add_argument("--out", help="a new or empty folder to write NAME.png into (default: a new "
                                      "one, output/figures-<date>-<time>)")
    args = parser.parse_args(argv)
    unknown = [name for name in args.names if name not in figures.FIGURES]
    if unknown:
        raise UsageError(f"unknown figure {unknown[0]!r}; choose from {', '.join(figures.FIGURES)}")
    return [name for name in figures.FIGURES if name in args.names or not args.names], args.out


def write(names, folder):
    """Compute, draw and write each figure, saying so on stdout, then the time they took in all."""
    begin = time.perf_counter()
    for name in names:
        start = time.perf_counter()
        module = importlib.import_module(f"figures.{name}")
        folder.write(f"{name}.png", module.draw(module.compute()).png())
        print(f"figures: wrote {folder.path(name + '.png')} ({time.perf_counter() - start:.1f} s)")
    print(f"figures: {len(names)} figure{'s' * (len(names) > 1)} in {time.perf_counter() - begin:.1f} s")


def main(argv=None):
    """Write the figures asked for; returns the exit code."""
    with run.Signals() as signals:
        try:
            names, out = parse(sys.argv[1:] if argv is None else argv)
            folder = files.RunFolder.make(out, "figures", [f"{name}.png" for name in names], signals)
        except (UsageError, ValueError) as err:
            print(f"figures: error: {err}", file=sys.stderr)
            return 2
        except run.Stopped as stopped:
            print(f"figures: stopped: {stopped.reason}; nothing written", file=sys.stderr)
            return stopped.code
        try:
            write(names, folder)
            return 0
        except run.Stopped as stopped:
            print(f"figures: stopped: {stopped.reason}; the figures written so far are whole", file=sys.stderr)
            return stopped.code
        except (OSError, time_integrator.SimulationError) as err:     # a failed write (a full disk), a failed step
            print(f"figures: error: {err}", file=sys.stderr)
            return 1
        finally:
            signals.close()
