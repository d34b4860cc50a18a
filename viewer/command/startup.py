"""`python simulator.py` (and `python -m figures`) before numpy loads: one BLAS thread, Ctrl+C,
SIGTERM, SIGHUP and SIGQUIT in one line, stdout and stderr best effort; then the command line
(viewer.main)."""
import contextlib
import importlib
import io
import os
import signal
import sys

# the signals that stop a run in one line (docs/output.md, "How a run ends"): exit code 128 + the
# signal's number; SIGHUP (a closed terminal or SSH session) and SIGQUIT (Ctrl+\) not on Windows
SIGNALS = [(signal.SIGINT, 130, "interrupted"), (signal.SIGTERM, 143, "terminated (SIGTERM)"),
           (getattr(signal, "SIGHUP", None), 129, "hangup (SIGHUP)"),
           (getattr(signal, "SIGQUIT", None), 131, "quit (SIGQUIT)")]
EXIT_CODES = {signum: code for signum, code, _ in SIGNALS if signum is not None}
REASONS = {signum: reason for signum, _, reason in SIGNALS if signum is not None}


class BestEffort(io.TextIOBase):
    """A text stream whose writes never fail: after the first that does, it writes to os.devnull."""

    def __init__(self, stream):
        self.stream = stream

    def write(self, text):
        self._try("write", text)
        return len(text)

    def flush(self):
        self._try("flush")

    def _try(self, method, *args):
        if self.stream is None:             # no stream, or broken already
            return
        try:
            getattr(self.stream, method)(*args)
        except (OSError, ValueError):       # ValueError: the stream was closed
            with contextlib.suppress(OSError, ValueError, AttributeError):
                devnull = os.open(os.devnull, os.O_WRONLY)
                os.dup2(devnull, self.stream.fileno())
                os.close(devnull)
            self.stream = None


class WhileStarting:
    """The signals' handler until the run takes them over (run.Signals, which leaves them ignored
    as it hands them back: these words would then be untrue): one line, the exit code, at once."""

    def __init__(self, program):
        self.program = program

    def __call__(self, signum, frame):
        line = f"{self.program}: stopped: {REASONS[signum]} while starting; nothing written\n"
        with contextlib.suppress(OSError):      # stderr closed or full: the exit code still says it
            os.write(2, line.encode())
        os._exit(EXIT_CODES[signum])


def run_command_line(program="simulator.py", main="viewer.main"):
    """The exit code of `main`'s main(argv), one BLAS thread set first (benchmarks/README.md)."""
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    for signum in EXIT_CODES:
        signal.signal(signum, WhileStarting(program))
    sys.stdout, sys.stderr = BestEffort(sys.stdout), BestEffort(sys.stderr)
    code = importlib.import_module(main).main(sys.argv[1:])      # its run takes the signals over
    for signum in EXIT_CODES:       # the run has said how it ended: a late signal changes nothing
        signal.signal(signum, signal.SIG_IGN)
    return code
