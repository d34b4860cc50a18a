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
REASONS = {signal.SIGINT: "interrupted", signal.SIGTERM: "terminated (SIGTERM)"}


def _stopped_while_starting(program, signum, frame):
    os.write(2, f"{program}: stopped: {REASONS[signum]} while starting; nothing written\n".encode())
    os._exit(EXIT_CODES[signum])


def run_command_line(program="simulator.py", main="viewer.cli"):
    """The exit code of `main`'s main(argv). One BLAS thread (two on two busy cores made the small banded
    factorizations 10-25x slower: benchmarks/README.md), set before numpy loads."""
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    for signum in EXIT_CODES:
        signal.signal(signum, functools.partial(_stopped_while_starting, program))
    code = importlib.import_module(main).main(sys.argv[1:])      # its run takes the signals over
    for signum in EXIT_CODES:       # the run has said how it ended: a late signal changes nothing
        signal.signal(signum, signal.SIG_IGN)
    return code
