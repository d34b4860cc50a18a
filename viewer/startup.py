"""`python simulator.py` (and `python -m figures`), before numpy loads: the process's settings, then
the command line (viewer/cli.py, figures/cli.py).

Numpy, scipy and pygame take a moment to load. Until the run takes over its signals (viewer/run.py),
Ctrl+C or SIGTERM during that moment end the program here, in one line, with nothing written.
"""
import functools
import importlib
import os
import signal
import sys

EXIT_CODES = {signal.SIGINT: 130, signal.SIGTERM: 143}      # 128 + the signal's number


def _stopped_while_starting(program, signum, frame):
    os.write(2, f"{program}: stopped: {'interrupted' if signum == signal.SIGINT else 'terminated (SIGTERM)'} "
                f"while starting; nothing written\n".encode())
    os._exit(EXIT_CODES[signum])


def run_command_line(program="simulator.py", main="viewer.cli"):
    """The exit code of `main`'s main(argv). One BLAS thread (two on two busy cores made the small banded
    factorizations 10-25x slower: benchmarks/README.md), set before numpy loads."""
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    for signum in EXIT_CODES:
        signal.signal(signum, functools.partial(_stopped_while_starting, program))
    command_line = importlib.import_module(main)
    for signum in EXIT_CODES:       # until the run takes them over (Signals in main), and after it is done
        signal.signal(signum, signal.SIG_IGN)
    return command_line.main(sys.argv[1:])
