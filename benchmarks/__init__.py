"""Benchmarks, run from the repository's folder as `python -m benchmarks.<name>` (see README.md).

Only a full run (the plain command) writes into benchmarks/results/, the tables README.md quotes;
any other run writes into a new temporary folder, or into the folder --out names.
"""
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "benchmarks", "results")


def output_folder(out, full, program):
    """`out` if given, else RESULTS for a full run, else a new temporary folder `program`-...;
    created if need be."""
    if out is None:
        out = RESULTS if full else tempfile.mkdtemp(prefix=f"{program}-")
    os.makedirs(out, exist_ok=True)
    return out


def export_tree(rev, folder):
    """The tree to measure: `rev` itself if it is a folder, else commit `rev` written into `folder`
    by git archive (the checkout is not touched)."""
    if os.path.isdir(rev):
        return os.path.abspath(rev)
    archive = subprocess.run(["git", "-C", ROOT, "archive", "--format=tar", rev],
                             capture_output=True)
    if archive.returncode != 0:
        raise SystemExit(f"error: git archive {rev}: {archive.stderr.decode().strip()}")
    subprocess.run(["tar", "-x", "-C", folder], input=archive.stdout, check=True)
    return folder


def in_fresh_process(module, *args):
    """`python -m module --worker JSON(args)` in the repository's folder: the JSON it printed last
    (a tree's modules are imported afresh there)."""
    done = subprocess.run([sys.executable, "-m", module, "--worker", json.dumps(args)], cwd=ROOT,
                          capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{module} --worker {args} failed:\n{done.stderr}")
    return json.loads(done.stdout.splitlines()[-1])
