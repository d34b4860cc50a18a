"""`python simulator.py`, before numpy loads: the process's settings, then the command line (viewer/cli.py).

Numpy, scipy and pygame take a moment to load. Until the run takes over its signals (viewer/run.py),
Ctrl+C or SIGTERM during that moment end the program here, in one line, with nothing written.
"""
import os
import signal
import sys

EXIT_CODES = {signal.SIGINT: 130, signal.SIGTERM: 143}      # 128 + the signal's number


def _stopped_while_starting(signum, frame):
    os.write(2, f"simulator.py: stopped: {'interrupted' if signum == signal.SIGINT else 'terminated (SIGTERM)'} "
                f"while starting; nothing written\n".encode())
    os._exit(EXIT_CODES[signum])


def run_command_line():
    """The command line's exit code. One BLAS thread (two on two busy cores made the small banded
    factorizations 10-25x slower: benchmarks/README.md), set before numpy loads."""
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    for signum in EXIT_CODES:
        signal.signal(signum, _stopped_while_starting)
    from viewer import cli
    for signum in EXIT_CODES:       # until the run takes them over (cli.main), and after it is done
        signal.signal(signum, signal.SIG_IGN)
    return cli.main(sys.argv[1:])
