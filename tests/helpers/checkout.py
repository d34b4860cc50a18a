"""Whether a benchmark left the checkout as it was (the benchmarks' tests)."""
import os
import shutil
import subprocess

import pytest

from helpers import ROOT
RESULTS = os.path.join(ROOT, "benchmarks", "results")      # what benchmarks/README.md quotes


def checkout_state():
    """What a benchmark must not change: `git status --porcelain` of the checkout, and the size and
    modification time of every file in benchmarks/results/ (a file rewritten with the same bytes
    counts too). Skips the test where this is not a git checkout."""
    if shutil.which("git") is None:
        pytest.skip("git is not installed, so whether the checkout stays clean cannot be told")
    status = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=all"],
                            capture_output=True, text=True)
    if status.returncode != 0:
        pytest.skip(f"not inside a git checkout: {status.stderr.strip()}")
    stamps = {entry.name: (entry.stat().st_size, entry.stat().st_mtime_ns)
              for entry in os.scandir(RESULTS)}
    return status.stdout, stamps
