"""What the benchmarks share: text tables, CSV files, runs taken in turn, and their noise: NOISY
where repeats spread by more than SPREAD_LIMIT of their median or the process waited for a CPU
(median wall / CPU time above WAIT_LIMIT: other processes stretch wall time, not CPU time).
"""
import csv
import io
import math
import os
import statistics
import subprocess
import sys
import time

from benchmarks import ROOT
from viewer.output import whole_files

try:
    import resource         # POSIX: the CPU time of finished child processes
except ImportError:         # Windows: no such figure, a process's CPU time is nan
    resource = None

SPREAD_LIMIT, WAIT_LIMIT = 0.20, 1.15


def aligned(cells):
    """Rows of text cells as lines: columns right-aligned but the last, a rule under the head."""
    widths = [max(len(row[i]) for row in cells) for i in range(len(cells[0]) - 1)]
    lines = ["  ".join([c.rjust(w) for c, w in zip(row, widths)] + [row[-1]]) for row in cells]
    return lines[:1] + ["-" * len(lines[0])] + lines[1:]


def text(columns, rows, **names):
    """aligned of a table: `columns` are (title, format) pairs, each format filled in from a row
    (a dict), each title from `names`."""
    return aligned([[title.format(**names) for title, _ in columns]]
                   + [[form.format(**row) for _, form in columns] for row in rows])


def write_csv(path, columns, rows, digits=6):
    """`rows` (dicts) as the CSV file `path`, floats to `digits` significant digits."""
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, columns, extrasaction="ignore", lineterminator="\n")
    writer.writeheader()
    writer.writerows({k: f"{v:.{digits}g}" if isinstance(v, float) else v for k, v in row.items()}
                     for row in rows)
    whole_files.write_atomic(path, buffer.getvalue())


def spread(values):
    return (max(values) - min(values)) / statistics.median(values)


def noise(walls, cpus):
    """'ok', or why the machine was too busy for these figures to mean much."""
    reasons = []
    if spread(cpus) > SPREAD_LIMIT:
        reasons.append(f"CPU times spread {100 * spread(cpus):.0f}%")
    wait = statistics.median(walls) / statistics.median(cpus)
    if wait > WAIT_LIMIT:
        reasons.append(f"wall/CPU {wait:.2f}")
    return "NOISY: " + ", ".join(reasons) if reasons else "ok"


def medians(results):
    """{figure: its median} over `results`, a list of dicts of figures."""
    return {key: statistics.median(r[key] for r in results) for key in results[0]}


def in_turn(jobs, repeats):
    """Call each of `jobs` ({key: function of no argument}) in turn, `repeats` rounds, so that all
    meet the machine in the same state: {key: [what each call returned]}."""
    results = {key: [] for key in jobs}
    for round_ in range(repeats):
        for key, job in jobs.items():
            results[key].append(job())
        print(f"  round {round_ + 1}/{repeats} done", file=sys.stderr, flush=True)
    return results


def children_cpu():
    """CPU seconds of the finished child processes so far (nan without `resource`)."""
    if resource is None:
        return math.nan
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_process(command):
    """Run `command` in the repository's folder (SDL's dummy driver, one BLAS thread): wall s,
    CPU s, stdout, stderr; RuntimeError if it fails."""
    env = {**os.environ, "SDL_VIDEODRIVER": "dummy", "OPENBLAS_NUM_THREADS": "1"}
    cpu, start = children_cpu(), time.perf_counter()
    done = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, env=env)
    wall, cpu = time.perf_counter() - start, children_cpu() - cpu
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed:\n{done.stderr}")
    return wall, cpu, done.stdout, done.stderr
