"""Supporting scripts: reports and benchmarks run from the repository root as python -m benchmarks.<name>.

Where they write (benchmarks/README.md says it too): `benchmarks/results/` holds the tables and plots
the README quotes, so only a benchmark's full run (its plain command, no option that narrows or changes
what it measures) writes there, or a run told so by `--out benchmarks/results`. Every other run
(`--quick`, `speed --sizes`, `speed --against`, ...) writes into a new temporary folder and says which.
"""
import os
import tempfile

RESULTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "results")


def output_folder(out, full, program):
    """The folder a benchmark writes into, created if need be: `out` when given; RESULTS for a full
    run; else a new temporary folder named after `program` (a smoke or partial run must not overwrite
    the published results)."""
    if out is None:
        out = RESULTS if full else tempfile.mkdtemp(prefix=f"{program}-")
    os.makedirs(out, exist_ok=True)
    return out
