"""What the benchmarks share: where they write, other trees, text tables, CSV files, runs taken in
turn, and their noise: NOISY where repeats spread by more than SPREAD_LIMIT of their median or the
process waited for a CPU (median wall / CPU time above WAIT_LIMIT: load stretches wall time only).
"""
import csv
import io
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time

from viewer.output import whole_files

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "benchmarks", "results")
SCRATCH = os.path.join(ROOT, "output")          # where `python simulator.py` writes: `scratch`
SPREAD_LIMIT, WAIT_LIMIT = 0.20, 1.15


def output_folder(out, full, program):
    """`out` if given, else RESULTS for a full run, else a new temporary folder `program`-..."""
    if out is None:
        out = RESULTS if full else tempfile.mkdtemp(prefix=f"{program}-")
    os.makedirs(out, exist_ok=True)
    return out


def scratch(prefix):
    """A temporary folder in SCRATCH, where `python simulator.py` writes: a run's files cost what
    they cost the default run (on this machine new files under /tmp cost up to 8x; benchmarks/
    README.md, "Where the runs write")."""
    try:
        os.makedirs(SCRATCH, exist_ok=True)
    except OSError as err:          # a file named output, a read-only checkout
        raise SystemExit(f"error: {SCRATCH} cannot hold the runs' folders: "
                         f"{err.strerror}") from None
    return tempfile.TemporaryDirectory(prefix=prefix, dir=SCRATCH)


def export_tree(rev, folder):
    """The tree to measure: `rev` if a folder, else commit `rev` git-archived into `folder`."""
    if os.path.isdir(rev):
        return os.path.abspath(rev)
    archive = subprocess.run(["git", "-C", ROOT, "archive", "--format=tar", rev],
                             capture_output=True)
    if archive.returncode != 0:
        raise SystemExit(f"error: git archive {rev}: {archive.stderr.decode().strip()}")
    subprocess.run(["tar", "-x", "-C", folder], input=archive.stdout, check=True)
    return folder


def in_fresh_process(module, function, *args):
    """What `module.function(*args)` returned (through JSON) in a fresh Python process."""
    code = (f"import json, sys, {module} as m\n"
            f"print(json.dumps(m.{function}(*json.loads(sys.argv[1]))))")
    done = subprocess.run([sys.executable, "-c", code, json.dumps(args)], cwd=ROOT,
                          capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{module}.{function}{tuple(args)} failed:\n{done.stderr}")
    return json.loads(done.stdout.splitlines()[-1])


def text(columns, rows, **names):
    """A table's lines from `columns`, (title filled in from `names`, row key, format spec)."""
    cells = [[title.format(**names) for title, _, _ in columns]]
    cells += [[format(row[key], spec) for _, key, spec in columns] for row in rows]
    widths = [max(map(len, column)) for column in zip(*cells)]
    lines = ["  ".join([c.rjust(w) for c, w in zip(row[:-1], widths)] + [row[-1]]) for row in cells]
    return lines[:1] + ["-" * len(lines[0])] + lines[1:]


def write_csv(path, columns, rows, digits=6):
    """`rows` (dicts) as the CSV file `path`, floats to `digits` significant digits; says so."""
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, columns, extrasaction="ignore", lineterminator="\n")
    writer.writeheader()
    writer.writerows({k: f"{v:.{digits}g}" if isinstance(v, float) else v for k, v in row.items()}
                     for row in rows)
    whole_files.write_whole(path, buffer.getvalue(), replace=True)
    print(f"wrote {path}", file=sys.stderr)


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


def in_turn(jobs, repeats):
    """{key: [what it returned]} of each of `jobs` called in turn, `repeats` rounds (all alike)."""
    results = {key: [] for key in jobs}
    for round_ in range(repeats):
        for key, job in jobs.items():
            results[key].append(job())
        print(f"  round {round_ + 1}/{repeats} done", file=sys.stderr, flush=True)
    return results


def run_process(command, cwd=ROOT, **env):
    """Run `command` in `cwd` (SDL's dummy driver, one BLAS thread, the variables `env`): wall s,
    CPU s (nan on Windows, which keeps no children's CPU time), stderr; RuntimeError if it fails."""
    env = {**os.environ, "SDL_VIDEODRIVER": "dummy", "OPENBLAS_NUM_THREADS": "1", **env}
    before, start = os.times(), time.perf_counter()
    done = subprocess.run(command, cwd=cwd, capture_output=True, text=True, env=env)
    wall, after = time.perf_counter() - start, os.times()
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed:\n{done.stderr}")
    cpu = sum(after[2:4]) - sum(before[2:4])        # children_user + children_system
    return wall, math.nan if os.name == "nt" else cpu, done.stderr
