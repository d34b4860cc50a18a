"""The time step side by side with an earlier commit (`python -m benchmarks.speed --against REV`).

The default scene run by `simulator.simulate` at n_seg 4 (300 steps), 16 (300 steps) and 32 (150 steps,
through the impact), once with the working tree and once with commit REV (exported with `git archive`
into a temporary folder), each run in its own Python process with its tree first on sys.path,
alternating A/B/A/B; medians of the per-step CPU and wall time, each tree's total Newton iterations
(the same trajectory must take the same number: a mismatch is flagged) and the ratio working tree /
REV. Only `simulator.build_scene(n_seg=...)`, `simulator.simulate(scene, steps)` and
`record.report.newton_iterations` are used, so any tree that has them can be compared. REV may also
be a folder holding a tree.
"""
import json
import os
import statistics
import subprocess
import sys
import time

from benchmarks.tables import aligned, noise

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# n_seg: (steps from the start, runs per tree)
AGAINST = {4: (300, 7), 16: (300, 5), 32: (150, 3)}
AGAINST_QUICK = {4: (30, 2)}
AGAINST_COLUMNS = ["n_seg", "steps", "runs", "cpu_ms_new", "cpu_ms_old", "cpu_ratio", "wall_ms_new", "wall_ms_old",
                   "wall_ratio", "newton_new", "newton_old", "noise"]


def run_default_scene(tree, n_seg, steps):
    """(CPU s, wall s, Newton iterations) of `steps` steps of simulator.simulate on the default scene
    at n_seg, with `tree`'s modules (runs in the worker process)."""
    sys.path.insert(0, tree)
    import simulator
    scene = simulator.build_scene(n_seg=n_seg)
    newton, wall, cpu = 0, time.perf_counter(), time.process_time()
    for record in simulator.simulate(scene, steps):
        newton += record.report.newton_iterations
    return time.process_time() - cpu, time.perf_counter() - wall, newton


def run_in_process(tree, n_seg, steps):
    job = json.dumps({"tree": tree, "n_seg": n_seg, "steps": steps})
    done = subprocess.run([sys.executable, "-m", "benchmarks.speed_against", job], cwd=ROOT,
                          capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"n_seg {n_seg} with the tree {tree} failed:\n{done.stderr}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def compare(new_tree, old_tree, configs):
    """The comparison's rows: per n_seg, runs alternating new/old, medians per step."""
    rows = []
    for n_seg, (steps, runs) in configs.items():
        new, old = [], []
        for r in range(runs):
            new.append(run_in_process(new_tree, n_seg, steps))
            old.append(run_in_process(old_tree, n_seg, steps))
            print(f"  n_seg {n_seg} run {r + 1}/{runs}: CPU {new[-1][0] / steps * 1e3:.3g} ms/step (working tree), "
                  f"{old[-1][0] / steps * 1e3:.3g} (against)", file=sys.stderr, flush=True)
        row = {"n_seg": n_seg, "steps": steps, "runs": runs}
        for name, results in (("new", new), ("old", old)):
            row[f"cpu_ms_{name}"] = 1e3 * statistics.median(c for c, _, _ in results) / steps
            row[f"wall_ms_{name}"] = 1e3 * statistics.median(w for _, w, _ in results) / steps
            row[f"newton_{name}"] = results[0][2]
        row["cpu_ratio"] = row["cpu_ms_new"] / row["cpu_ms_old"]
        row["wall_ratio"] = row["wall_ms_new"] / row["wall_ms_old"]
        same = {n for _, _, n in new} | {n for _, _, n in old}
        noisy = [f"{name}: {verdict}" for name, results in (("new", new), ("old", old))
                 if (verdict := noise([w for _, w, _ in results], [c for c, _, _ in results])) != "ok"]
        row["noise"] = "; ".join(noisy) or "ok"
        if len(same) != 1:
            row["noise"] = f"NEWTON MISMATCH ({sorted(same)}); " + row["noise"]
        rows.append(row)
    return rows


def format_comparison(rows, rev):
    head = ["n_seg", "steps", "runs", "CPU ms/step new", f"CPU {rev}", "CPU new/old", "wall ms/step new",
            f"wall {rev}", "wall new/old", "Newton new", f"Newton {rev}", "noise"]
    cells = [head] + [[str(r["n_seg"]), str(r["steps"]), str(r["runs"]), f"{r['cpu_ms_new']:.3g}",
                       f"{r['cpu_ms_old']:.3g}", f"{r['cpu_ratio']:.2f}", f"{r['wall_ms_new']:.3g}",
                       f"{r['wall_ms_old']:.3g}", f"{r['wall_ratio']:.2f}", str(r["newton_new"]),
                       str(r["newton_old"]), r["noise"]] for r in rows]
    return "\n".join(aligned(cells) + [
        f"new: the working tree; {rev}: the tree compared against; the default scene from its start through",
        "simulator.simulate, each run a fresh process, runs alternating new/old; medians of CPU and wall time per step;",
        "Newton: total Newton iterations of a run (the same trajectory must take the same number)"])


def export_tree(rev, folder):
    """The tree to compare against: `rev` itself if it is a folder, else commit `rev` (git archive into
    `folder`; the checkout is not touched)."""
    if os.path.isdir(rev):
        return os.path.abspath(rev)
    archive = subprocess.run(["git", "-C", ROOT, "archive", "--format=tar", rev], capture_output=True)
    if archive.returncode != 0:
        raise SystemExit(f"speed: error: git archive {rev}: {archive.stderr.decode().strip()}")
    subprocess.run(["tar", "-x", "-C", folder], input=archive.stdout, check=True)
    return folder


if __name__ == "__main__":      # a worker: one run of one tree, its figures as JSON on stdout
    job = json.loads(sys.argv[1])
    print(json.dumps(run_default_scene(job["tree"], job["n_seg"], job["steps"])))
