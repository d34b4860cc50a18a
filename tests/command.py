"""The command line as the tests run it in this process."""
import io
import sys

from viewer import cli


def run_main(*args):
    """viewer.cli.main(args) in this process: (exit code, stderr lines)."""
    err, old = io.StringIO(), sys.stderr
    sys.stderr = err
    try:
        code = cli.main(list(args))
    finally:
        sys.stderr = old
    return code, err.getvalue().splitlines()
