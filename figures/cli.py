"""`python -m figures [NAME ...] [--out DIR]`: writes NAME.png into a new folder, as simulator.py
does (viewer.output.files.RunFolder). Bad input: one line `figures: error: ...`, exit code 2;
Ctrl+C 130 (SIGTERM 143); a failed write ("cannot write X: why", as simulator.py says it) or step:
one line, exit code 1.
"""
import importlib
import sys
import time

import figures
import time_integrator
from viewer.command import progress, run
from viewer.command.cli import CommandLineError, Parser
from viewer.output import files


def parse(argv):
    """(the figures asked for, in the order of figures.FIGURES; the output folder or None)."""
    names = ", ".join(figures.FIGURES)
    parser = Parser(prog="python -m figures", description="Write the lecture's claims as pictures.")
    parser.add_argument("names", nargs="*", metavar="NAME",
                        help=f"a figure: {names} (default: all of them)")
    parser.add_argument("--out", help="a new or empty folder to write NAME.png into "
                                      "(default: a new one, output/figures-<date>-<time>)")
    args = parser.parse_args(argv)
    unknown = [name for name in args.names if name not in figures.FIGURES]
    if unknown:
        raise CommandLineError(f"unknown figure {unknown[0]!r}; choose from {names}")
    return [name for name in figures.FIGURES if name in args.names or not args.names], args.out


def write(names, folder):
    """Compute, draw and write each figure, saying so on stdout, then the time they took."""
    begin = time.perf_counter()
    for name in names:
        start = time.perf_counter()
        module = importlib.import_module(f"figures.{name}")
        folder.signals.check()          # a signal whose raise the import dropped: before compute
        folder.write(f"{name}.png", module.draw(module.compute()).png())
        seconds = time.perf_counter() - start
        print(f"figures: wrote {files.shown(folder.path(name + '.png'))} ({seconds:.1f} s)")
    plural = "s" * (len(names) > 1)
    print(f"figures: {len(names)} figure{plural} in {time.perf_counter() - begin:.1f} s")


def kept(folder):
    """'N figures kept in out/' (each whole), 'nothing written in out/', or 'nothing written'."""
    if folder is None:
        return "nothing written"
    count = sum(name.endswith(".png") for name in folder.written)
    said = f"{count} figure{'s' * (count != 1)} kept" if count else "nothing written"
    return f"{said} in {files.shown(folder.folder)}/"


def main(argv=None):
    """Write the figures asked for; returns the exit code."""
    with run.Signals() as signals:
        folder = None
        try:
            try:
                names, out = parse(sys.argv[1:] if argv is None else argv)
                pngs = [f"{name}.png" for name in names]
                folder = files.RunFolder.make(out, "figures", pngs, signals)
                write(names, folder)
                return 0
            except (CommandLineError, ValueError) as err:
                if folder is not None:      # not bad input: a bug in a figure
                    raise
                signals.close()             # the error is said: a signal from here on waits
                print(f"figures: error: {err}", file=sys.stderr)
                return 2
            except (OSError, time_integrator.SimulationError) as err:   # a full disk, a step
                signals.close()
                where = "the figures' folder" if folder is None else folder.folder
                said = (f"figures: error: {files.cannot_write(err, where)}"   # a path runs on
                        if isinstance(err, OSError) else progress.wrapped(f"figures: error: {err}"))
                print(said, file=sys.stderr)
                return 1
        except run.Stopped as stopped:      # also as an error was found
            signals.close()
            print(f"figures: stopped: {stopped.reason}; {kept(folder)}", file=sys.stderr)
            return stopped.code
        finally:
            signals.close()
            if folder is not None:
                folder.release()        # its claim (files.CLAIM) removed: the folder is done
