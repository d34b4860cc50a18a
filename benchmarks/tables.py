"""What the benchmarks share: aligned text tables, CSV files written whole, and how noisy a timing is.

A timing is noisy when its repeats spread by more than SPREAD_LIMIT (of their median) or the process
waited for a CPU (median wall / CPU time above WAIT_LIMIT): on a shared machine other processes take
the CPU at times, which stretches wall time but not the process's own CPU time.
"""
import csv
import io
import statistics

from viewer.output import whole_files

SPREAD_LIMIT, WAIT_LIMIT = 0.20, 1.15


def aligned(cells):
    """Rows of text cells as lines: right-aligned columns, the last left as it is, a rule under the head."""
    widths = [max(len(c[i]) for c in cells) for i in range(len(cells[0]))]
    lines = ["  ".join(c.rjust(w) for c, w in zip(line[:-1], widths)) + "  " + line[-1] for line in cells]
    return lines[:1] + ["-" * len(lines[0])] + lines[1:]


def write_csv(path, columns, rows, digits=6):
    """Write `rows` (dicts) as the CSV file `path` with `columns`, floats to `digits` significant digits,
    whole (a temporary file renamed over it)."""
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=columns, extrasaction="ignore", lineterminator="\n")
    writer.writeheader()
    writer.writerows({k: (f"{v:.{digits}g}" if isinstance(v, float) else v) for k, v in r.items()} for r in rows)
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
