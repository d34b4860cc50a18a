"""Running the notebook in Jupyter leaves notebooks/.ipynb_checkpoints/: git ignores it (issue 40),
so a student's `git status` stays clean."""
import shutil
import subprocess

import pytest

from helpers import ROOT


def test_the_notebooks_checkpoints_are_ignored():
    if shutil.which("git") is None:
        pytest.skip("no git to ask")
    asked = subprocess.run(["git", "check-ignore", "-q", "notebooks/.ipynb_checkpoints/"
                            "lecture-checkpoint.ipynb"], cwd=ROOT, capture_output=True)
    if asked.returncode == 128:
        pytest.skip(f"not a git checkout: {asked.stderr.decode().strip()}")
    assert asked.returncode == 0            # 1: not ignored
